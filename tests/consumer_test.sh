#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Installs activecal from the build tree into a temporary prefix, then
# configures, builds and runs tests/consumer against it with
# find_package(activecal), as software that links activecal would.
#
#   tests/consumer_test.sh <activecal build dir> <source dir>
set -euo pipefail
build="$(cd "$1" && pwd)"
src="$(cd "$2" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
# Only public headers are installed: no src/ or internal header.
if find "$work/prefix/include" -name '*internal*' | grep -q .; then
  echo "internal headers were installed"; exit 1
fi
cmake -S "$src/tests/consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" -j 2 >/dev/null
"$work/build/calibrate_my_arm" "$src/data/puma560.yaml" "$work/calibrated.yaml"
grep -q "^name: puma560_sun_hollerbach" "$work/calibrated.yaml"
# The installed programs run too. --help exits with status 1 (gflags) and
# lists the program's flags.
status=0
"$work/prefix/bin/activecal_select" --help >"$work/help.txt" 2>&1 || status=$?
[ "$status" -eq 1 ] || { echo "activecal_select --help: status $status"; exit 1; }
grep -q -- "-algorithm" "$work/help.txt" ||
  { echo "activecal_select --help does not list -algorithm"; exit 1; }
"$work/prefix/bin/activecal_select" --algorithm=greedy --certificate=false \
  --levels=3 >/dev/null
echo "consumer built against the installed package and ran"
