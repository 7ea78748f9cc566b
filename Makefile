# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# The two commands of the README, and a few more for developers.
#   make demo   install what is missing, build, run the main job end to end
#   make test   install what is missing, build, run the whole test suite (Release: unit, scene,
#               host, integration and data tests; clang with ASan+UBSan: the tests of the readers
#               of outside input, and their fuzz targets briefly)
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo_output

.PHONY: all demo test deps configure build deb deb-arm64 cross test-cross test-release test-asan bench fuzz format clean

all: build

# DEPS_FLAGS=--test adds the tools the tests run against (PCL, Open3D, CloudCompare).
DEPS_FLAGS ?=

deps:
	@bash toolchain/install-deps.sh $(DEPS_FLAGS)
	@bash toolchain/setup-multicast.sh

configure: deps
	@cmake --preset release >/dev/null

build: configure
	@cmake --build --preset release -j $(JOBS)

# The demo needs the two programs only, not the tests.
demo: configure
	@bash toolchain/check-disk.sh 4
	@cmake --build --preset release -j $(JOBS) --target bimslam bimslam-rig
	@./build/release/bin/bimslam demo --out $(DEMO_OUT) --overwrite

# Debian packages of the Release build in build/release/packages (toolchain/debian/README.md):
# bimslam-rig and bimslam-tools, for this machine's architecture. Builds only what they hold.
deb: configure
	@cmake --build --preset release -j $(JOBS) --target deb_contents
	@cd build/release && cpack -G DEB

# The aarch64 cross-build (preset aarch64, toolchain/aarch64-linux-gnu.cmake): bimslam-rig,
# bimslam-go1-bridge and the unit tests of the libraries they link, into build/aarch64;
# test-cross runs those tests under qemu-user (CMake's cross-compiling emulator).
cross:
	@bash toolchain/install-deps.sh --cross
	@cmake --preset aarch64 >/dev/null
	@cmake --build --preset aarch64 -j $(JOBS)

test-cross: cross
	@ctest --preset aarch64 -j $(JOBS)

# bimslam-rig for arm64 from the cross-build, into build/aarch64/packages: only the two programs
# are built; dpkg-shlibdeps reads the staged libraries' shlibs/symbols (toolchain/README.md).
deb-arm64:
	@bash toolchain/install-deps.sh --cross
	@cmake --preset aarch64 >/dev/null
	@cmake --build build/aarch64 -j $(JOBS) --target deb_contents
	@cd build/aarch64 && cpack -G DEB

test: DEPS_FLAGS = --test
test: test-release test-asan

# The `sanitized` tests run in test-asan; Release builds and runs the rest (`make build` and
# `ctest --preset release` build and run everything, the sanitized tests included).
test-release: configure
	@bash toolchain/check-disk.sh 8
	@cmake --build --preset release -j $(JOBS) --target release_tests
	@ctest --preset integration -j $(JOBS)

# One clang build with AddressSanitizer, UndefinedBehaviorSanitizer and libFuzzer's coverage
# hooks: the tests of the readers of outside input, then the fuzz targets, each briefly. (GCC's
# ASan+UBSan build took twice clang's compile time, and a separate fuzz build compiled the
# readers a third time.)
test-asan: deps
	@cmake --preset asan >/dev/null
	@cmake --build --preset asan -j $(JOBS) --target sanitizer_tests fuzz_tests
	@ctest --preset asan -j $(JOBS)

bench: build
	@cmake --build --preset release -j $(JOBS) --target benchmarks
	@for b in build/release/bin/*_benchmark; do echo "== $$b"; $$b; done

# The fuzz targets long: FUZZ_SECONDS per libFuzzer target, FUZZ_ITERATIONS mutants per reader seed.
FUZZ_SECONDS ?= 600
FUZZ_ITERATIONS ?= 200000
fuzz: deps
	@cmake --preset asan >/dev/null
	@cmake --build --preset asan -j $(JOBS) --target fuzz_tests
	@BIMSLAM_FUZZ_SECONDS=$(FUZZ_SECONDS) BIMSLAM_FUZZ_ITERATIONS=$(FUZZ_ITERATIONS) \
		ctest --preset fuzz -j $(JOBS)

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	@rm -rf build
