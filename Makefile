# quatrot: every entry point of the project. The Makefile creates its own
# virtual environment from validation/requirements.txt and builds the Python
# extension with maturin; nothing else needs to be installed by hand.

SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP_VENV := $(VENV)/.requirements-installed
# maturin needs the virtual environment active; LAMMPS needs MPICH's library.
export VIRTUAL_ENV := $(abspath $(VENV))
export PATH := $(abspath $(VENV))/bin:$(PATH)
export LD_LIBRARY_PATH := $(abspath $(VENV))/lib:$(LD_LIBRARY_PATH)
RESULTS ?= results

.PHONY: all test validate fixtures bench develop lint rust-test py-test clean

all: test

$(STAMP_VENV): validation/requirements.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r validation/requirements.txt
	touch $@

# The extension module, built into the virtual environment.
develop: $(STAMP_VENV)
	$(VENV)/bin/maturin develop --quiet --release

lint:
	cargo fmt --all -- --check
	cargo clippy --all-targets --features python -- -D warnings

rust-test:
	cargo test --release

py-test: develop
	$(PY) -m pytest -q validation/tests

test: lint rust-test py-test

fixtures: develop
	$(PY) -m validation.fixtures

validate: develop
	$(PY) -m validation.report --out $(RESULTS)

bench: develop
	cargo bench
	$(PY) -m validation.bench --out benchmarks
	$(PY) -m validation.bench.ewald --out benchmarks

clean:
	rm -rf target $(VENV) $(RESULTS)
