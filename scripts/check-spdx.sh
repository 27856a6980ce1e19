#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Every source file of the project names its licence on its first line (after a #! line):
#   // SPDX-License-Identifier: Apache-2.0     (.cc, .h, .h.in)
#   # SPDX-License-Identifier: Apache-2.0      (CMakeLists.txt, .cmake, .cmake.in, .sh)
#   <!-- SPDX-License-Identifier: Apache-2.0 -->   (.html)
# Source files: the tracked .cc .h .in .cmake .sh .html and CMakeLists.txt files, less data
# (samples/, test/bad_sessions/: sessions, not sources).
# Usage: scripts/check-spdx.sh [--fix]
#   lists the files missing the line and exits 1 if any; --fix adds the line to them first.
set -euo pipefail
cd "$(dirname "$0")/.."
fix=0
[ "${1:-}" = "--fix" ] && fix=1
tag="SPDX-License-Identifier: Apache-2.0"
missing=0
while IFS= read -r -d '' file; do
  case "$file" in samples/*|test/bad_sessions/*) continue ;; esac
  first=$(head -n 1 "$file")
  second=$(sed -n 2p "$file")
  if [[ $first == *"$tag"* ]] || { [[ $first == '#!'* ]] && [[ $second == *"$tag"* ]]; }; then
    continue
  fi
  case "$file" in
    *.cc|*.h|*.h.in) line="// $tag" ;;
    *.html) line="<!-- $tag -->" ;;
    *) line="# $tag" ;;
  esac
  if [ $fix = 1 ]; then
    tmp="$file.spdx-tmp"
    if [[ $first == '#!'* ]]; then
      { printf '%s\n%s\n' "$first" "$line"; tail -n +2 "$file"; } > "$tmp"
    else
      { printf '%s\n' "$line"; cat "$file"; } > "$tmp"
    fi
    chmod --reference="$file" "$tmp"
    mv "$tmp" "$file"
    echo "check-spdx: added to $file"
  else
    echo "$file"
    missing=$((missing + 1))
  fi
done < <(if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
           git ls-files -z --cached --others --exclude-standard -- \
             '*.cc' '*.h' '*.in' '*.cmake' '*.sh' '*.html' 'CMakeLists.txt' '*/CMakeLists.txt'
         else  # a copy without git: every such file but the build folders'
           find . \( -name 'build*' -prune \) -o -type f \( -name '*.cc' -o -name '*.h' -o \
             -name '*.in' -o -name '*.cmake' -o -name '*.sh' -o -name '*.html' -o -name CMakeLists.txt \) \
             -printf '%P\0'
         fi)
if [ $missing -gt 0 ]; then
  echo "check-spdx: $missing file(s) without '$tag' on the first line (scripts/check-spdx.sh --fix adds it)" >&2
  exit 1
fi
