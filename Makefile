# Two entry points for a fresh machine (see README):
#   make        main job: set up, derive, audit the paper, generate the default spec
#   make test   every test (sets itself up the same way)
SHELL := /bin/bash
.DEFAULT_GOAL := all

PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
CLI    := $(PY) -m codegen
# SPEC=path/to/motor.yaml runs any target on that one spec. Without SPEC: derive,
# generate, firmware and bench use DEFAULT_SPEC (audit: the paper alone); verify and unity every
# checked-in spec (SPECS); simulate each checked-in motor once (SIM_SPECS).
DEFAULT_SPEC := spec/paper_motor.yaml
ONE_SPEC = $(or $(SPEC),$(DEFAULT_SPEC))
# make splits SPEC at spaces (several specs are SPEC="a.yaml b.yaml"), so a path with a
# space in it cannot go through make: SPEC="my motors/m.yaml" ran `generate /my` and
# `motors/m.yaml`. A SPEC of several words one of which is no file stops here, in one line.
# SPEC reaches the shell quoted (`quoted`): a path with a parenthesis or a quote in it
# ("m(1).yaml", "it's.yaml") had been a shell syntax error. A '$' make itself expands
# before any recipe runs (SPEC='a$HOME.yaml' read "aOME.yaml"), so it stops here.
quoted = $(foreach w,$(1),'$(subst ','\'',$(w))')
ifneq ($(findstring $$,$(value SPEC)),)
$(error SPEC contains '$$', which make expands before the shell sees it: rename the file, or run the CLI: $(VENV)/bin/python -m codegen COMMAND 'path')
endif
ifneq ($(word 2,$(SPEC)),)
$(foreach s,$(SPEC),$(if $(wildcard $(s)),,$(error SPEC="$(SPEC)": no file "$(s)": make splits SPEC at spaces, so a path with a space cannot go through make; run the CLI: $(VENV)/bin/python -m codegen COMMAND "path with spaces.yaml")))
endif

# Debian packages the project needs. Installed by `make sysdeps` (root or sudo).
# chromium renders the HTML audit in its browser test; fonts-lmodern gives it a math font.
# frama-c-base (EVA, WP), why3 and the SMT solvers z3 and cvc4 run `make prove`.
APT_PACKAGES ?= python3-venv gcc make gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi qemu-system-arm chromium fonts-lmodern frama-c-base why3 z3 cvc4
# Specs whose output is checked in under generated/: the paper's motor, the same motor
# with the resistance-aware rule (method improved_r), and a second motor.
SPECS ?= spec/paper_motor.yaml spec/paper_motor_improved_r.yaml spec/example_maxon_ec45_flat_48v.yaml
# The simulation runs every method on a motor, so it needs each motor once.
SIM_SPECS ?= spec/paper_motor.yaml spec/example_maxon_ec45_flat_48v.yaml

.PHONY: all setup sysdeps lock derive audit audit-screenshot generate firmware flash verify prove unity simulate robustness pil test lint format check-generated bench clean

all: setup derive audit generate

sysdeps:
	@missing=""; for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi

# Python dependencies: exactly the versions (and hashes) of requirements.lock, installed
# by uv (from PyPI, pinned) into a fresh .venv whenever pyproject.toml or the lock change.
# Bytecode: with PYTHONDONTWRITEBYTECODE set (some machines set it) nothing writes a .pyc,
# and each process compiles SymPy from source, about 1.8 s of every command's start. The
# recipes run without it (unexport below), so a module is compiled once, at its first
# import, into its __pycache__/ (the venv's, or the project's, ignored by git); and the
# install imports what the commands and the tests import (WARM_IMPORTS), so that a command
# run outside make, with the variable set, finds them compiled too. uv's
# --compile-bytecode compiled every module of the venv instead (about 5600, 14.6 s on a
# fresh clone on 2 cores, against 5.6 s for the third of them that is ever imported).
unexport PYTHONDONTWRITEBYTECODE
WARM_IMPORTS := bldc.cli bldc.commands.checks codegen.generate codegen.audit verify.check \
  verify.prove verify.unity_run sim.cli sim.studies sim.averaged sim.figures sim.robustness \
  emulation.bench emulation.pil.report oracle.model pytest xdist.plugin hypothesis
UV_VERSION ?= 0.13.9
UV := $(VENV)/bin/uv

$(VENV)/.installed: pyproject.toml requirements.lock
	@$(PYTHON) -m venv --help >/dev/null 2>&1 || $(MAKE) sysdeps
	rm -rf $(VENV)
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --disable-pip-version-check uv==$(UV_VERSION)
	$(UV) pip install -q --python $(PY) --require-hashes -r requirements.lock
	$(UV) pip install -q --python $(PY) --no-deps -e . -C editable_mode=compat
	$(PY) -c 'import importlib, sys; [importlib.import_module(m) for m in sys.argv[1:]]' $(WARM_IMPORTS)
	@touch $@

# Re-resolve requirements.lock from pyproject.toml (newest versions that fit); commit it.
lock: $(VENV)/.installed
	$(UV) pip compile pyproject.toml --extra dev --universal --python-version 3.11 \
	  --generate-hashes --no-header -q -o requirements.lock

# The project's own modules are installed editable, so uv compiles none of them: with
# PYTHONDONTWRITEBYTECODE set, every command (and each of the tests' subprocesses and
# workers) compiled them from source, about 0.4 s of each start. compileall writes their
# .pyc beside them (__pycache__/, ignored by git) and afterwards only what changed.
PACKAGES := bldc codegen oracle verify sim emulation

setup: sysdeps $(VENV)/.installed
	@$(PY) -m compileall -q $(PACKAGES)

derive: setup
	$(CLI) derive $(call quoted,$(ONE_SPEC))

# The paper's audit, the same for every motor: generated/paper/AUDIT.md and AUDIT.html;
# with SPEC=, also that motor's generated/<name>/DERIVATION.md.
audit: setup
	$(CLI) audit $(call quoted,$(SPEC))

# The README's pictures of the HTML audit, taken in headless Chromium.
audit-screenshot: setup
	$(PY) -m codegen.audit.browser generated/paper/AUDIT.html docs/audit.png
	$(PY) -m codegen.audit.browser generated/paper/AUDIT.html docs/audit_equation.png eq-4

generate: setup
	$(CLI) generate $(call quoted,$(ONE_SPEC))

# Cross-compile the generated output of the spec for the Cortex-M3; sizes by section.
firmware: setup
	$(CLI) firmware $(call quoted,$(ONE_SPEC))

# Flash the firmware of SPEC (or the default spec) through an ST-Link or CMSIS-DAP probe
# with pyocd (README, Firmware). Not run by the tests: there is no probe here. The part
# is pyocd's target name; the link script assumes 64 KiB flash and 20 KiB RAM (C8/CB).
PYOCD_TARGET ?= stm32f103c8
flash: firmware
	@command -v pyocd >/dev/null 2>&1 || { echo "flash: pyocd not found: install it (pipx install pyocd), then 'pyocd pack install $(PYOCD_TARGET)'" >&2; exit 5; }
	name=$$(sed -n 's/^name: *//p' $(call quoted,$(ONE_SPEC)) | head -n 1); \
	pyocd load --target $(PYOCD_TARGET) build/$$name/firmware.hex

# The generated core against the exact symbolic model (exhaustive, random, boundary);
# report.json and error_vs_speed.png into generated/<name>/verify/.
verify: setup
	@for spec in $(call quoted,$(or $(SPEC),$(SPECS))); do $(CLI) verify "$$spec" || exit $$?; done

# Frama-C on the shipped C: EVA (0 alarms over every input) and WP (the ACSL contracts)
# on every public function of every checked-in spec, or SPEC=... only (a spec without
# current generated/ output is generated into build/prove/ first). Writes
# generated/<spec>/PROOF.md; fails on any alarm, unproven contract or missing tool.
PROVE_SPECS = $(if $(filter command line environment,$(origin SPEC)),$(SPEC),$(SPECS))
prove: setup
	$(PY) -m verify.prove $(call quoted,$(PROVE_SPECS)) --jobs 2

# Commutation simulation (the generated core in the loop): figures and SIMULATION.md
# into generated/<name>/simulation/, for every checked-in motor, or SPEC=... only.
simulate: setup
	@for spec in $(call quoted,$(or $(SPEC),$(SIM_SPECS))); do $(CLI) simulate "$$spec" || exit $$?; done

# Robustness campaign (Dask LocalCluster; the core against sampled tolerances):
# ROBUSTNESS.md into generated/<name>/robustness/, same spec choice as simulate.
robustness: setup
	@for spec in $(call quoted,$(or $(SPEC),$(SIM_SPECS))); do $(PY) -m sim.robustness "$$spec" || exit $$?; done

# The generated Unity tests: host (ASan/UBSan) and Cortex-M3 under qemu mps2-an385.
# Real Unity when UNITY_DIR points to a checkout, else the stand-in runner.
unity: setup
	@for spec in $(call quoted,$(or $(SPEC),$(SPECS))); do $(CLI) unity "$$spec" || exit $$?; done

lint: setup
	$(PY) -m ruff check $(PACKAGES) tests
	$(PY) -m ruff format --check $(PACKAGES) tests
	$(VENV)/bin/lint-imports

format: setup
	$(PY) -m ruff format $(PACKAGES) tests
	$(PY) -m ruff check --fix $(PACKAGES) tests

# Regenerate into a temporary folder and fail with a diff if generated/ is stale: the
# paper audit (generated/paper/) and every checked-in spec.
check-generated: setup
	@tmp=$$(mktemp -d); trap 'rm -rf "$$tmp"' EXIT; \
	cp spec/paper_printed.parsed.json "$$tmp/parsed.json"; \
	$(PY) -m codegen audit -o "$$tmp/paper" >/dev/null || exit 1; \
	if ! diff -ru generated/paper "$$tmp/paper"; then \
	  echo "generated/paper is stale: run 'make audit' and commit it"; exit 1; \
	fi; \
	for spec in $(SPECS); do \
	  name=$$(sed -n 's/^name: *//p' $$spec | head -n 1); \
	  $(PY) -m codegen generate $$spec -o "$$tmp/$$name" >/dev/null || exit 1; \
	  if ! diff -ru -x verify -x simulation -x robustness -x pil -x PROOF.md -x __pycache__ generated/$$name "$$tmp/$$name"; then \
	    echo "generated/$$name is stale: run 'make generate SPEC=$$spec' and commit it"; exit 1; \
	  fi; \
	done; \
	if ! diff -u "$$tmp/parsed.json" spec/paper_printed.parsed.json; then \
	  echo "spec/paper_printed.parsed.json was stale and has been refreshed: commit it"; exit 1; \
	fi; \
	echo "check-generated: generated/ is up to date"

# Every test, on every core (pytest-xdist, work stealing: a worker that runs out takes
# half of another's queue, so no core idles while the other runs its share of the long
# tests); the Frama-C proof of each checked-in spec (`make prove`) is one of them
# (tests/test_prove.py), queued first with the other long ones. check-generated runs
# beside the suite (it only reads generated/ and writes to a temporary folder; the
# tests that write under generated/ write what it leaves out of its diff), and either
# failing fails the target.
test: setup lint
	@$(MAKE) --no-print-directory check-generated & checked=$$!; \
	$(PY) -m pytest -n auto --dist worksteal; status=$$?; \
	wait $$checked || status=1; \
	exit $$status

# Speed and size figures of SPEC, each with its target; exits 1 on a miss. Flags for the
# driver (python -m emulation --help): BENCH_FLAGS=--report-only, --only handlers,peers.
BENCH_FLAGS ?=
# Firmware in the loop: build each spec's firmware (SPEC, or every checked-in spec), run
# the fault scenarios on the emulated STM32F103 and write generated/<name>/pil/PIL.md.
pil: setup
	$(PY) -m emulation.pil.report $(call quoted,$(or $(SPEC),$(SPECS)))

bench: setup
	$(PY) -m emulation $(call quoted,$(ONE_SPEC)) $(BENCH_FLAGS)

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache .ruff_cache
