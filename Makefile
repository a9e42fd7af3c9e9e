# floe: the two Quick start commands (`make demo`, `make test`) and helpers.
# Each target installs what it needs; see README.md.

CARGO ?= cargo
FLOE  := target/release/floe
DEMO  := out/demo

.PHONY: demo test deps check-tools validation bench clean

## Tools and system packages. Only Rust is needed so far; the HDF5 output
## (issue 4) will add libhdf5-dev and pkg-config here, apt-installed when missing.
deps: check-tools

check-tools:
	@command -v $(CARGO) >/dev/null 2>&1 || { echo "error: cargo not found; install Rust (rustup) first" >&2; exit 1; }
	@$(CARGO) fmt --version >/dev/null 2>&1 || { echo "error: rustfmt missing: rustup component add rustfmt" >&2; exit 1; }
	@$(CARGO) clippy --version >/dev/null 2>&1 || { echo "error: clippy missing: rustup component add clippy" >&2; exit 1; }

## The main job: the paper's lab slide-hold-slide as a spring-slider run, and
## the hold-time table. Writes $(DEMO)/{series.csv,summary.json,friction.png}.
demo: deps
	$(CARGO) build --release -p floe-cli
	$(FLOE) slider run scenarios/slider/lab_slide_hold_slide.toml --out $(DEMO) --force
	$(FLOE) slider hold --preset lab --hold 1,10,100,1000
	@echo "plot: $(DEMO)/friction.png"

## The whole test suite: formatting, lints, and every test (release mode: the
## physics tests run spring-sliders for millions of steps).
test: deps
	$(CARGO) fmt --all --check
	$(CARGO) clippy --workspace --all-targets --release -- -D warnings
	$(CARGO) test --workspace --release

## Regenerate the validation section of docs/friction.md and docs/validation/*.png.
validation: deps
	$(CARGO) run --release -p floe-cli --example friction_validation

## Criterion benchmarks (figures in docs/performance.md).
bench: deps
	$(CARGO) bench -p floe-friction --bench contact_update

clean:
	$(CARGO) clean
	rm -rf out
