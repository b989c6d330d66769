# hdrc3 developer entry points. `make demo` and `make test` set everything up themselves.
SHELL := /bin/bash
.DEFAULT_GOAL := help

PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
PY := $(VENV)/bin/python
BUILD := build
MYPY_PACKAGES := $(filter-out hdrc3_interfaces,$(wildcard hdrc3 hdrc3_[a-z]* sim))

# Stamps are keyed on the content of their inputs (for pyproject.toml: the [project] and
# [build-system] tables only), so a no-op setup is a few hash computations. The interfaces depend
# only on the ROS 2 wheels they are generated and compiled against (the `ros-*` requirements, the
# `interfaces` extra, the build system) and on their own files: a new Python dependency or entry
# point reinstalls the package without regenerating them.
DEPS_HASH := $(shell $(PYTHON) -c 'import hashlib, json, tomllib; d = tomllib.load(open("pyproject.toml", "rb")); print(hashlib.sha256(json.dumps([d["project"], d["build-system"]], sort_keys=True).encode()).hexdigest()[:16])')
ROS_DEPS_HASH := $(shell $(PYTHON) -c 'import hashlib, json, sys, tomllib; d = tomllib.load(open("pyproject.toml", "rb")); p = d["project"]; ros = sorted(r for r in p["dependencies"] if r.startswith("ros-")); print(hashlib.sha256(json.dumps([sys.version_info[:2], ros, p["optional-dependencies"]["interfaces"], d["build-system"]], sort_keys=True).encode()).hexdigest()[:16])')
IFACE_HASH := $(shell (echo $(ROS_DEPS_HASH); find hdrc3_interfaces -type f | LC_ALL=C sort | xargs cat) | sha256sum | cut -c1-16)
DEPS_STAMP := $(VENV)/.stamp-deps-$(DEPS_HASH)
IFACE_STAMP := $(VENV)/.stamp-interfaces-$(IFACE_HASH)

# DDS stays on loopback unless the user widens it deliberately.
export ROS_AUTOMATIC_DISCOVERY_RANGE ?= LOCALHOST

.PHONY: help setup demo test flights fuzz check bench clean

help:
	@echo "make demo   - set up and run the demo mission"
	@echo "make test   - set up and run the test suite"
	@echo "make flights - the whole-mission tests with two aircraft (not in make test)"
	@echo "make fuzz   - the property tests with 2500 examples each from random seeds"
	@echo "make check  - ruff + mypy"
	@echo "make bench  - run the benchmarks under bench/"
	@echo "make setup  - create .venv, install ROS 2 Jazzy wheels, hdrc3 and hdrc3_interfaces"

setup: $(DEPS_STAMP) $(IFACE_STAMP)

$(DEPS_STAMP):
	@echo "setup 1/2: Python packages into $(VENV) (ROS 2 Jazzy wheels, JSBSim, OMPL, ...: minutes on a fresh machine)"
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade 'pip>=24' 'setuptools>=68,<81' wheel
	$(PY) -m pip install --quiet -e '.[dev,interfaces]' --config-settings editable_mode=compat
	@# ros-rosidl-parser pulls lark-parser 0.12, which owns the same `lark` module as lark 1.x
	@# and adds stale `lark-stubs` that mypy would prefer: remove it, then reinstall lark 1.x so
	@# that the module on disk is lark 1.x (rosidl's parser works with it).
	LARK=$$($(PY) -c 'import importlib.metadata as m; print("lark==" + m.version("lark"))') && \
	  $(PY) -m pip uninstall --quiet --yes lark-parser && \
	  $(PY) -m pip install --quiet --force-reinstall --no-deps "$$LARK"
	@rm -f $(VENV)/.stamp-deps-*
	@touch $@

$(IFACE_STAMP): | $(DEPS_STAMP)
	@echo "setup 2/2: hdrc3_interfaces (rosidl generation and a C build: minutes on a fresh machine)"
	@rm -rf $(BUILD)/hdrc3_interfaces && mkdir -p $(BUILD)/hdrc3_interfaces
	cd $(BUILD)/hdrc3_interfaces && \
	  PATH=$(CURDIR)/$(VENV)/bin:$$PATH CMAKE_PREFIX_PATH=$(CURDIR)/$(VENV) AMENT_PREFIX_PATH=$(CURDIR)/$(VENV) \
	  cmake $(CURDIR)/hdrc3_interfaces -DPython3_EXECUTABLE=$(CURDIR)/$(PY) \
	    -DCMAKE_INSTALL_PREFIX=$(CURDIR)/$(VENV) -DBUILD_TESTING=OFF > cmake.log 2>&1 || { cat cmake.log; exit 1; }
	cd $(BUILD)/hdrc3_interfaces && PATH=$(CURDIR)/$(VENV)/bin:$$PATH $(MAKE) -j2 install > make.log 2>&1 || { tail -50 make.log; exit 1; }
	$(PY) -c "import hdrc3_interfaces.msg, hdrc3_interfaces.srv, hdrc3_interfaces.action"
	@rm -f $(VENV)/.stamp-interfaces-*
	@touch $@

demo: setup
	$(VENV)/bin/hdrc3 demo

test: setup
	$(PY) -m pytest -n 2 --dist loadgroup -q --hypothesis-profile=ci -m "not flight"

# Whole missions with two aircraft (issue 12's done-when scenarios): minutes each at --speed max,
# too long for `make test` on 2 cores.
flights: setup
	$(PY) -m pytest -q -m flight

# One process, so that Hypothesis prints how many examples each property test ran. Thousands of
# examples outlast the suite's 300 s per-test timeout on a loaded machine: allow an hour per test.
fuzz: setup
	$(PY) -m pytest -q -m property --hypothesis-profile=fuzz --hypothesis-show-statistics \
	  --timeout=3600

check: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/mypy $(MYPY_PACKAGES)

bench: setup
	@set -e; for b in bench/*.py; do echo "== $$b"; $(PY) $$b; done

clean:
	rm -rf $(BUILD) $(VENV)
