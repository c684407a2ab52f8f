#!/usr/bin/env bash
# The main job: builds Release, bakes the sample patterns (weft-bake, through the build's
# weft_bake() rules), runs the baked drape in weft-sim, then the seed paper's experiments (Liu, Sun,
# Xu 2008, section 3): the drape timing table beside the paper's, the flag (wind) and the sphere
# (collision), then sews the sample skirt onto the project's own mannequin (weft-bake --body
# mannequin) and runs it on the walking mannequin, and draws three pictures (out/drape-baked.png,
# out/sphere.png, out/skirt-walk.png) with weft-sim --png. Timings: lowest median of 3 runs (see README).
#   bash scripts/main-job.sh
# Environment: WEFT_BUILD_DIR (default build), WEFT_OUT_DIR (default out; JSON lines land there),
# WEFT_BENCH_CPU (CPU to pin the single-threaded bench to; default 1 when there are two or more).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
build_dir=${WEFT_BUILD_DIR:-build}
out_dir=${WEFT_OUT_DIR:-out}
mkdir -p "$build_dir" "$out_dir"

echo "== build (Release, $build_dir)"
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DWEFT_SANITIZE=OFF >"$build_dir/configure.log" 2>&1 ||
  { cat "$build_dir/configure.log"; exit 1; }
ninja -C "$build_dir" weft-bench weft-sim weft-bake sample_assets >"$build_dir/build.log" 2>&1 || { grep -E -A5 'error|FAILED' "$build_dir/build.log" | head -n 80; exit 1; }

bench=("$build_dir/tools/bench/weft-bench")
cpus=$(nproc 2>/dev/null || echo 1)
cpu=${WEFT_BENCH_CPU:-$([[ $cpus -ge 2 ]] && echo 1 || echo 0)}
if command -v taskset >/dev/null && [[ $cpus -ge 2 ]]; then
  bench=(taskset -c "$cpu" "${bench[@]}")
fi
json="$out_dir/seed-bench.jsonl"
: >"$json"

echo "== machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $cpus CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "== bench: ${bench[*]}"
echo
echo "== bake: samples/patterns -> $build_dir/samples/assets"
for asset in "$build_dir"/samples/assets/*.weft; do
  "$build_dir/tools/bake/weft-bake" --info "$asset" --json
done
echo
echo "== weft-sim: the seed drape from the baked sheet, then from the in-memory grid"
sim=("${bench[@]:0:${#bench[@]}-1}" "$build_dir/tools/sim/weft-sim")
"${sim[@]}" samples/scenes/drape-baked.json --assets "$build_dir/samples/assets"
"${sim[@]}" samples/scenes/drape.json
echo
echo "== the sample skirt dressed on the mannequin (weft-bake --body mannequin), then walking (weft-sim)"
"$build_dir/tools/bake/weft-bake" samples/patterns/skirt.json --body mannequin -o "$out_dir/skirt-dressed.weft"
"${sim[@]}" samples/scenes/skirt-walk.json --assets "$out_dir"
echo
echo "== pictures (weft-sim --png: tools/render on Mesa's llvmpipe, headless)"
sim_tool="$build_dir/tools/sim/weft-sim"
if "$sim_tool" samples/scenes/drape-baked.json --assets "$build_dir/samples/assets" --png "$out_dir/drape-baked.png" >/dev/null &&
  "$sim_tool" samples/scenes/sphere.json --png "$out_dir/sphere.png" >/dev/null &&
  "$sim_tool" samples/scenes/skirt-walk.json --assets "$out_dir" --png "$out_dir/skirt-walk.png" >/dev/null; then
  echo "pictures: $out_dir/drape-baked.png, $out_dir/sphere.png, $out_dir/skirt-walk.png (1280x720)"
else
  echo "pictures: not written (weft-sim built without the renderer? run scripts/install-deps.sh)"
fi
echo
"${bench[@]}" drape --sizes 25,50,75,100 --repeat 3 --json-out "$json"
echo
"${bench[@]}" flag --sizes 25,50,100 --json-out "$json"
echo
"${bench[@]}" sphere --sizes 25,50,100 --json-out "$json"
echo
echo "main-job: done; $(wc -l <"$json") JSON lines in $json"
