#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# xacro input: --robot=x.urdf.xacro runs `xacro` when it is on PATH (here a
# fake one that logs its call and prints the URDF), passes a failing
# xacro's error on in one line, and without xacro says in one line how to
# run it.
#
#   tests/xacro_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

cp "$data/ur10e.urdf" ur10e.urdf.xacro
mkdir -p fake bad empty
cat >fake/xacro <<SH
#!/bin/sh
echo "\$@" >>"$work/xacro_calls.txt"
exec cat "\$1"
SH
cat >bad/xacro <<'SH'
#!/bin/sh
echo "" >&2
echo "No such file or directory: macro.xacro [Errno 2]" >&2
echo "when processing file: $1" >&2
exit 2
SH
chmod +x fake/xacro bad/xacro

# With xacro: the robot loads and a calibrated URDF is written (from the
# expanded text).
if PATH="$work/fake:$PATH" "$apps/activecal_identify" --robot=ur10e.urdf.xacro \
    --tip_link=tool0 --measurements="$data/figaroh_ur10e/measurements.csv" \
    --rotation_weight=0.1 --model_selection=none --urdf_out=calibrated.urdf >out.txt 2>err.txt &&
  [ ! -s err.txt ] && grep -q "robot 'ur10e': 6 joints" out.txt &&
  [ "$(sort -u xacro_calls.txt)" = "ur10e.urdf.xacro" ] &&
  grep -q '<joint name="shoulder_pan_joint"' calibrated.urdf; then
  ok "a xacro robot through xacro on PATH"
else
  fail "a xacro robot through xacro on PATH"; cat err.txt out.txt xacro_calls.txt
fi

PATH="$work/bad:$PATH"
expect_fail "xacro's error in one line" \
  "--robot: ur10e.urdf.xacro: xacro failed (exit status 2): No such file or directory: macro.xacro [Errno 2]" \
  activecal_identify --robot=ur10e.urdf.xacro --tip_link=tool0
PATH="${PATH#$work/bad:}"
# Without xacro (PATH for the program only: the checks need their tools).
env PATH="$work/empty" "$apps/activecal_identify" --robot=ur10e.urdf.xacro \
  --tip_link=tool0 >out.txt 2>err.txt
status=$?
want='activecal_identify: error: --robot: ur10e.urdf.xacro is a xacro file: run `xacro ur10e.urdf.xacro > robot.urdf` (xacro is not installed)'
if [ "$status" -eq 1 ] && [ "$(cat err.txt)" = "$want" ]; then
  ok "xacro not installed: $(cat err.txt)"
else
  fail "xacro not installed (status $status)"; cat err.txt
fi
expect_fail "a missing xacro file" \
  "--robot: missing.xacro: cannot open" \
  activecal_identify --robot=missing.xacro

cli_end
