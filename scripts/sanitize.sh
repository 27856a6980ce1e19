#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds everything with AddressSanitizer + UndefinedBehaviorSanitizer (g++, -DWALLCAL_SANITIZE=ON)
# into build-asan/ and runs the whole ctest suite under it. Any sanitizer report fails the run:
# UBSan halts on the first error (-fno-sanitize-recover), LeakSanitizer reports leaks at exit.
# Usage: bash scripts/sanitize.sh [extra ctest arguments, e.g. -R bad_sessions]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${SANITIZE_BUILD_DIR:-build-asan}
jobs=${SANITIZE_BUILD_JOBS:-2}

bash scripts/install-deps.sh

# Also in effect while building: gtest_discover_tests runs each test binary to list its tests.
export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# -O1 -g1: quicker to compile than RelWithDebInfo, still with file:line in sanitizer reports.
# The benchmarks are not tests: not built here. No -Werror here: GCC 12 gives false
# maybe-uninitialized warnings inside std::regex under ASan at -O1; the main build (scripts/test.sh)
# enforces warnings as errors.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g1" \
  -DWALLCAL_BENCH=OFF -DWALLCAL_SANITIZE=ON -DWALLCAL_WERROR=OFF >/dev/null
cmake --build "$build" -j"$jobs"
# Twice as many tests as build jobs, as scripts/test.sh: several tests mostly wait.
ctest --test-dir "$build" --output-on-failure -j"$(( jobs * 2 ))" "$@"
