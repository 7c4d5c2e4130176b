# ringlube: the two commands of the README.
#   make run   set up if needed, then run the main job on the shipped default inputs
#   make test  set up if needed, then every test
SHELL := /bin/bash
BUILD ?= build
PYTHON ?= python3
APT_PACKAGES := gfortran cmake ninja-build libhdf5-dev hdf5-tools liblapack-dev libblas-dev
DEFAULT_DECK := inputs/crf450r_4000rpm_full_cold.nml

PY_STAMP := $(BUILD)/.python-installed
PY_SOURCES := $(wildcard fortran/src/*.f90 fortran/f2py/*.f90 pydriver/ringlube/*.py) pyproject.toml CMakeLists.txt

.PHONY: all setup system-deps build python run test bench clean

all: build

# System packages, installed with apt-get only when something is missing.
system-deps:
	@missing=""; \
	for p in $(APT_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing system packages:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null; \
	fi

$(BUILD)/build.ninja: CMakeLists.txt tests/fortran/tests.cmake | system-deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release

build: system-deps $(BUILD)/build.ninja
	cmake --build $(BUILD)

# The Python package (scikit-build-core builds the f2py extension through CMakeLists.txt).
$(PY_STAMP): $(PY_SOURCES) | system-deps
	$(PYTHON) -m pip install -q --disable-pip-version-check "scikit-build-core>=0.10" "numpy>=2.0" "f2py-cmake>=0.2" ninja pytest
	$(PYTHON) -m pip install -q --disable-pip-version-check --no-build-isolation .
	@mkdir -p $(BUILD) && touch $@

python: $(PY_STAMP)

setup: build python

DEFAULT_STUDY := inputs/study_default.nml

# The main job: the cold deck's summary, then the default design study (cold and hot).
run: setup
	mkdir -p out
	$(BUILD)/ringlube-solve $(DEFAULT_DECK) -o out/crf450r_4000rpm_full_cold.h5
	ringlube optimise $(DEFAULT_STUDY) --direct

test: setup
	cd $(BUILD) && ctest --output-on-failure
	$(PYTHON) -m pytest -q

bench: setup
	$(PYTHON) tests/bench/python_overhead.py
	$(PYTHON) tests/bench/bench.py

clean:
	rm -rf $(BUILD) out
