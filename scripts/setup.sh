#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# README command 1: install what is missing, build what `wallcal calibrate` needs (the wallcal
# target and its configs: no tests, no benchmarks) and calibrate the bundled sample session.
# ccache is used when found. scripts/test.sh then builds the tests in the same build/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/configure.sh
cmake --build build -j"${JOBS:-2}" --target wallcal
./build/wallcal calibrate samples/lms291-sapporo --output build/sample-offsets.yaml
echo "setup: offsets written to build/sample-offsets.yaml; the program is build/wallcal"
