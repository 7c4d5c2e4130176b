# ringlube: the two commands of the README.
#   make run   set up if needed, then run the main job on the shipped default inputs
#   make test  set up if needed, then every test
SHELL := /bin/bash
BUILD ?= build
PYTHON ?= python3
APT_PACKAGES := gfortran cmake ninja-build libhdf5-dev hdf5-tools liblapack-dev libblas-dev
DEFAULT_DECK := inputs/crf450r_4000rpm_full_cold.nml

.PHONY: all setup system-deps build run test clean

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

setup: build

run: setup
	mkdir -p out
	$(BUILD)/ringlube-solve $(DEFAULT_DECK) -o out/crf450r_4000rpm_full_cold.h5

test: setup
	cd $(BUILD) && ctest --output-on-failure

clean:
	rm -rf $(BUILD) out
