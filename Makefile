# floe: the two Quick start commands (`make demo`, `make test`) and helpers.
# Each target installs what it needs; see README.md.

CARGO ?= cargo
FLOE  := target/release/floe
DEMO  := out/demo
# MPI (`mpirun -np K floe run`, docs/hpc.md) is on unless MPI=0: then no MPI
# library is needed and floe runs as one process.
MPI ?= 1
ifeq ($(MPI),0)
FEATURES :=
PY_FEATURES :=
else
FEATURES := --features floe-cli/mpi
PY_FEATURES := --features mpi
endif

# The Python package (python/, docs/python.md) is built into .venv unless
# PYTHON=0: then no Python is needed and its tests are skipped.
PYTHON ?= 1
VENV   := .venv
PY     := $(VENV)/bin/python
ifeq ($(PYTHON),0)
# The extension's crate needs a Python to build against: left out.
CRATES := --workspace --exclude floe-python
else
CRATES := --workspace
endif

.PHONY: demo slider-demo test build deps check-tools system-deps python-deps python-package validation bench lammps paraview clean

## Tools and system packages: Rust's tools, HDF5, NetCDF-C, pkg-config and (unless
## MPI=0) Open MPI with libclang for its bindings (apt-installed when missing), and
## optionally h5py, xarray and netCDF4 for the Python examples of docs/output.md.
deps: check-tools system-deps python-deps python-package

check-tools:
	@command -v $(CARGO) >/dev/null 2>&1 || { echo "error: cargo not found; install Rust (rustup) first" >&2; exit 1; }
	@$(CARGO) fmt --version >/dev/null 2>&1 || { echo "error: rustfmt missing: rustup component add rustfmt" >&2; exit 1; }
	@$(CARGO) clippy --version >/dev/null 2>&1 || { echo "error: clippy missing: rustup component add clippy" >&2; exit 1; }

## HDF5 (>= 1.10.7; tested with Debian 12's 1.10.8) for the run files, found
## through pkg-config. With HDF5_DIR set (an HPC module system), nothing is
## installed: hdf5-metno builds against $$HDF5_DIR.
system-deps:
	@if [ -n "$$HDF5_DIR" ]; then \
	  echo "HDF5_DIR=$$HDF5_DIR: building against that HDF5, installing nothing"; \
	else \
	  missing=""; \
	  command -v pkg-config >/dev/null 2>&1 || missing="$$missing pkg-config"; \
	  if ! dpkg -s libhdf5-dev >/dev/null 2>&1 \
	     && ! pkg-config --exists hdf5 2>/dev/null \
	     && ! pkg-config --exists hdf5-serial 2>/dev/null; then \
	    missing="$$missing libhdf5-dev"; \
	  fi; \
	  if ! dpkg -s libnetcdf-dev >/dev/null 2>&1 && ! pkg-config --exists netcdf 2>/dev/null; then \
	    missing="$$missing libnetcdf-dev"; \
	  fi; \
	  if [ "$(MPI)" != 0 ]; then \
	    command -v mpirun >/dev/null 2>&1 || missing="$$missing openmpi-bin"; \
	    if ! dpkg -s libopenmpi-dev >/dev/null 2>&1 && ! command -v mpicc >/dev/null 2>&1; then \
	      missing="$$missing libopenmpi-dev"; \
	    fi; \
	    if ! dpkg -s libclang-dev >/dev/null 2>&1 && [ -z "$$LIBCLANG_PATH" ]; then \
	      missing="$$missing libclang-dev"; \
	    fi; \
	  fi; \
	  if [ -n "$$missing" ]; then \
	    command -v apt-get >/dev/null 2>&1 || { echo "error: missing$$missing and no apt-get: install HDF5 >= 1.10.7, NetCDF-C >= 4.7, pkg-config and an MPI-3 library with libclang (or build with MPI=0), or set HDF5_DIR and NETCDF_DIR (see README.md, docs/hpc.md)" >&2; exit 1; }; \
	    sudo=""; [ "$$(id -u)" = 0 ] || sudo="sudo"; \
	    echo "installing$$missing"; \
	    $$sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq $$missing; \
	  fi; \
	fi

## Optional: h5py, numpy and matplotlib for the h5py example of docs/output.md
## (tests/io/h5py.rs skips without them). Never fails.
python-deps:
	@if ! command -v python3 >/dev/null 2>&1; then \
	  echo "note: no python3: the h5py and xarray examples are skipped (optional)"; \
	elif python3 -c "import h5py, numpy, matplotlib, xarray, netCDF4" >/dev/null 2>&1; then \
	  :; \
	elif python3 -m pip --version >/dev/null 2>&1; then \
	  python3 -m pip install --user -q h5py numpy matplotlib xarray netCDF4 >/dev/null 2>&1 \
	  || python3 -m pip install --user --break-system-packages -q h5py numpy matplotlib xarray netCDF4 >/dev/null 2>&1 \
	  || echo "note: could not pip-install h5py numpy matplotlib xarray netCDF4 (optional: tests/io/h5py.rs and tests/study/grid_xarray.rs skip)"; \
	else \
	  echo "note: no pip for python3: the h5py and xarray examples are skipped (optional; apt-get install python3-h5py python3-matplotlib python3-xarray python3-netcdf4)"; \
	fi

## The Python package `floe` (python/): a virtual environment in .venv with
## maturin and the test dependencies (python/requirements-dev.txt, from PyPI),
## and floe built into it (`maturin develop --release`, sharing target/).
python-package:
ifeq ($(PYTHON),0)
	@echo "PYTHON=0: the Python package is not built"
else
	@command -v python3 >/dev/null 2>&1 || { echo "error: no python3: the Python package needs CPython >= 3.9 (or build with PYTHON=0)" >&2; exit 1; }
	@[ -x $(PY) ] || python3 -m venv $(VENV) || { echo "error: python3 -m venv $(VENV) failed: apt-get install python3-venv (or build with PYTHON=0)" >&2; exit 1; }
	@[ $(VENV)/.installed -nt python/requirements-dev.txt ] \
	  || { $(PY) -m pip install -q --upgrade pip >/dev/null && $(PY) -m pip install -q -r python/requirements-dev.txt && touch $(VENV)/.installed; } \
	  || { echo "error: could not install python/requirements-dev.txt into $(VENV) (PyPI unreachable? build with PYTHON=0)" >&2; exit 1; }
	cd python && PATH="$(CURDIR)/$(VENV)/bin:$$PATH" VIRTUAL_ENV=$(CURDIR)/$(VENV) maturin develop --release --quiet $(PY_FEATURES)
endif

## The main job: a DEM run of the default scenario (a few hundred diamond
## floes sheared by the wind in a walled channel) into an HDF5 file, pictures
## of it, a summary, then the same ice under Amontons, rate and rate-and-state
## friction side by side. Writes $(DEMO)/demo.h5, $(DEMO)/pictures/*.png and
## $(DEMO)/compare/report.md.
demo: deps
	$(CARGO) build --release -p floe-cli $(FEATURES)
	$(FLOE) run scenarios/demo.toml -o $(DEMO)/demo.h5 --force
	$(FLOE) render $(DEMO)/demo.h5 --every 5 -o $(DEMO)/pictures --force
	$(FLOE) info $(DEMO)/demo.h5 | head -20
	$(FLOE) compare scenarios/demo.toml -o $(DEMO)/compare --force --quiet
	@echo "pictures: $(DEMO)/pictures/   comparison: $(DEMO)/compare/report.md"

## The spring-slider experiments of the paper: the lab slide-hold-slide and
## the hold-time table. Writes $(DEMO)/slider/{series.csv,summary.json,friction.png}.
slider-demo: deps
	$(CARGO) build --release -p floe-cli $(FEATURES) $(FEATURES)
	$(FLOE) slider run scenarios/slider/lab_slide_hold_slide.toml --out $(DEMO)/slider --force
	$(FLOE) slider hold --preset lab --hold 1,10,100,1000

## The whole test suite: formatting, lints, and every test (release mode: the
## physics tests run spring-sliders for millions of steps), with MPI: the
## tests/cli/mpi_run.rs runs `mpirun -np K floe run`.
test: deps
	$(CARGO) fmt --all --check
	$(CARGO) clippy $(CRATES) --all-targets --release $(FEATURES) -- -D warnings
	$(CARGO) test $(CRATES) --release $(FEATURES)
ifneq ($(PYTHON),0)
	$(PY) -m pytest -q python/tests
endif

## The release binary, with MPI unless MPI=0.
build: deps
	$(CARGO) build --release -p floe-cli $(FEATURES)

## Regenerate the validation section of docs/friction.md and docs/validation/*.png.
validation: deps
	$(CARGO) run --release -p floe-study --example friction_validation

## Criterion benchmarks (figures in docs/performance.md).
bench: deps
	$(CARGO) bench -p floe-friction --bench contact_update
	$(CARGO) bench -p floe-dem --bench dem_step
	$(CARGO) bench -p floe-dem --bench narrow_phase

## Optional: ParaView (Debian's `paraview` package, about 440 MB) for pvpython,
## with which python/tests/test_xdmf.py reads `floe export --xdmf` files as
## ParaView does (skipped without it).
paraview:
	@if command -v pvpython >/dev/null 2>&1; then \
	  echo "pvpython found: $$(command -v pvpython)"; \
	else \
	  command -v apt-get >/dev/null 2>&1 || { echo "error: no pvpython and no apt-get: install ParaView (https://www.paraview.org/download/)" >&2; exit 1; }; \
	  sudo=""; [ "$$(id -u)" = 0 ] || sudo="sudo"; \
	  echo "installing paraview"; \
	  $$sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq paraview; \
	fi

## Optional: LAMMPS (Debian's `lammps` package; it brings Open MPI's mpirun) for
## benches/vs_lammps.sh, which installs nothing itself.
lammps:
	@if command -v lmp >/dev/null 2>&1; then \
	  echo "lmp found: $$(command -v lmp)"; \
	else \
	  command -v apt-get >/dev/null 2>&1 || { echo "error: no lmp and no apt-get: install LAMMPS with the GRANULAR and BODY packages (https://docs.lammps.org/Install.html)" >&2; exit 1; }; \
	  sudo=""; [ "$$(id -u)" = 0 ] || sudo="sudo"; \
	  echo "installing lammps"; \
	  $$sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq lammps; \
	fi

clean:
	$(CARGO) clean
	rm -rf out
