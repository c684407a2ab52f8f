#!/usr/bin/env bash
# Builds and tests Weft: Release (build/), then AddressSanitizer + UBSan, RelWithDebInfo
# (build-asan/); between them, the tests without the tools (-DWEFT_BUILD_TOOLS=OFF, Release,
# build-notools/: the runtime, cook, lib/ and the tests only, so that they stay buildable without
# the tools); then, where clang is installed, checks the determinism hashes with a Clang build
# (build-clang/) and fuzzes briefly (scripts/fuzz.sh, build-fuzz/).
# Every configuration runs even when an earlier one fails, so one report shows them all.
#   bash scripts/test.sh
# Environment: WEFT_BUILD_DIR, WEFT_ASAN_BUILD_DIR, WEFT_FUZZ_BUILD_DIR (build directories, relative
# to the repository), WEFT_NOTOOLS_BUILD_DIR (default build-notools), WEFT_SKIP_NOTOOLS=1 (no
# tools-off build), WEFT_SKIP_ASAN=1 (no ASan build), WEFT_SKIP_FUZZ=1, WEFT_FUZZ_SECONDS (per
# harness, default 30), WEFT_CTEST_ARGS (extra ctest arguments, e.g. "-LE slow"), WEFT_SKIP_CLANG=1
# (no Clang determinism check), WEFT_CLANG_BUILD_DIR (default build-clang).
# Exits non-zero when anything failed; the last line is always a one-line summary.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
build_dir=${WEFT_BUILD_DIR:-build}
asan_dir=${WEFT_ASAN_BUILD_DIR:-build-asan}
jobs=$(nproc 2>/dev/null || echo 2)
read -r -a ctest_extra <<<"${WEFT_CTEST_ARGS:-}"
start=$SECONDS
results=()  # one entry per configuration: "name: outcome"
failed=0

# Configures, builds and tests one configuration; records its outcome in `results`.
run_config() {  # name dir cmake-args...
  local name=$1 dir=$2
  shift 2
  mkdir -p "$dir"
  echo "== $name: configure ($dir)"
  if ! cmake -S "$root" -B "$dir" -G Ninja "$@" >"$dir/configure.log" 2>&1; then
    cat "$dir/configure.log"
    results+=("$name: configure FAILED")
    return 1
  fi
  echo "== $name: build"
  if ! ninja -C "$dir" -j "$jobs" >"$dir/build.log" 2>&1; then
    grep -E -A5 'error|FAILED' "$dir/build.log" | head -n 80
    results+=("$name: build FAILED")
    return 1
  fi
  local warnings
  warnings=$(grep -c 'warning:' "$dir/build.log" || true)
  [[ "$warnings" == 0 ]] || echo "   $warnings compiler warning(s), see $dir/build.log"
  echo "== $name: ctest"
  # Passing tests are kept in $dir/ctest.log; failures, their output and the totals are shown.
  { (cd "$dir" && ctest --output-on-failure -j "$jobs" "${ctest_extra[@]}") 2>&1; echo $? >"$dir/ctest.rc"; } |
    tee "$dir/ctest.log" | grep -E -v '^ +Start +[0-9]+: |Test +#[0-9]+: .* Passed +[0-9.]+ sec' || true
  # ctest ends with "100% tests passed, 0 tests failed out of N" or "... K tests failed out of N".
  local total bad
  total=$(sed -n 's/.*tests failed out of \([0-9][0-9]*\).*/\1/p' "$dir/ctest.log" | tail -n1)
  bad=$(sed -n 's/.* \([0-9][0-9]*\) tests failed out of .*/\1/p' "$dir/ctest.log" | tail -n1)
  if [[ "$(cat "$dir/ctest.rc")" != 0 ]]; then
    results+=("$name: ${bad:-?} of ${total:-?} tests FAILED")
    return 1
  fi
  results+=("$name: ${total:-0} tests passed")
}

run_config release "$build_dir" -DCMAKE_BUILD_TYPE=Release -DWEFT_SANITIZE=OFF || failed=1

# The tests configure, build and pass without the tools (they need the runtime, cook and lib/ only;
# those that need a tool are left out): a few minutes, the tools and samples are not built.
if [[ -z "${WEFT_SKIP_NOTOOLS:-}" ]]; then
  notools_start=$SECONDS
  run_config tools-off "${WEFT_NOTOOLS_BUILD_DIR:-build-notools}" -DCMAKE_BUILD_TYPE=Release -DWEFT_SANITIZE=OFF \
    -DWEFT_BUILD_TOOLS=OFF || failed=1
  results[-1]="${results[-1]} ($((SECONDS - notools_start))s)"
fi

if [[ -z "${WEFT_SKIP_ASAN:-}" ]]; then
  export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=0:halt_on_error=1:detect_stack_use_after_return=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
  run_config asan "$asan_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWEFT_SANITIZE=ON || failed=1
fi

# Clang, Release, renderer off: the determinism hashes (tests/determinism.txt) from a second
# compiler, and weft-sim --gltf built without OpenGL. Only what those tests need is built (the
# runtime, cook, the tools that bake the sample skirt, weft-sim).
if [[ -z "${WEFT_SKIP_CLANG:-}" ]]; then
  if command -v clang++ >/dev/null; then
    clang_dir=${WEFT_CLANG_BUILD_DIR:-build-clang}
    mkdir -p "$clang_dir"
    echo "== clang: configure, build and run the determinism hashes and the glTF export ($clang_dir)"
    if CC=clang CXX=clang++ cmake -S "$root" -B "$clang_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DWEFT_RENDER=OFF \
         >"$clang_dir/configure.log" 2>&1 &&
       ninja -C "$clang_dir" -j "$jobs" weft_determinism_tests weft-sim weft_gltf_export_tests >"$clang_dir/build.log" 2>&1 &&
       (cd "$clang_dir" && ctest --output-on-failure --no-tests=error -R 'committed value|gltf|glTF'); then
      results+=("clang: determinism hashes as committed, --gltf without the renderer")
    else
      grep -E -A5 'error|FAILED' "$clang_dir/configure.log" "$clang_dir/build.log" 2>/dev/null | head -n 40 || true
      results+=("clang: determinism FAILED")
      failed=1
    fi
  else
    results+=("clang: skipped (no clang++)")
  fi
fi

if [[ -z "${WEFT_SKIP_FUZZ:-}" ]]; then
  if command -v clang++ >/dev/null; then
    fuzz_seconds=${WEFT_FUZZ_SECONDS:-30}
    if bash "$root/scripts/fuzz.sh" "$fuzz_seconds"; then
      results+=("fuzz: no crash in ${fuzz_seconds}s per harness")
    else
      results+=("fuzz: FAILED")
      failed=1
    fi
  else
    results+=("fuzz: skipped (no clang++)")
  fi
fi

summary=$(printf '%s; ' "${results[@]}")
echo "test.sh: $([[ $failed == 0 ]] && echo PASS || echo FAIL) (${summary%; }) in $((SECONDS - start))s"
exit "$failed"
