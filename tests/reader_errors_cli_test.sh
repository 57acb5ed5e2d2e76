#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Every reader's error in one form (docs/bad_input.md): after the program
# and the flag, "<file>:<line>: <field>: <what>" (the YAML readers add the
# column: "<file>:<line>:<column>: <field>: <what>"). One table: each row a
# bad file, the line the error must name, and the program reading it; the
# line must match ^<file>:<line>(:<column>)?: <field>: .+$ with that file
# and line, status 1, one line on stderr.
#
#   tests/reader_errors_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

puma=(--robot="$data/puma560.yaml")
j6="q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad"
printf '%s\n0,0,0,0,0,0\n0.1,0.2,0,0,0,0\n0.2,0.1,0.3,0,0,0\n' "$j6" >poses.csv
"$apps/activecal_simulate" "${puma[@]}" --poses_csv=poses.csv --out=m.csv --quiet \
  >/dev/null || fail "simulate a measurements file"

# The bad files.
printf '%s\n0,0,0,0,0,0\n0,abc,0,0,0,0\n' "$j6" >bad_value_poses.csv
printf 'q1_rad,q2_rad,q3_rad,q4_rad,q5_rad\n0,0,0,0,0\n' >five_joints.csv
sed '3s/^position,[^,]*,/position,abc,/' m.csv >bad_value_m.csv
{ head -2 m.csv; echo "position,0,0,0"; } >short_row_m.csv
printf 'x_m,y_m,z_m\n0.5,0.1,0.2\n0.5,nan,0.2\n' >nan_targets.csv
# ISO 9283 cycles: two labels of one cycle each.
{ echo "$(head -1 m.csv),pose,commanded_x_m,commanded_y_m,commanded_z_m"
  sed -n 2p m.csv | sed 's/$/,P1,0.1,0.2,0.3/'
  sed -n 3p m.csv | sed 's/$/,P2,0.1,0.2,0.3/'; } >one_cycle.csv
{ echo "$(head -1 m.csv),pose,commanded_x_m,commanded_y_m,commanded_z_m"
  sed -n 2p m.csv | sed 's/$/,P1,0.1,0.2,0.3/'
  sed -n 3p m.csv | sed 's/$/,,0.1,0.2,0.3/'; } >empty_label.csv
sed 's/^  alpha: 0.1572$/  alpha: abc/' "$data/puma560.yaml" >bad_robot.yaml
printf 'distances:\n  - {from: a, to: b, distance_m: abc}\n' >bad_points.yaml
printf 'angle_unit: furlong\n' >bad_frames.yaml
printf 'delimiter: xx\n' >bad_map.yaml
printf 'clearance_m: abc\n' >bad_cell.yaml
printf 'joints: 3\n' >bad_controller.yaml

# file | line | program and arguments
cases=(
  "bad_value_poses.csv|3|activecal_simulate ${puma[*]} --poses_csv=bad_value_poses.csv --out=o1.csv"
  "five_joints.csv|1|activecal_simulate ${puma[*]} --poses_csv=five_joints.csv --out=o2.csv"
  "bad_value_m.csv|3|activecal_evaluate ${puma[*]} --measurements=bad_value_m.csv"
  "short_row_m.csv|3|activecal_identify ${puma[*]} --measurements=short_row_m.csv"
  "nan_targets.csv|3|activecal_compensate ${puma[*]} --targets_csv=nan_targets.csv --out=o3.csv"
  "one_cycle.csv|2|activecal_evaluate ${puma[*]} --measurements=one_cycle.csv --iso9283"
  "empty_label.csv|3|activecal_evaluate ${puma[*]} --measurements=empty_label.csv --iso9283"
  "bad_robot.yaml|19|activecal_evaluate --robot=bad_robot.yaml --measurements=m.csv"
  "bad_points.yaml|2|activecal_identify ${puma[*]} --measurements=m.csv --points=bad_points.yaml"
  "bad_frames.yaml|1|activecal_evaluate --robot=$data/ur10.urdf --tip_link=tool0 --frames=bad_frames.yaml --measurements=m.csv"
  "bad_map.yaml|1|activecal_evaluate ${puma[*]} --column_map=bad_map.yaml --measurements=m.csv"
  "bad_cell.yaml|1|activecal_simulate ${puma[*]} --cell=bad_cell.yaml --poses_csv=poses.csv --out=o4.csv"
  "bad_controller.yaml|1|activecal_select ${puma[*]} --controller=bad_controller.yaml --program_out=o5.src --num_poses=5"
)
for c in "${cases[@]}"; do
  IFS='|' read -r file line cmd <<<"$c"
  read -r -a argv <<<"$cmd"
  "$apps/${argv[0]}" "${argv[@]:1}" >out.txt 2>err.txt
  status=$?
  # After "<program>: error: " and the flag(s) ("--robot: ", "--iso9283: ").
  msg=$(sed -E 's/^activecal_[a-z_]+: (error: )?((--[a-z0-9_]+)( and --[a-z0-9_]+)?: )*//' err.txt)
  esc=$(printf '%s' "$file" | sed 's/\./\\./g')
  if [ "$status" -eq 1 ] && [ "$(wc -l <err.txt)" -eq 1 ] &&
    printf '%s\n' "$msg" | grep -Eq "^$esc:$line(:[0-9]+)?: [A-Za-z0-9_.]+(\[[0-9]+\][A-Za-z0-9_.]*)*: .+\$"; then
    ok "$file: $msg"
  else
    fail "$file (status $status, want $file:$line: <field>: ...): $(cat err.txt)"
  fi
done
for f in o1.csv o2.csv o3.csv o4.csv o5.src; do
  [ -e "$f" ] && fail "$f written" || ok "$f not written"
done

cli_end
