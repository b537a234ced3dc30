#!/usr/bin/env bash
# Runs the libFuzzer targets of the `fuzz` preset (docs/reliability.md, "Fuzzing").
#
#   bash tests/fuzz/run.sh [--build DIR] [--seconds N | --runs M] [--jobs J] [TARGET...]
#
# TARGET: asset_reader, scene_reader, mesh_import, nanovdb_grid (default: all, one after another).
# --seconds N fuzzes each target for N seconds (default 60, what CI runs); --runs M until M
# executions instead. --jobs J runs J fuzzing processes per target (libFuzzer -fork=J).
# Each target works in DIR/fuzz-work/<target>/: corpus/ (seeded from tests/fuzz/corpus/<target>,
# grows across runs), findings/ (crash-, timeout-, oom-, leak- files) and fuzz.log. The line
# "fuzz <target>: N executions" reports libFuzzer's own count. Exit 1 if any target left a
# finding: reproduce it with DIR/bin/fuzz_<target> FILE, fix it, and add it to
# tests/fuzz/regressions/<target>/ (the ctest replay runs every file there).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build/fuzz
seconds=60
runs=0
jobs=1
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --seconds) seconds=$2; runs=0; shift 2 ;;
    --runs) runs=$2; seconds=0; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    asset_reader|scene_reader|mesh_import|nanovdb_grid) targets+=("$1"); shift ;;
    *) echo "usage: bash tests/fuzz/run.sh [--build DIR] [--seconds N | --runs M] [--jobs J] [asset_reader|scene_reader|mesh_import|nanovdb_grid...]" >&2; exit 2 ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(asset_reader scene_reader mesh_import nanovdb_grid)

# The sanitizers' reports are what a finding is; keep them symbolized and fatal.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/fuzz/lsan-suppressions.txt}

failed=0
for target in "${targets[@]}"; do
  exe=$build/bin/fuzz_$target
  [ -x "$exe" ] || { echo "fuzz: no $exe (cmake --preset fuzz && cmake --build --preset fuzz)" >&2; exit 2; }
  work=$build/fuzz-work/$target
  mkdir -p "$work/corpus" "$work/findings"
  limit=(-max_total_time="$seconds")
  [ "$runs" -gt 0 ] && limit=(-runs="$runs")
  # -timeout: no input of these readers may take 10 s. -rss_limit_mb / -malloc_limit_mb: a
  # reader that asks for more than 2 GiB (or 1 GiB at once) on an input of a few kB is a finding.
  flags=(-timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 -print_final_stats=1
         -artifact_prefix="$work/findings/" "${limit[@]}")
  fork=0
  [ "$jobs" -gt 1 ] && fork=$jobs
  if [ "$target" = mesh_import ]; then
    # The mesh target runs assimp in this process; bigger inputs only slow it down. assimp
    # crashes on some malformed files (sluice-bake reads them in a child process, where a crash
    # is an error): -fork keeps fuzzing past them, and they are sorted out below.
    flags+=(-max_len=16384 -ignore_crashes=1)
    fork=$jobs
  fi
  [ "$fork" -gt 0 ] && flags+=(-fork="$fork")
  echo "fuzz $target: $exe ${flags[*]}"
  set +e
  "$exe" "${flags[@]}" "$work/corpus" "tests/fuzz/corpus/$target" >"$work/fuzz.log" 2>&1
  status=$?
  set -e
  # Executions: the final statistics (one process), or the fork driver's last status line.
  if [ "$fork" -gt 0 ]; then
    execs=$( (grep -E '^#[0-9]+:' "$work/fuzz.log" || true) | tail -n 1 | sed -E 's/^#([0-9]+):.*/\1/')
  else
    execs=$( (grep -h '^stat::number_of_executed_units:' "$work/fuzz.log" || true) | awk '{print $2}')
  fi
  execs=${execs:-0}
  # A mesh crash whose faulting frame is inside libassimp is assimp's own bug: contained by
  # sluice-bake's isolated import (tests/reliability/assimp-crashes/ holds each one found, and
  # HostileMesh.CrashesInsideAssimpExitTwo bakes them). Kept apart; anything else is a finding.
  if [ "$target" = mesh_import ]; then
    mkdir -p "$work/assimp-crashes"
    for f in "$work"/findings/crash-*; do
      [ -e "$f" ] || continue
      # The first frame outside libc, libstdc++ and the fuzzer and sanitizer runtimes.
      frame=$(timeout -s KILL 60 "$exe" "$f" 2>&1 | grep -E '^ +#[0-9]+ ' |
              grep -v -E 'libc\.so|libstdc\+\+|libgcc|/fuzz_[a-z_]+\+0x' | head -n 1 || true)
      if echo "$frame" | grep -q 'libassimp\.so'; then
        mv "$f" "$work/assimp-crashes/"
        echo "fuzz $target: $(basename "$f") crashes inside assimp (contained by the isolated import): $work/assimp-crashes/"
      fi
    done
  fi
  findings=$(find "$work/findings" -type f | wc -l)
  echo "fuzz $target: $execs executions, exit $status, $findings findings in $work/findings (log $work/fuzz.log)"
  if [ "$status" -ne 0 ] || [ "$findings" -gt 0 ]; then
    failed=1
    grep -E 'ERROR: |runtime error|fuzz invariant broken|SUMMARY' "$work/fuzz.log" | head -n 20 || true
  fi
done
rm -rf /dev/shm/sluice-fuzz-mesh-* 2>/dev/null || true
# SLUICE_FUZZ_FINDINGS_FAIL=0 (what CI sets): report findings loudly but exit 0, so a short
# random run that happens upon a new input does not block unrelated work; the regression inputs
# replayed by ctest are the gate. Build failures still fail (setup.sh stops before this script).
if [ "$failed" -ne 0 ] && [ "${SLUICE_FUZZ_FINDINGS_FAIL:-1}" = 0 ]; then
  echo "fuzz: FINDINGS LEFT above (not failing: SLUICE_FUZZ_FINDINGS_FAIL=0); reproduce, fix, add to tests/fuzz/regressions/"
  exit 0
fi
exit "$failed"
