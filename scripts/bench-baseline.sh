#!/usr/bin/env bash
# Benchmark baselines: one CSV per machine and SIMD path, bench/baselines/<machine>/<path>.csv.
# A row per scene: the seed scenes (weft-bench drape, flag, sphere at n = 50 and 100: lowest median
# of 3 runs) and the dressed garments on their animated bodies (weft-bench garment, every collision
# model), pinned to one core, with the time per step, the passes that dominate it and the strain it
# ends with (the strains are deterministic: a changed strain is a changed result, not noise).
#   scripts/bench-baseline.sh            # (re)write this machine's CSVs
#   scripts/bench-baseline.sh --check    # run the same set, print each row's time against the CSV
# Timings are only comparable on the machine that wrote the CSV, and noisy there: --check prints
# ratios, it does not fail. Environment: WEFT_BUILD_DIR (default build), WEFT_BENCH_CPU (default 1
# when there are two or more), WEFT_BASELINE_DIR (default bench/baselines).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
build=${WEFT_BUILD_DIR:-build}
bench_tool=$build/tools/bench/weft-bench
check=false
[[ "${1:-}" == "--check" ]] && check=true
command -v jq >/dev/null || { echo "bench-baseline: needs jq (scripts/install-deps.sh)" >&2; exit 1; }
[[ -x "$bench_tool" ]] || { echo "bench-baseline: no $bench_tool (ninja -C $build weft-bench)" >&2; exit 1; }

machine=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | tr 'A-Z' 'a-z' | sed 's/([^)]*)//g; s/[^a-z0-9]\+/-/g; s/^-//; s/-$//')
dir=${WEFT_BASELINE_DIR:-bench/baselines}/$machine
cpus=$(nproc 2>/dev/null || echo 1)
cpu=${WEFT_BENCH_CPU:-$([[ $cpus -ge 2 ]] && echo 1 || echo 0)}
pin=()
command -v taskset >/dev/null && [[ $cpus -ge 2 ]] && pin=(taskset -c "$cpu")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

header="bench,scene,n,config,collision,simd,sweeps,us_per_step,constraints_us,body_us,normals_us,max_strain,mean_strain"
# One CSV row per JSON line; fields a bench does not have are left empty.
to_csv() {
  jq -r --arg bench "$1" '[$bench, .scene, (.n // .particles), (.config // ""), (.collision // ""), .simd,
      (.sweeps // ((.substeps // 1) * (.iterations // 1))), .us_per_step, .constraints_us, (.body_us // ""),
      (.normals_us // ""), .max_strain, .mean_strain] | @csv'
}

for path in scalar avx2; do
  echo "bench-baseline: $path on $machine (cpu $cpu)" >&2
  for scene in drape flag sphere; do
    "${pin[@]}" "$bench_tool" "$scene" --sizes 50,100 --repeat 3 --paths "$path" --json 2>/dev/null |
      grep '^{' | to_csv "$scene" >>"$tmp/$path.rows"
  done
  "${pin[@]}" "$bench_tool" garment --json --steps 200 --simd "$path" 2>/dev/null |
    grep '^{' | to_csv garment >>"$tmp/$path.rows"
  { echo "$header"; cat "$tmp/$path.rows"; } >"$tmp/$path.csv"
done

if ! $check; then
  mkdir -p "$dir"
  for path in scalar avx2; do cp "$tmp/$path.csv" "$dir/$path.csv"; done
  echo "bench-baseline: wrote $dir/scalar.csv, $dir/avx2.csv ($(($(wc -l <"$dir/avx2.csv") - 1)) rows each)"
  exit 0
fi

# --check: this run's time per step over the committed one, row by row (keyed by everything but
# the figures); strains that differ are flagged, being results rather than timings.
for path in scalar avx2; do
  [[ -f "$dir/$path.csv" ]] || { echo "bench-baseline: no $dir/$path.csv for this machine" >&2; exit 1; }
  echo "== $path: now / baseline ($dir/$path.csv)"
  awk -F, 'NR == FNR { if (FNR > 1) { key = $1 FS $2 FS $3 FS $4 FS $5 FS $7; t[key] = $8; s[key] = $12 } next }
           FNR > 1 { key = $1 FS $2 FS $3 FS $4 FS $5 FS $7
                     if (!(key in t)) { printf "%-60s new row\n", key; next }
                     printf "%-60s %9.1f us  x%.2f%s\n", key, $8, $8 / t[key], ($12 == s[key] ? "" : "  strain changed")
                   }' "$dir/$path.csv" "$tmp/$path.csv"
done
