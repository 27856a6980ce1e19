#!/usr/bin/env bash
# The installed wallcal, used as a user and as a downstream project would, with no source tree:
#  1. cmake --install the build into a fresh prefix;
#  2. copy the sample session out, and run the installed calibrate from a folder where neither
#     the source tree nor the build tree can be found (configs come from <prefix>/share/wallcal);
#  3. build test/downstream against the installed package (find_package(wallcal)) and run it.
# Usage: install_test.sh SOURCE_DIR BUILD_DIR   (ctest runs it; label "install")
set -euo pipefail
src=$1
build=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/wallcal-install-test.XXXXXX")
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cp -r "$src/samples/lms291-sapporo" "$work/session"
rm -f "$work/session/offsets.yaml"
cd "$work"
unset WALLCAL_CONFIG_DIR
"$work/prefix/bin/calibrate" --version
"$work/prefix/bin/characterise" --version
"$work/prefix/bin/guide" --version
"$work/prefix/bin/calibrate" session --output "$work/offsets.yaml" --quiet > "$work/summary.txt"
grep -q "x = 2.5422" "$work/summary.txt" || { cat "$work/summary.txt"; echo "install_test: installed calibrate gave another mount" >&2; exit 1; }
test -s "$work/offsets.yaml"
cmake -S "$src/test/downstream" -B "$work/downstream" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/downstream" -j2 >/dev/null
WALLCAL_CONFIG_DIR="$work/prefix/share/wallcal" "$work/downstream/downstream" session \
  > "$work/mount.txt" 2>/dev/null
read -r x y yaw < "$work/mount.txt"
[ "$x" = "2.5422" ] && [ "$y" = "0.0630" ] || { echo "install_test: downstream mount $x $y $yaw" >&2; exit 1; }
echo "install_test: installed calibrate and the downstream project both give x = $x m, y = $y m"
