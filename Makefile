# Thin wrapper around CMake. `make run` and `make test` install what is missing first.
BUILD ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)

.PHONY: all deps configure build run test bench clean test-sanitize

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

clean:
	rm -rf $(BUILD)
