# raytracer: build, test, render, measure.
# `make` builds ./raytracer; `make test` is what CI runs.

CARGO ?= cargo
BIN := target/release/raytracer

.PHONY: all build test run render-scenes bench bench-scaling accuracy fuzz fuzz-cmin clean

all: raytracer

raytracer: build
	cp $(BIN) ./raytracer

build:
	$(CARGO) build --release --locked

# Everything CI checks: formatting, lints, unit, integration and snapshot
# tests, and the library built without the command line.
test: raytracer
	$(CARGO) fmt --check
	$(CARGO) clippy --locked --all-targets -- -D warnings
	$(CARGO) test --locked
	CARGO="$(CARGO)" scripts/library_user.sh

run: raytracer
	./raytracer render scenes/sample.txt out.png

# Render every scene in scenes/ to docs/gallery/ and write docs/gallery.md
# with each image and the statistics of its render.
GALLERY_SCENES := $(wildcard scenes/*.txt)
render-scenes: raytracer
	mkdir -p docs/gallery
	{ echo '# Gallery'; echo; \
	  echo 'Every scene in `scenes/`, rendered by `make render-scenes` with the default'; \
	  echo 'settings (f64, 1 sample per pixel, up to 8 reflections). The statistics under'; \
	  echo 'each image are that render'"'"'s `--stats`: a scene without lights casts no shadow'; \
	  echo 'ray, one where nothing reflects no reflection ray, one without textures reads'; \
	  echo 'no texel. Timings are from the machine that ran it.'; \
	  for scene in $(GALLERY_SCENES); do \
	    name=$$(basename $$scene .txt); \
	    echo; echo "## $$name"; echo; \
	    echo "[\`$$scene\`](../$$scene): $$(sed -n '/^#/!q; s/^# *//p' $$scene | tr '\n' ' ')"; echo; \
	    echo "![$$name](gallery/$$name.png)"; echo; echo '```text'; \
	    ./raytracer render $$scene docs/gallery/$$name.png --quiet --stats --threads 1 2>&1; \
	    echo '```'; \
	  done; } > docs/gallery.md

# Ours against POV-Ray 3.7 and Embree 3 (bench/embree/, installed and built
# when missing), alternating, one thread: tables of medians written into
# docs/performance.md. REPS=N for more samples.
bench:
	scripts/bench.sh

# Our render time against object count (10 to 1,000,000 spheres), medians
# to docs/scaling.csv, plotted to docs/scaling.png.
bench-scaling:
	scripts/scaling.sh
	$(CARGO) run --release --locked --example plot -- \
	  docs/scaling_plot.csv docs/scaling.png \
	  --title "Render time against sphere count (1000², one thread)" \
	  --x-label "spheres" --y-label "seconds.render" --log-x --log-y --lines

# What accuracy costs: `raytracer accuracy` over scenes/ and scenes/hard/
# (each at its own resolution) with plots, to docs/accuracy.md and
# docs/accuracy/ (scripts/accuracy.sh). Under 10 minutes on 2 cores.
accuracy: raytracer
	scripts/accuracy.sh

# Fuzz the front end (docs/reliability.md): `make fuzz` runs each target
# (scene text, JSON scenes, texture decoding, the formatter, the language
# server's edits) for FUZZ_SECONDS of wall
# clock, or FUZZ_CPU_SECONDS of the fuzzer's CPU time when that is set, with
# one libFuzzer job, growing fuzz/corpus/TARGET (git ignores it) from the
# committed fuzz/seeds/TARGET, and appends a dated line per target (wall and
# CPU seconds, executions, crashes) to the run log at the end of
# docs/reliability.md (scripts/fuzz.sh); a crash lands in
# fuzz/artifacts/TARGET and fails the target. Needs cargo-fuzz
# (`cargo install cargo-fuzz`). libFuzzer's instrumentation and ASan use
# nightly-only rustc flags: RUSTC_BOOTSTRAP=1 allows them on the stable
# toolchain (use FUZZ_FLAGS="--sanitizer none" to fuzz without ASan).
FUZZ_SECONDS ?= 600
FUZZ_TARGETS ?= scene json texture format lsp
FUZZ_CPU_SECONDS ?=
FUZZ_FLAGS ?=
fuzz:
	FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_CPU_SECONDS=$(FUZZ_CPU_SECONDS) \
	  FUZZ_FLAGS="$(FUZZ_FLAGS)" CARGO="$(CARGO)" \
	  scripts/fuzz.sh $(FUZZ_TARGETS)

# Shrink the fuzz corpora to the inputs that add coverage (fuzz/corpus/ is
# not committed: add an input that matters to fuzz/seeds/ by hand).
fuzz-cmin:
	cd fuzz && for target in $(FUZZ_TARGETS); do \
	  RUSTC_BOOTSTRAP=1 $(CARGO) fuzz cmin -O $(FUZZ_FLAGS) $$target corpus/$$target || exit 1; \
	done

clean:
	$(CARGO) clean
	rm -f raytracer out.png
