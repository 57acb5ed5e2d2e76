#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Builds the libFuzzer targets with clang (ASan + UBSan), replays the
# regression inputs (what earlier fuzzing found, kept after the fix), then
# fuzzes each parser for a fixed time from its seed corpus.
#
#   tests/fuzz/run.sh [seconds per target, default 30]
#
# FUZZ_BUILD_DIR: a tree already configured with ACTIVECAL_BUILD_FUZZERS=ON
# (./run.sh fuzz and ./run.sh test give build-sanitize/, where the gtests
# run under the same sanitizers); without it, build-fuzz/ is configured here.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
seconds="${1:-30}"
if [ -n "${FUZZ_BUILD_DIR:-}" ]; then
  build="$(cd "$FUZZ_BUILD_DIR" && pwd)"
  grep -q '^ACTIVECAL_BUILD_FUZZERS:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null ||
    { echo "fuzz: $build is not configured with ACTIVECAL_BUILD_FUZZERS=ON" >&2; exit 1; }
else
  build="$root/build-fuzz"
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DACTIVECAL_BUILD_FUZZERS=ON -DACTIVECAL_BUILD_APPS=OFF \
    -DACTIVECAL_BUILD_TESTS=OFF -DACTIVECAL_BUILD_BENCHMARKS=OFF \
    -DACTIVECAL_INSTALL=OFF >/dev/null
fi
targets=(robot_yaml poses_csv measurements_csv urdf frames_yaml targets_csv)
# Only the fuzzers and what they link (core, io): the other libraries are
# checked by the sanitizer suite (./run.sh sanitize). In build-sanitize/
# they are already built.
cmake --build "$build" -j "${JOBS:-$(nproc)}" \
  --target "${targets[@]/#/fuzz_}" >/dev/null
# Leaks inside urdfdom itself are suppressed (lsan.supp says which).
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
for target in "${targets[@]}"; do
  fuzzer="$build/tests/fuzz/fuzz_$target"
  regressions="$here/regressions/$target"
  if [ -d "$regressions" ] && [ -n "$(ls -A "$regressions")" ]; then
    "$fuzzer" "$regressions"/* >/dev/null 2>&1 ||
      { echo "fuzz: a regression input of $target fails again" >&2;
        "$fuzzer" "$regressions"/*; exit 1; }
  fi
  work="$(mktemp -d)"
  cp "$here/corpus/$target"/* "$work/"
  echo "fuzz: $target for $seconds s"
  status=0
  (cd "$work" && "$fuzzer" -max_total_time="$seconds" -max_len=4096 -timeout=10 \
    -print_final_stats=1 . >log.txt 2>&1) || status=$?
  grep -E "^stat::number_of_executed_units|ERROR|SUMMARY" "$work/log.txt" || true
  if [ "$status" -ne 0 ]; then
    mkdir -p "$root/fuzz-findings"
    cp "$work"/crash-* "$work"/timeout-* "$work"/leak-* "$root/fuzz-findings/" 2>/dev/null || true
    tail -40 "$work/log.txt" >&2
    echo "fuzz: $target found a failing input, copied to $root/fuzz-findings; fix it and add it to $regressions" >&2
    rm -rf "$work"
    exit 1
  fi
  rm -rf "$work"
done
echo "fuzz: all parsers ran clean"
