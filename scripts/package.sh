#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The Debian packages: a Release build (no tests, no benchmarks) with prefix /usr in
# build-release/, then cpack -G DEB, stripped. Writes build-release/wallcal_VERSION-1_amd64.deb
# (the program) and build-release/libwallcal-dev_VERSION-1_amd64.deb (headers, static libraries,
# CMake package). Install with: sudo apt install ./build-release/wallcal_*.deb
# Usage: scripts/package.sh [lintian]   (lintian: also run lintian on both packages)
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build-release -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr \
  -DWALLCAL_TESTS=OFF -DWALLCAL_BENCH=OFF "${launcher[@]}"
cmake --build build-release -j"${JOBS:-2}"
(cd build-release && cpack -G DEB)
ls -l build-release/*.deb
for deb in build-release/wallcal_*.deb build-release/libwallcal-dev_*.deb; do
  echo "$(basename "$deb"): installed size $(dpkg-deb -f "$deb" Installed-Size) KiB"
done
if [ "${1:-}" = "lintian" ]; then
  lintian --info build-release/wallcal_*.deb build-release/libwallcal-dev_*.deb || true
fi
