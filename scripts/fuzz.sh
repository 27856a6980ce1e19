#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds the libFuzzer targets (one per reader, test/fuzz/) with clang into build-fuzz/ and runs
# each for FUZZ_SECONDS (default 60) with AddressSanitizer + UndefinedBehaviorSanitizer.
# Seeds: test/fuzz/corpus/<target>/, the bundled sample session, configs/, the bad-session corpus
# test/bad_sessions/, and ../shared/testdata/real/ when present. New inputs the fuzzer finds are
# kept in build-fuzz/fuzz-corpus/<target>/ (reused by the next run); a crash leaves its input in
# build-fuzz/fuzz-artifacts/ and makes this script fail.
# Usage: bash scripts/fuzz.sh [target ...]
#   (targets: carmen nmea survey gsi session_yaml config_yaml mcap rosbag2_yaml rosbag1 ros_messages)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
seconds=${FUZZ_SECONDS:-60}
jobs=${FUZZ_BUILD_JOBS:-2}
build=${FUZZ_BUILD_DIR:-build-fuzz}

bash scripts/install-deps.sh fuzz

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DCMAKE_CXX_COMPILER=clang++ -DWALLCAL_FUZZ=ON -DWALLCAL_WERROR=ON >/dev/null
cmake --build "$build" --target fuzz_targets -j"$jobs"

targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(carmen nmea survey gsi session_yaml config_yaml mcap rosbag2_yaml rosbag1 ros_messages)

# Seeds gathered fresh each run (small: logs are cut to their first lines).
seeds="$build/fuzz-seeds"
rm -rf "$seeds"
for t in "${targets[@]}"; do mkdir -p "$seeds/$t" "$build/fuzz-corpus/$t"; done
mkdir -p "$build/fuzz-artifacts"
add_head() {  # add_head TARGET FILE LINES: the first LINES lines of FILE (gzip: decompressed)
  local target=$1 file=$2 lines=$3 name
  [ -d "$seeds/$target" ] && [ -f "$file" ] || return 0
  name=$(echo "${file#"$root"/}" | tr '/' '_')
  if [[ $file == *.gz ]]; then
    { zcat "$file" 2>/dev/null || true; } | head -n "$lines" > "$seeds/$target/$name.head" || true
  else
    head -n "$lines" "$file" > "$seeds/$target/$name.head" || true
  fi
}
add_bytes() {  # add_bytes TARGET FILE BYTES: the first BYTES bytes of FILE
  [ -d "$seeds/$1" ] && [ -f "$2" ] || return 0
  head -c "$3" "$2" > "$seeds/$1/$(echo "${2#"$root"/}" | tr '/' '_').head"
}
add_file() {  # add_file TARGET FILE
  [ -d "$seeds/$1" ] && [ -f "$2" ] || return 0
  cp "$2" "$seeds/$1/$(echo "${2#"$root"/}" | tr '/' '_')"
}
for t in "${targets[@]}"; do
  for f in test/fuzz/corpus/"$t"/*; do add_file "$t" "$root/$f"; done
done
shopt -s nullglob globstar
for f in "$root"/samples/*/*.nmea "$root"/test/bad_sessions/**/*.nmea; do add_head nmea "$f" 60; done
for f in "$root"/samples/*/*.clf "$root"/test/bad_sessions/**/*.clf; do add_head carmen "$f" 4; done
for f in "$root"/samples/*/survey.csv "$root"/test/bad_sessions/**/*.csv; do add_file survey "$f"; done
for f in "$root"/samples/*/session.yaml "$root"/test/bad_sessions/**/*.yaml; do add_file session_yaml "$f"; done
for f in "$root"/configs/**/*.yaml "$root"/samples/*/truth.yaml; do add_file config_yaml "$f"; done
real="$root/../shared/testdata/real"
if [ -d "$real" ]; then
  for f in "$real"/nmea/*.log; do add_head nmea "$f" 80; done
  for f in "$real"/carmen/*.log.gz; do add_head carmen "$f" 6; done
  for f in "$real"/gsi/*.gsi; do add_head gsi "$f" 40; add_head survey "$f" 40; done
  for f in "$real"/ros2/*.mcap; do add_file mcap "$f"; done
  # Bag heads: the header and the start of the first chunk (cut: the reader's tail path).
  for f in "$real"/ros1/*.bag; do add_bytes rosbag1 "$f" 60000; done
fi

status=0
printf '%-14s %10s %8s %8s %8s  %s\n' target executions coverage features crashes result
for t in "${targets[@]}"; do
  log="$build/fuzz-$t.log"
  case $t in
    nmea) dict=nmea ;; carmen) dict=carmen ;; survey) dict=csv ;; gsi) dict=gsi ;; mcap) dict=mcap ;;
    rosbag2_yaml) dict=rosbag2 ;; rosbag1 | ros_messages) dict=ros ;; *) dict=yaml ;;
  esac
  rm -f "$build/fuzz-artifacts/$t-"*
  set +e
  # -max_len: CARMEN lines of a 361-beam scan are ~3 kB; 64 kB leaves room for several.
  # -rss_limit_mb: a reader holds one line at a time; 2 GB means a runaway allocation.
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=0 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/test/fuzz/fuzz_$t" -max_total_time="$seconds" -max_len=65536 -timeout=25 \
      -rss_limit_mb=2048 -print_final_stats=1 -dict="test/fuzz/dict/$dict.dict" \
      -artifact_prefix="$build/fuzz-artifacts/$t-" \
      "$build/fuzz-corpus/$t" "$seeds/$t" >"$log" 2>&1
  rc=$?
  set -e
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || true)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || true)
  crashes=$(ls "$build/fuzz-artifacts/" 2>/dev/null | grep -c "^$t-" || true)
  if [ $rc -eq 0 ]; then result=ok; else result="FAILED (exit $rc, see $log)"; status=1; fi
  printf '%-14s %10s %8s %8s %8s  %s\n' "$t" "${execs:-?}" "${cov:-?}" "${ft:-?}" "$crashes" "$result"
  if [ $rc -ne 0 ]; then grep -E 'ERROR|SUMMARY|runtime error|==[0-9]+==' "$log" | head -20 || true; fi
done
exit $status
