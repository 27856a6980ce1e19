#!/usr/bin/env bash
# README command 1: install what is missing, build, and calibrate the bundled sample session.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j2
./build/wallcal calibrate samples/lms291-sapporo --output build/sample-offsets.yaml
echo "setup: offsets written to build/sample-offsets.yaml; programs are in build/"
