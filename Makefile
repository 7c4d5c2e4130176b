# ringlube: the two commands of the README.
#   make run   set up if needed, then run the main job on the shipped default inputs
#   make test  set up if needed, then `make lint`, then every test
#   make lint  the Python linter and both formatters in check mode (make format applies them)
# Python lives in the project virtual environment $(VENV) (created from $(PYTHON)), so the
# system interpreter is never modified (Debian's refuses `pip install`, PEP 668).
SHELL := /bin/bash
BUILD ?= build
PYTHON ?= python3
VENV ?= .venv
APT_PACKAGES := gfortran cmake ninja-build libhdf5-dev hdf5-tools liblapack-dev libblas-dev
DEFAULT_DECK := inputs/crf450r_4000rpm_full_cold.nml
DEFAULT_STUDY := inputs/study_default.nml
# Fortran checked by fprettify (settings: .fprettify.rc): every file.
FORTRAN_FORMATTED := $(wildcard fortran/src/*.f90 fortran/app/*.f90 fortran/f2py/*.f90 \
                       tests/fortran/*.f90 tests/bench/*.f90)

VPY := $(VENV)/bin/python
PIP := $(VPY) -m pip --disable-pip-version-check
PY_STAMP := $(VENV)/.ringlube-installed
PY_SOURCES := $(wildcard fortran/src/*.f90 fortran/src/*.f90.in fortran/f2py/*.f90 pydriver/ringlube/*.py pydriver/ringlube/*/*.py \
                inputs/*.nml inputs/*.md inputs/pressure/*.csv) pyproject.toml CMakeLists.txt

# Prints [build-system] requires of pyproject.toml, one a line (tomllib from Python 3.11,
# else the copy of tomli inside pip).
define BUILD_REQUIRES
try:
    import tomllib
except ImportError:
    from pip._vendor import tomli as tomllib
with open("pyproject.toml", "rb") as f:
    print("\n".join(tomllib.load(f)["build-system"]["requires"]))
endef
export BUILD_REQUIRES

# apt-get install, as root or through sudo.
APT_INSTALL = if [ "$$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi; \
  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq

.PHONY: all setup system-deps build python run lint format test bench clean distclean

all: build

# System packages, installed with apt-get only when something is missing.
system-deps:
	@missing=""; \
	for p in $(APT_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing system packages:$$missing"; \
	  $(APT_INSTALL) $$missing >/dev/null; \
	fi

$(BUILD)/build.ninja: CMakeLists.txt tests/fortran/tests.cmake | system-deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release

build: system-deps $(BUILD)/build.ninja
	cmake --build $(BUILD)

# The project virtual environment (Debian ships venv/ensurepip as python3-venv).
$(VPY):
	@if ! $(PYTHON) -c 'import venv, ensurepip' >/dev/null 2>&1; then \
	  echo "installing python3-venv (needed by $(PYTHON) -m venv)"; \
	  $(APT_INSTALL) python3-venv >/dev/null; \
	fi
	rm -rf $(VENV)
	$(PYTHON) -m venv $(VENV) || { rm -rf $(VENV); exit 1; }

# The Python package and every dependency, into the venv: first the build requirements
# (read from pyproject.toml), then the package with its `study` and `test` extras
# (scikit-build-core builds the f2py extension through CMakeLists.txt).
$(PY_STAMP): $(PY_SOURCES) $(VPY) | system-deps
	$(VPY) -c "$$BUILD_REQUIRES" > $(VENV)/build-requirements.txt
	$(PIP) install -q -r $(VENV)/build-requirements.txt
	$(PIP) install -q --no-build-isolation ".[study,test]"
	@touch $@

python: $(PY_STAMP)

setup: build python

# The main job: the cold deck's summary, then the default design study (cold and hot).
run: setup
	mkdir -p out
	$(BUILD)/ringlube-solve $(DEFAULT_DECK) -o out/crf450r_4000rpm_full_cold.h5
	$(VENV)/bin/ringlube optimise $(DEFAULT_STUDY) --direct --restart

# ruff and fprettify come with the `test` extra (pinned there: a formatter's output
# changes between versions). ruff's settings are in pyproject.toml.
lint: python
	$(VENV)/bin/ruff check pydriver tests
	$(VENV)/bin/ruff format --check pydriver tests
	@diff=$$($(VENV)/bin/fprettify --diff $(FORTRAN_FORMATTED)) || exit 1; \
	if [ -n "$$diff" ]; then echo "$$diff"; echo "Fortran not formatted (make format)"; exit 1; fi
	@echo "fprettify: $(words $(FORTRAN_FORMATTED)) Fortran files formatted"

format: python
	$(VENV)/bin/ruff check --fix pydriver tests
	$(VENV)/bin/ruff format pydriver tests
	$(VENV)/bin/fprettify $(FORTRAN_FORMATTED)

test: setup lint
	cd $(BUILD) && ctest --output-on-failure
	$(VPY) -m pytest -q

bench: setup
	$(VPY) tests/bench/python_overhead.py
	$(VPY) tests/bench/bench.py

clean:
	rm -rf $(BUILD) out

# Also the virtual environment (the next set-up downloads the Python packages again).
distclean: clean
	rm -rf $(VENV)
