# raytracer: build, test, render, measure.
# `make` builds ./raytracer; `make test` is what CI runs.

CARGO ?= cargo
BIN := target/release/raytracer

.PHONY: all build test lint fmt run render-scenes bench accuracy fuzz clean

all: raytracer

raytracer: build
	cp $(BIN) ./raytracer

build:
	$(CARGO) build --release --locked

# Everything CI checks: formatting, lints, unit, integration and snapshot tests.
test: raytracer
	$(CARGO) fmt --check
	$(CARGO) clippy --locked --all-targets -- -D warnings
	$(CARGO) test --locked

run: raytracer
	./raytracer render scenes/sample.txt out.png

clean:
	$(CARGO) clean
	rm -f raytracer out.png
