#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The installed wallcal, used as a user and as a downstream project would, with no source tree:
#  1. both packages' contents into a fresh root: the Debian packages themselves (dpkg -x) when
#     WALLCAL_DEB_DIR names a folder holding wallcal_*.deb and libwallcal-dev_*.deb
#     (scripts/package.sh writes them to build-release/), else the build's two install
#     components (cmake --install --component wallcal, then dev) under ROOT/usr;
#  2. the layout the packages promise: only wallcal in usr/bin, wallcal(1) gzipped, the bash
#     completion, the copyright files, no header from an internal/ folder;
#  3. wallcal --help, and wallcal calibrate on a copy of the sample from a folder where neither
#     the source tree nor the build tree can be found (configs come from ROOT/usr/share/wallcal);
#  4. test/downstream built against the installed package (find_package(wallcal)) and run.
# Usage: install_test.sh SOURCE_DIR BUILD_DIR   (ctest runs it; label "install")
set -euo pipefail
src=$1
build=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/wallcal-install-test.XXXXXX")
trap 'rm -rf "$work"' EXIT
root="$work/root"
fail() { echo "install_test: $*" >&2; exit 1; }

if [ -n "${WALLCAL_DEB_DIR:-}" ]; then
  for deb in "$WALLCAL_DEB_DIR"/wallcal_*.deb "$WALLCAL_DEB_DIR"/libwallcal-dev_*.deb; do
    [ -f "$deb" ] || fail "no $deb"
    dpkg-deb -x "$deb" "$root"
  done
  echo "install_test: unpacked $(cd "$WALLCAL_DEB_DIR" && ls wallcal_*.deb libwallcal-dev_*.deb | tr '\n' ' ')"
else
  cmake --install "$build" --component wallcal --prefix "$root/usr" >/dev/null
  cmake --install "$build" --component dev --prefix "$root/usr" >/dev/null
fi
prefix="$root/usr"

[ "$(ls "$prefix/bin")" = "wallcal" ] || fail "usr/bin holds $(ls "$prefix/bin" | tr '\n' ' ')"
test -s "$prefix/share/man/man1/wallcal.1.gz" || fail "no man page"
gzip -t "$prefix/share/man/man1/wallcal.1.gz"
test -s "$prefix/share/bash-completion/completions/wallcal" || fail "no bash completion"
grep -q "^Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/" \
  "$prefix/share/doc/wallcal/copyright" || fail "no machine-readable copyright"
test -s "$prefix/share/doc/libwallcal-dev/copyright" || fail "no copyright for libwallcal-dev"
internal=$(find "$prefix/include" -path '*/internal/*' | head -3)
[ -z "$internal" ] || fail "private headers installed: $internal"
test -f "$prefix/include/wallcal/pipeline/calibration.h" || fail "no public header"

cp -r "$src/samples/lms291-sapporo" "$work/session"
rm -f "$work/session/offsets.yaml"
cd "$work"
unset WALLCAL_CONFIG_DIR
"$prefix/bin/wallcal" --version
help=$("$prefix/bin/wallcal" --help)
grep -q "^  calibrate " <<< "$help" || fail "wallcal --help lists no calibrate"
"$prefix/bin/wallcal" characterise --version
"$prefix/bin/wallcal" calibrate session --output "$work/offsets.yaml" --quiet > "$work/summary.txt"
grep -q "x = 2.5426" "$work/summary.txt" || { cat "$work/summary.txt"; fail "installed wallcal calibrate gave another mount"; }
"$prefix/bin/wallcal" guide --version
test -s "$work/offsets.yaml"
cmake -S "$src/test/downstream" -B "$work/downstream" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/downstream" -j2 >/dev/null
WALLCAL_CONFIG_DIR="$prefix/share/wallcal" "$work/downstream/downstream" session \
  > "$work/mount.txt" 2>/dev/null
read -r x y yaw < "$work/mount.txt"
[ "$x" = "2.5426" ] && [ "$y" = "0.0621" ] || fail "downstream mount $x $y $yaw"
echo "install_test: installed wallcal calibrate and the downstream project both give x = $x m, y = $y m"
