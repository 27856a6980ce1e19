#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The first half of README commands 1 and 2 (scripts/setup.sh, scripts/test.sh): install what is
# missing and configure build/ (RelWithDebInfo, warnings as errors unless WALLCAL_WERROR=OFF,
# ccache as the compiler launcher when found). Its arguments are install-deps.sh's options
# (scripts/test.sh asks for the browser its page test drives).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh "$@"
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
# -g1: line tables for backtraces and sanitizer reports, not the full debug information (a
# quarter less compile time, smaller objects and links); a Debug build has it all.
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DWALLCAL_WERROR="${WALLCAL_WERROR:-ON}" "${launcher[@]}"
