# Two entry points for a fresh Debian 12 machine: `make demo` and `make test`.
# Every target installs missing Debian packages first, then builds into $(BUILD_DIR).
SHELL := /bin/bash
BUILD_DIR ?= build
# The catkin devel space: <repo>/devel for the default build (Debian's rosrun ignores everything
# below <package>/build/), <dir>/devel otherwise. scripts/devel_dir.sh is the one rule.
DEVEL_DIR := $(shell scripts/devel_dir.sh $(BUILD_DIR))
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
# Debian's ROS tools need Debian's interpreter (catkin_pkg, rospkg), not a pyenv one.
export PATH := /usr/bin:/bin:$(PATH)

.PHONY: all deps configure build test demo bench eval clean format fuzz soak

all: build

deps:
	@scripts/install_deps.sh

# A devel space left inside the build directory by an older layout (and the sanitizer builds that
# used to sit beside it) would give rosrun a second copy of every tool: removed.
configure: deps
	@if [[ "$(DEVEL_DIR)" != "$(abspath $(BUILD_DIR))/devel" ]]; then \
	  rm -rf $(BUILD_DIR)/devel $(BUILD_DIR)_asan $(BUILD_DIR)_tsan; fi
	@cmake -S . -B $(BUILD_DIR) -DPYTHON_EXECUTABLE=/usr/bin/python3 \
	  -DCATKIN_DEVEL_PREFIX=$(DEVEL_DIR) \
	  -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DCATKIN_ENABLE_TESTING=ON > $(BUILD_DIR).configure.log 2>&1 \
	  || { cat $(BUILD_DIR).configure.log; exit 1; }

build: configure
	@echo "[build] compiling into $(BUILD_DIR) with $(JOBS) jobs"
	@$(MAKE) --no-print-directory -C $(BUILD_DIR) -j$(JOBS) all

# After the normal tests, run_tests.sh runs scripts/sanitizer_tests.sh (ASan+UBSan unit tests in
# $(BUILD_DIR)/asan, TSan nodelet rostests in $(BUILD_DIR)/tsan) and counts them in its last line.
# SANITIZERS=0 skips them for quick local runs; SANITIZERS=asan or tsan runs one.
SANITIZERS ?= 1
test: build
	@$(MAKE) --no-print-directory -C $(BUILD_DIR) -j$(JOBS) tests
	@SANITIZERS='$(SANITIZERS)' JOBS=$(JOBS) scripts/run_tests.sh $(BUILD_DIR)

demo: build
	@scripts/demo.sh $(BUILD_DIR)

bench: build
	@bench/run_benchmarks.sh $(BUILD_DIR)

# The paper's depth and novel-view tables with the baselines (README, section Evaluation).
eval: build
	@scripts/eval.sh $(BUILD_DIR)

# libFuzzer harnesses (fuzz/, clang, ASan + UBSan) in build_fuzz, FUZZ_SECONDS each (default 60);
# fails on any crash, leak or timeout.
fuzz: deps
	@scripts/fuzz.sh $(FUZZ_SECONDS)

# The bag looped at 3x through pipeline.launch for SOAK_SECONDS (default 120; README: the 1-hour
# run), random parameter changes; fails on a crash, RSS growth >= 20 MB or drops beyond the policy.
SOAK_SECONDS ?= 120
soak: build
	@BUILD_DIR=$(BUILD_DIR) scripts/soak.sh $(SOAK_SECONDS)

format:
	@find include src test bench -name '*.hpp' -o -name '*.cpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR) $(DEVEL_DIR) $(BUILD_DIR).configure.log build_fuzz
