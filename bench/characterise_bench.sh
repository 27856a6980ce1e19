#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# characterise's honesty over seeds: for each characterisation scenario, SEEDS simulated
# sessions (seeds 1..SEEDS), characterise on each, and RMS((estimate − truth) / reported σ) of
# k, b and the noise σ (honest σ: 0.8–1.25). Printed: the RMS over all seeds with the 90 %
# interval an honest σ would give for that many seeds (chi distribution), and the RMS of each
# block of 20 consecutive seeds (20 seeds alone scatter by ±16 %: 0.74–1.25 at 90 %).
# Usage: bench/characterise_bench.sh BUILD_DIR [SEEDS=200]
# Needs build/wallcal (cmake --build BUILD --target wallcal).
set -euo pipefail
build=${1:?usage: characterise_bench.sh BUILD_DIR [SEEDS]}
seeds=${2:-200}
src=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/wallcal_char_bench.XXXXXX")
trap 'rm -rf "$work"' EXIT
printf 'solver:\n  bootstrap_samples: 0\n' > "$work/fast.yaml"

# Per scenario: RMS over all seeds, its honest 90 % interval (Wilson–Hilferty quantiles of χ²
# with m degrees of freedom), the largest |err/σ| and how many are beyond 3 (an honest σ puts
# 0.27 % there), and the RMS of each block of 20 seeds.
cat > "$work/summary.awk" <<'AWK'
function rms_interval(m, z) { return sqrt((1 - 2 / (9 * m) + z * sqrt(2 / (9 * m))) ^ 3) }
$2 == "failed" { failed++; next }
function worst(v, i) { if (v < 0) v = -v; if (v > mx[i]) mx[i] = v; if (v > 3) over[i]++ }
{ m++; k += $2 * $2; b += $3 * $3; s += $4 * $4; worst($2, 1); worst($3, 2); worst($4, 3)
  blk = int((m - 1) / 20); bk[blk] += $2 * $2; bb[blk] += $3 * $3; bs[blk] += $4 * $4; bn[blk]++ }
END {
  printf "%-24s %3d runs (%d failed)  RMS(err/sigma): k %.2f  b %.2f  sigma %.2f" \
         "  (honest: %.2f-%.2f at 90 %%)\n", name, m, failed, sqrt(k / m), sqrt(b / m),
         sqrt(s / m), rms_interval(m, -1.645), rms_interval(m, 1.645)
  printf "  largest |err/sigma|: k %.2f  b %.2f  sigma %.2f;  beyond 3: k %d  b %d  sigma %d" \
         "  (honest: %.1f expected each)\n", mx[1], mx[2], mx[3], over[1], over[2], over[3],
         0.0027 * m
  for (j = 0; j * 20 < m; j++) {
    if (bn[j] < 20) break
    printf "  seeds %3d-%3d: k %.2f  b %.2f  sigma %.2f\n", 20 * j + 1, 20 * j + 20,
           sqrt(bk[j] / 20), sqrt(bb[j] / 20), sqrt(bs[j] / 20)
  }
}
AWK

# scenario  true n  true c (m)  true sigma (m)
run() {
  local scenario=$1 n=$2 c=$3 sigma=$4
  : > "$work/$scenario.txt"
  for seed in $(seq 1 "$seeds"); do
    "$build/wallcal" simulate --config "$src/configs/simulate/$scenario.yaml" --seed "$seed" \
        --output "$work/s" > /dev/null
    "$build/wallcal" characterise "$work/s" --config "$work/fast.yaml" --output "$work/p.yaml" \
        > "$work/out.txt" || true
    awk -v n="$n" -v c="$c" -v s="$sigma" -v seed="$seed" '
      $1 == "k" { k = $3; sk = $5 }
      $1 == "b_mm" { b = $3; sb = $5 }
      $1 == "sigma_mm" { sg = $3; ssg = $5 }
      END { if (sk == "" || sb == "" || ssg == "") { print seed, "failed"; exit }
            printf "%d %.3f %.3f %.3f\n", seed, (k - 1 / n) / sk, (b - (-1000 * c / n)) / sb,
                   (sg - 1000 * s) / ssg }' "$work/out.txt" >> "$work/$scenario.txt"
    rm -rf "$work/s"
  done
  awk -v name="$scenario" -f "$work/summary.awk" "$work/$scenario.txt"
}
run characterise_lms291 0.9992 0.006 0.008
run characterise_urg04lx 0.9899 0.007 0.0029

# The warm-up drift over the first hour (8.4 mm · (1 − e^−3) = 7.98 mm), DRIFT_SEEDS seeds
# (default 10: each session is an hour long).
drift_seeds=${DRIFT_SEEDS:-10}
: > "$work/drift.txt"
for seed in $(seq 1 "$drift_seeds"); do
  "$build/wallcal" simulate --config "$src/configs/simulate/characterise_lms291_warmup.yaml" \
      --seed "$seed" --output "$work/s" > /dev/null
  "$build/wallcal" characterise "$work/s" --config "$work/fast.yaml" --output "$work/p.yaml" \
      > "$work/out.txt" || true
  awk '$1 == "drift_mm" { printf "%.3f\n", ($3 - 7.98) / $5 }' "$work/out.txt" >> "$work/drift.txt"
  rm -rf "$work/s"
done
awk -v n="$drift_seeds" '
  function rms_interval(m, z) { return sqrt((1 - 2 / (9 * m) + z * sqrt(2 / (9 * m))) ^ 3) }
  { m++; d += $1 * $1; if ($1 * $1 <= 1) within++ }
  END { printf "%-24s %2d runs of %d  RMS(err/sigma): drift over the first hour %.2f" \
               "  (honest: %.2f-%.2f at 90 %%); %d of %d within 1 sigma\n",
               "characterise_lms291_warmup", m, n, sqrt(d / m), rms_interval(m, -1.645),
               rms_interval(m, 1.645), within, m }' "$work/drift.txt"
