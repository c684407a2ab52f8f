#!/usr/bin/env bash
# Builds the libFuzzer harnesses with clang (build-fuzz/, WEFT_FUZZ=ON), replays each one's seed
# corpus, then fuzzes each for a bounded time. Exits non-zero on any crash, leak or sanitizer report.
#   bash scripts/fuzz.sh [SECONDS]     # per harness, default 60
# Environment: WEFT_FUZZ_BUILD_DIR (default build-fuzz). New inputs the fuzzer finds go to
# $build/corpus/<harness>/ (the checked-in corpus is only read); crashes to $build/artifacts/.
# To keep a crasher as a regression seed, copy it into tests/fuzz/corpus/<harness>/.
set -euo pipefail

# One line per harness: tests/fuzz/fuzz_<name>.cpp with its seed corpus in tests/fuzz/corpus/<name>/
# (and a weft_fuzz_harness line in tests/fuzz/CMakeLists.txt).
harnesses=(
  asset_loader
  pattern
)

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
seconds=${1:-60}
build=${WEFT_FUZZ_BUILD_DIR:-build-fuzz}
jobs=$(nproc 2>/dev/null || echo 2)
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (bash scripts/install-deps.sh)" >&2; exit 1; }

mkdir -p "$build"
echo "== fuzz: configure ($build)"
if ! CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWEFT_FUZZ=ON \
    -DWEFT_BUILD_TESTS=OFF -DWEFT_BUILD_TOOLS=OFF >"$build/configure.log" 2>&1; then
  cat "$build/configure.log"
  exit 1
fi
echo "== fuzz: build"
targets=("${harnesses[@]/#/fuzz_}")
if ! ninja -C "$build" -j "$jobs" "${targets[@]}" >"$build/build.log" 2>&1; then
  grep -E -A5 'error|FAILED' "$build/build.log" | head -n 80
  exit 1
fi

export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=0:halt_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
failed=0
for name in "${harnesses[@]}"; do
  exe="$build/tests/fuzz/fuzz_$name"
  seeds="tests/fuzz/corpus/$name"
  work="$build/corpus/$name"
  artifacts="$build/artifacts/$name/"
  mkdir -p "$work" "$artifacts"
  echo "== fuzz $name: replay $(ls "$seeds" | wc -l) seeds"
  if ! "$exe" -runs=0 "$seeds" >"$build/$name-replay.log" 2>&1; then
    tail -n 40 "$build/$name-replay.log"
    echo "fuzz $name: a seed FAILED"
    failed=1
    continue
  fi
  echo "== fuzz $name: ${seconds}s"
  if ! "$exe" -max_total_time="$seconds" -artifact_prefix="$artifacts" -print_final_stats=1 \
      "$work" "$seeds" >"$build/$name-fuzz.log" 2>&1; then
    tail -n 60 "$build/$name-fuzz.log"
    echo "fuzz $name: CRASH, input in $artifacts"
    failed=1
    continue
  fi
  grep -E 'stat::number_of_executed_units|cov:' "$build/$name-fuzz.log" | tail -n 2 | sed 's/^/   /'
done
echo "fuzz.sh: $([[ $failed == 0 ]] && echo PASS || echo FAIL) (${harnesses[*]}, ${seconds}s each)"
exit "$failed"
