#!/usr/bin/env bash
# README command 2: build with warnings as errors and run the whole test suite under ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWALLCAL_WERROR=ON
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2
