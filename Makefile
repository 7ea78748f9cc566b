# The two commands of the README, and a few more for developers.
#   make demo   install what is missing, build, run the main job end to end
#   make test   install what is missing, build, run the whole test suite (Release: integration and
#               data tests; the unit tests under ASan+UBSan; the fuzz targets briefly under
#               clang + libFuzzer)
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo_output

.PHONY: all demo test deps configure build test-release test-asan test-fuzz bench fuzz format clean

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
	@cmake --build --preset release -j $(JOBS) --target bimslam bimslam-rig
	@./build/release/bin/bimslam demo --out $(DEMO_OUT) --overwrite

test: DEPS_FLAGS = --test
test: test-release test-asan test-fuzz

# The unit tests run in test-asan; Release builds and runs the rest (`make build` and
# `ctest --preset release` build and run everything, unit tests included).
test-release: configure
	@cmake --build --preset release -j $(JOBS) --target integration_tests
	@ctest --preset integration -j $(JOBS)

# The unit tests again, built with AddressSanitizer and UndefinedBehaviorSanitizer.
test-asan: deps
	@cmake --preset asan >/dev/null
	@cmake --build --preset asan -j $(JOBS) --target unit_tests
	@ctest --preset asan -j $(JOBS)

bench: build
	@cmake --build --preset release -j $(JOBS) --target benchmarks
	@for b in build/release/bin/*_benchmark; do echo "== $$b"; $$b; done

# The fuzz targets (clang, libFuzzer, ASan + UBSan), each run briefly.
test-fuzz: deps
	@cmake --preset fuzz >/dev/null
	@cmake --build --preset fuzz -j $(JOBS) --target fuzz_tests
	@ctest --preset fuzz -j $(JOBS)

# The same, long: FUZZ_SECONDS per libFuzzer target, FUZZ_ITERATIONS mutants per reader seed.
FUZZ_SECONDS ?= 600
FUZZ_ITERATIONS ?= 200000
fuzz: deps
	@cmake --preset fuzz >/dev/null
	@cmake --build --preset fuzz -j $(JOBS) --target fuzz_tests
	@BIMSLAM_FUZZ_SECONDS=$(FUZZ_SECONDS) BIMSLAM_FUZZ_ITERATIONS=$(FUZZ_ITERATIONS) \
		ctest --preset fuzz -j $(JOBS)

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	@rm -rf build
