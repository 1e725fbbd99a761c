# Two entry points for a fresh machine (see README):
#   make        main job: set up, derive, audit the paper, generate the default spec
#   make test   every test (sets itself up the same way)
SHELL := /bin/bash
.DEFAULT_GOAL := all

PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
SPEC   ?= spec/paper_motor.yaml
SPEC_NAME = $(shell sed -n 's/^name: *//p' $(SPEC) | head -n 1)

# Debian packages the project needs. Installed by `make sysdeps` (root or sudo).
# chromium renders the HTML audit in its browser test; fonts-lmodern gives it a math font.
# frama-c-base (EVA, WP), why3 and the SMT solvers z3 and cvc4 run `make prove`.
APT_PACKAGES ?= python3-venv gcc make gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi qemu-system-arm chromium fonts-lmodern frama-c-base why3 z3 cvc4
# Specs whose output is checked in under generated/: the paper's motor, the same motor
# with the resistance-aware rule (method improved_r), and a second motor.
SPECS ?= spec/paper_motor.yaml spec/paper_motor_improved_r.yaml spec/example_maxon_ec45_flat_48v.yaml
# The simulation runs every method on a motor, so it needs each motor once.
SIM_SPECS ?= spec/paper_motor.yaml spec/example_maxon_ec45_flat_48v.yaml

.PHONY: all setup sysdeps derive audit audit-screenshot generate firmware verify prove unity simulate robustness test lint format check-generated bench clean

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

$(VENV)/.installed: pyproject.toml
	@$(PYTHON) -m venv --help >/dev/null 2>&1 || $(MAKE) sysdeps
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[dev]'
	@touch $@

setup: sysdeps $(VENV)/.installed

derive: setup
	$(PY) -m codegen derive $(SPEC)

# The paper's audit, the same for every motor: generated/paper/AUDIT.md and AUDIT.html.
audit: setup
	$(PY) -m codegen audit

# The README's pictures of the HTML audit, taken in headless Chromium.
audit-screenshot: setup
	$(PY) -m codegen.audit.browser generated/paper/AUDIT.html docs/audit.png
	$(PY) -m codegen.audit.browser generated/paper/AUDIT.html docs/audit_equation.png eq-4

generate: setup
	$(PY) -m codegen generate $(SPEC)

# Cross-compile the checked-in output of SPEC for the Cortex-M3; sizes by section.
firmware: setup
	$(PY) -m codegen.build_firmware generated/$(SPEC_NAME) build/$(SPEC_NAME)

# The generated core against the exact symbolic model (exhaustive, random, boundary),
# for every checked-in spec; report.json and error_vs_speed.png beside the code.
verify: setup
	@for spec in $(SPECS); do $(PY) -m verify $$spec || exit 1; done

# Frama-C on the shipped C: EVA (0 alarms over every input) and WP (the ACSL contracts)
# on every public function of every checked-in spec, or SPEC=... only (a spec without
# current generated/ output is generated into build/prove/ first). Writes
# generated/<spec>/PROOF.md; fails on any alarm, unproven contract or missing tool.
PROVE_SPECS = $(if $(filter command line environment,$(origin SPEC)),$(SPEC),$(SPECS))
prove: setup
	$(PY) -m verify.prove $(PROVE_SPECS) --jobs 2

# Commutation simulation (the generated core in the loop): figures and SIMULATION.md
# into generated/<spec>/simulation/, for every checked-in spec, or SPEC=... only.
SIM_RUN_SPECS = $(if $(filter command line environment,$(origin SPEC)),$(SPEC),$(SIM_SPECS))
simulate: setup
	@for spec in $(SIM_RUN_SPECS); do $(PY) -m sim $$spec || exit 1; done

# Robustness campaign (Dask LocalCluster; the core against sampled tolerances):
# ROBUSTNESS.md into generated/<spec>/robustness/, same spec choice as simulate.
robustness: setup
	@for spec in $(SIM_RUN_SPECS); do $(PY) -m sim.robustness $$spec || exit 1; done

# The generated Unity tests: host (ASan/UBSan) and Cortex-M3 under qemu mps2-an385.
# Real Unity when UNITY_DIR points to a checkout, else the stand-in runner.
unity: setup
	@for spec in $(SPECS); do \
	  name=$$(sed -n 's/^name: *//p' $$spec | head -n 1); \
	  $(PY) -m verify.unity_run generated/$$name || exit 1; \
	done

lint: setup
	$(PY) -m ruff check codegen oracle verify sim tests
	$(PY) -m ruff format --check codegen oracle verify sim tests
	$(VENV)/bin/lint-imports

format: setup
	$(PY) -m ruff format codegen oracle verify sim tests
	$(PY) -m ruff check --fix codegen oracle verify sim tests

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
	  if ! diff -ru -x verify -x simulation -x robustness -x PROOF.md generated/$$name "$$tmp/$$name"; then \
	    echo "generated/$$name is stale: run 'make generate SPEC=$$spec' and commit it"; exit 1; \
	  fi; \
	done; \
	if ! diff -u "$$tmp/parsed.json" spec/paper_printed.parsed.json; then \
	  echo "spec/paper_printed.parsed.json was stale and has been refreshed: commit it"; exit 1; \
	fi; \
	echo "check-generated: generated/ is up to date"

test: setup lint check-generated prove
	$(PY) -m pytest

bench: setup
	$(PY) -m codegen.bench $(SPEC)

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache .ruff_cache
