# Thin wrapper around CMake. `make run` and `make test` install what is missing first.
BUILD ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)

.PHONY: all deps configure build run test bench clean test-sanitize fuzz valgrind install

all: build

deps:
	@scripts/install-deps.sh

configure:
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

run: deps build
	$(BUILD)/radiosity render

test: deps build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Every bench/bench_*.c; tables go to stdout (bench/README.md keeps the measured ones).
bench: deps build
	@for b in $(BUILD)/bench_*; do [ -x "$$b" ] && "$$b"; echo; done

# The whole suite again under AddressSanitizer and UndefinedBehaviorSanitizer, in its own build
# dir; any sanitizer report fails it (scripts/test-sanitize.sh).
test-sanitize: deps
	@scripts/test-sanitize.sh build-sanitize

# Each libFuzzer target (fuzz/fuzz_*.c, clang) for FUZZ_SECONDS (default 60) from its seed corpus;
# FUZZ_TARGETS="ffm image" picks some.
fuzz: deps
	@scripts/fuzz.sh build-fuzz $(FUZZ_TARGETS)

# A short solve, render and path trace under valgrind memcheck: no errors, no leaks.
valgrind: deps
	@scripts/valgrind-check.sh build-valgrind

# The header, static and shared library, radiosity.pc, the CMake package and the tool under
# PREFIX (default /usr/local): make install PREFIX=$HOME/.local
PREFIX ?= /usr/local
install: build
	cmake --install $(BUILD) --prefix $(PREFIX)

clean:
	rm -rf $(BUILD)
