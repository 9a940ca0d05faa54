# raytracer: build, test, render, measure.
# `make` builds ./raytracer; `make test` is what CI runs.

CARGO ?= cargo
# Extra flags for the cargo builds and the test run (`make cold-times`
# passes --timings).
CARGO_FLAGS ?=
BIN := target/release/raytracer

.PHONY: all build check test test-times man web test-web cold-times run class-table render-scenes bench bench-profile bench-scaling accuracy fuzz fuzz-cmin clean \
	vsix preview-screenshot preview-latency grading-screenshot playground-screenshot gradescope

all: raytracer

raytracer: build
	cp $(BIN) ./raytracer

build:
	$(CARGO) build --release --locked $(CARGO_FLAGS)

# The suite spends most of its time waiting on the programs it runs (the
# graded tracers in their sandboxes, the Slurm cluster's scheduling, the
# timeouts it tests), so it runs twice as many tests at once as there are
# cores (docs/performance.md, "Build time").
TEST_THREADS ?= $(shell echo $$(( $$(nproc) * 2 )))

# The tests that need programs outside cargo or root (Slurm, browsers,
# editors, POV-Ray, GNU parallel, shells and man, the sandbox's attacks and
# its full disks, the classes of student tracers in Java, Python and
# JavaScript, Gradescope's container in podman, docs/grading.md's examples
# and its `--tracer` commands, which grade students in the sandbox): the
# full tier,
# which `make test` and CI run and `make check` leaves out.
FULL_TIER := slurm:: neovim:: vim_syntax:: vscode:: pov:: preview_browser:: \
	grade_browser:: grade_sandbox:: grade_disk:: grade_students:: grade_class:: \
	grade_doc_tracers:: distributed:: install:: gradescope:: \
	docs::the_grading_examples_run_as_written

# The fast tier, what a contributor runs after each edit: every crate's unit
# tests and the integration tests that need nothing but cargo and the
# binary, in the release profile `make` builds (docs/contributing.md says
# which tier to run when).
check: raytracer
	$(CARGO) test --release --locked --workspace --lib --tests $(CARGO_FLAGS) -- \
	  --test-threads=$(TEST_THREADS) $(addprefix --skip ,$(FULL_TIER))

# Everything CI checks, over the whole workspace: formatting, lints, each
# crate's unit tests, the integration and snapshot tests of tests/ (which
# include the tidy checks of the layering), and the doc tests. Clippy and
# the suite run in the release profile, reusing what `make` built (the
# procedural macros and build scripts clippy needs, the crates and
# dependencies the tests link, the binary they spawn); the examples are not
# built again here (clippy --all-targets checks them). The playground's test
# runs in `make test-web`, but is linted here: --all-targets leaves out a
# test that `test = false` keeps from `cargo test`.
test: raytracer
	$(CARGO) fmt --all --check
	$(CARGO) clippy --release --locked --workspace --all-targets -- -D warnings
	$(CARGO) clippy --release --locked --test playground -- -D warnings
	$(CARGO) test --release --locked --workspace --lib --tests $(CARGO_FLAGS) -- --test-threads=$(TEST_THREADS)
	$(CARGO) test --release --locked --workspace --doc

# Every test's time, by cargo-nextest (`cargo install cargo-nextest
# --locked`): the slow ones are named as they run, and each test's time is
# in target/nextest/default/junit.xml (.config/nextest.toml).
test-times: raytracer
	$(CARGO) nextest run --release --locked --workspace --lib --tests \
	  --test-threads=$(TEST_THREADS) $(CARGO_FLAGS)

# The playground (docs/playground.md): the page and its WebAssembly module
# in target/web/site, a folder to open from file:// or copy to any static
# web server (scripts/web.sh; installs Debian's wasm toolchain when
# missing; minutes cold, mostly std for wasm32).
web:
	scripts/web.sh

# The playground in headless Chromium (tests/playground.rs), on the folder
# `make web` built; .ci/run runs it after `make test`.
test-web: web
	$(CARGO) test --release --locked --test playground $(CARGO_FLAGS)

# Gradescope's autograder (docs/grading.md, "Gradescope"):
# target/gradescope/autograder.zip, with setup.sh and run_autograder at its
# root, the binary, the suite (SUITE=folder, default the built-in one) and
# our references rendered into its cache (scripts/gradescope.sh);
# REFERENCE_OPTIONS=file gives the course's constants, or
# REFERENCE_TRACER='./tracer {scene} {out}' REFERENCE_TRACER_DIR=folder its own tracer.
gradescope: build
	scripts/gradescope.sh target/gradescope

# The man pages, generated from the command line's definition (clap_mangen):
# raytracer.1 and one per command (raytracer-grade.1, ...) with its options
# and exit codes, in target/man/. `man target/man/raytracer-grade.1` reads
# one; README.md's install section installs them for `man raytracer-grade`.
man: raytracer
	./raytracer man --dir target/man

# The cold times in docs/contributing.md, measured from bare clones of HEAD
# (scripts/cold-times.sh; 15 to 20 minutes on 2 cores).
cold-times:
	scripts/cold-times.sh

run: raytracer
	./raytracer render scenes/sample.txt out.png

# The table of every class of tests/students graded on the default suite,
# written into docs/grading.md ("Readings the assignment leaves open") by
# scripts/class_table.py; the reports stay in target/classes. Needs the
# classes' compilers (cc, g++, javac) and interpreters (python3, node);
# some minutes.
CLASSES := tune judge held_out fresh unseen blind sealed masked veiled hidden cloaked shrouded
class-table: raytracer
	rm -rf target/classes
	for class in $(CLASSES); do \
	  ./raytracer grade --class tests/students/$$class -o target/classes/$$class \
	    --cache target/classes/cache --jobs 2 --memory 8192 --max-processes 4096; \
	  test $$? -le 1 || exit 1; \
	done
	scripts/class_table.py --into docs/grading.md $(addprefix target/classes/,$(CLASSES))

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

# Where a 100,000-sphere render's instructions go (cachegrind), and this
# build against BASE (an older binary) on the sphere grids, alternating:
# tables written into docs/performance.md (scripts/bench_profile.sh).
bench-profile:
	scripts/bench_profile.sh

# Our render time against object count (10 to 1,000,000 spheres), medians
# to docs/scaling.csv, plotted to docs/scaling.png (scripts/scaling.sh).
bench-scaling:
	scripts/scaling.sh

# What accuracy costs: one run of `raytracer accuracy` over a tuning set
# (scenes/, scenes/hard/), which chooses adaptive sampling's threshold, and
# a held-out set (the course corpus), with plots, to docs/accuracy.md and
# docs/accuracy/ (scripts/accuracy.sh; the doc's heading says how long the
# run took).
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
# (`cargo install --locked cargo-fuzz`). libFuzzer's instrumentation and ASan use
# nightly-only rustc flags: RUSTC_BOOTSTRAP=1 allows them on the stable
# toolchain (use FUZZ_FLAGS="--sanitizer none" to fuzz without ASan).
FUZZ_SECONDS ?= 600
FUZZ_TARGETS ?= scene json texture format lsp expand
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

# The VS Code extension of editors/vscode/, packaged by @vscode/vsce for
# `code --install-extension target/vscode/raytracer-scene.vsix` (needs node
# and npm; the packages install from its package-lock.json).
vsix:
	mkdir -p target/vscode
	cd editors/vscode && npm ci --no-audit --no-fund && \
	  npm run package -- --out ../../target/vscode/raytracer-scene.vsix

# docs/preview.png: the page of `raytracer preview` with an error showing,
# as headless Chromium draws it in the browser test (tests/preview_browser.rs).
preview-screenshot:
	RAYTRACER_PREVIEW_SCREENSHOT=$(CURDIR)/docs/preview.png \
	  $(CARGO) test --release --locked --test integration preview_browser::chromium_shows

# docs/grading-report.png: a student's report of `raytracer grade` as
# headless Chromium draws it in the browser test (tests/grade_browser.rs).
grading-screenshot:
	RAYTRACER_GRADING_SCREENSHOT=$(CURDIR)/docs/grading-report.png \
	  $(CARGO) test --release --locked --test integration grade_browser::

# docs/playground.png: the playground with a misspelt attribute, as
# headless Chromium draws it in the browser test (tests/playground.rs).
playground-screenshot: web
	RAYTRACER_PLAYGROUND_SCREENSHOT=$(CURDIR)/docs/playground.png \
	  $(CARGO) test --release --locked --test playground a_misspelt_attribute

# The save-to-image latency table of docs/preview.md: the same test's
# measurement, on a release build, written between its markers.
preview-latency:
	RAYTRACER_PREVIEW_LATENCY=$(CURDIR)/docs/preview.md \
	  $(CARGO) test --release --locked --test integration preview_latency -- --ignored --nocapture

clean:
	$(CARGO) clean
	rm -f raytracer out.png
