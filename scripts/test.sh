#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# README command 2: build everything (tests and benchmarks, warnings as errors) in build/ and run
# the whole test suite under ctest. After scripts/setup.sh only the tests are left to compile.
# Chromium and its WebDriver are installed too, for the test of guide --serve's page.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/configure.sh browser
cmake --build build -j"${JOBS:-2}"
# Twice as many tests as cores: the guide's follow and page tests mostly wait (on a log being
# appended, on the browser), leaving the cores to the others.
ctest --test-dir build --output-on-failure -j"$(( ${JOBS:-2} * 2 ))"
