#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs the Debian 12 packages wallcal builds with, if any is missing. Needs root (or sudo).
# Usage: install-deps.sh [fuzz] [bench] [browser]
#   fuzz: also clang with its libFuzzer/sanitizer runtimes (scripts/fuzz.sh);
#   bench: also /usr/bin/time (package time), for bench/speed_bench.sh;
#   browser: also Chromium and its WebDriver, for the test of guide --serve's page in a real
#     browser (test/serve/guide_page_browser_test.cc; skipped, saying so, without them).
# The sanitizer build (scripts/sanitize.sh) needs nothing more: g++'s
# AddressSanitizer and UBSan runtimes come with build-essential.
set -euo pipefail
packages=(build-essential cmake pkg-config libeigen3-dev libceres-dev libopencv-dev
          libgeographiclib-dev libyaml-cpp-dev libgtest-dev zlib1g-dev libbz2-dev
          liblz4-dev libzstd-dev libsqlite3-dev libssl-dev libcpp-httplib-dev)
for extra in "$@"; do
  case "$extra" in
    fuzz) packages+=(clang libclang-rt-dev) ;;
    bench) packages+=(time) ;;
    browser) packages+=(chromium chromium-driver) ;;
    *) echo "install-deps: unknown option '$extra'; expected fuzz, bench or browser" >&2; exit 2 ;;
  esac
done
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
