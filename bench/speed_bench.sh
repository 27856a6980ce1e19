#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Speed benchmark: simulate -> calibrate on LMS 291 sessions of growing length, against the
# floor of reading the same scan log (bench/parse_floor: getline + strtod, one thread),
# measured in the same run. Prints a markdown table (docs/results.md, "Speed").
#
# usage: bench/speed_bench.sh [BUILD_DIR] [MINUTES...]
#   BUILD_DIR  the build with wallcal and bench/parse_floor (default build)
#   MINUTES    session lengths (default: 5 15 60 240); one station a minute (59.5 s stops),
#              75 scans/s, the scenario of configs/simulate/bench_lms291_hour.yaml
# Then one more row, "60 + drives": the hour with car-like drives between the stations and the
# logger's delays (configs/simulate/bench_lms291_hour_drives.yaml), whose drives determine the
# scanner clock offset and the heading delay, so that calibrate makes clock rounds. DRIVES=0
# leaves it out.
# Environment: SPEED_BENCH_DIR, when set, holds the sessions and keeps them for the next run (a
# 4-hour session is 1.4 GB, simulated once); unset, they go to a temporary folder removed at
# exit. THREADS is passed to wallcal calibrate --threads (default: every core).
# Needs /usr/bin/time (Debian package `time`: scripts/install-deps.sh bench).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-build}"
shift || true
minutes=("$@")
[ ${#minutes[@]} -gt 0 ] || minutes=(5 15 60 240)
case "$build" in /*) ;; *) build="$root/$build" ;; esac
threads="${THREADS:-0}"
for program in wallcal bench/parse_floor; do
  [ -x "$build/$program" ] || { echo "speed_bench: $build/$program not built" >&2; exit 2; }
done
[ -x /usr/bin/time ] || { echo "speed_bench: /usr/bin/time missing (apt-get install time)" >&2; exit 2; }
if [ -n "${SPEED_BENCH_DIR:-}" ]; then
  work="$SPEED_BENCH_DIR"
  mkdir -p "$work"
else
  work=$(mktemp -d "${TMPDIR:-/tmp}/wallcal-speed-bench.XXXXXX")
  trap 'rm -rf "$work"' EXIT
fi

# Runs a command, prints "SECONDS PEAK_RSS_MB" (wall clock, maximum resident set).
measure() {
  local out="$work/time.txt"
  /usr/bin/time -o "$out" -f "%e %M" "$@" > "$work/stdout.txt" 2> "$work/stderr.txt" || {
    echo "speed_bench: failed: $*" >&2; cat "$work/stderr.txt" >&2; exit 3; }
  awk '{printf "%.2f %.0f\n", $1, $2 / 1024}' "$out"
}

thread_args=()
[ "$threads" = 0 ] || thread_args=(--threads "$threads")

echo "machine: $(nproc) cores, $(awk '/model name/ {sub(/.*: /, ""); print; exit}' /proc/cpuinfo)"
read -r sample_s sample_mb < <(measure "$build/wallcal" calibrate "$root/samples/lms291-sapporo" \
                               --output "$work/sample-offsets.yaml" --quiet "${thread_args[@]}")
echo "bundled sample (samples/lms291-sapporo): calibrate ${sample_s} s, peak ${sample_mb} MB"
echo
echo "| minutes | scans | log MB | floor s | calibrate s | × floor | peak MB | inspect s | × floor | calibrate µs/scan |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
# One row of the table: its label, the simulation config, the session folder (simulated once).
row() {
  local label="$1" config="$2" session="$3"
  if [ ! -f "$session/scans.clf" ]; then
    "$build/wallcal" simulate --config "$config" --output "$session" > /dev/null
  fi
  local scans log_mb floor_s cal_s cal_mb ins_s
  scans=$(grep -c '^RAWLASER1' "$session/scans.clf")
  log_mb=$(( $(stat -c %s "$session/scans.clf") / 1000000 ))
  cat "$session/scans.clf" > /dev/null  # the page cache holds the log for every reader alike
  read -r floor_s _ < <(measure "$build/bench/parse_floor" "$session/scans.clf")
  read -r cal_s cal_mb < <(measure "$build/wallcal" calibrate "$session" --output "$work/offsets.yaml" \
                           --force --quiet "${thread_args[@]}")
  read -r ins_s _ < <(measure "$build/wallcal" inspect "$session")
  awk -v m="$label" -v n="$scans" -v mb="$log_mb" -v f="$floor_s" -v c="$cal_s" -v r="$cal_mb" \
      -v i="$ins_s" 'BEGIN {printf "| %s | %d | %d | %.2f | %.2f | %.2f | %d | %.2f | %.2f | %.1f |\n",
                     m, n, mb, f, c, c / f, r, i, i / f, 1e6 * c / n}'
}

for m in "${minutes[@]}"; do
  sed -e "s/^num_stations: .*/num_stations: ${m}/" -e "s/^name: .*/name: speed-${m}min/" \
    "$root/configs/simulate/bench_lms291_hour.yaml" > "$work/speed-${m}min.yaml"
  row "$m" "$work/speed-${m}min.yaml" "$work/session-${m}min"
done
if [ "${DRIVES:-1}" != 0 ]; then
  row "60 + drives" "$root/configs/simulate/bench_lms291_hour_drives.yaml" "$work/session-60min-drives"
fi
