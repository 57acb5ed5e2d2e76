#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Measurement files as devices export them, through the programs: the
# warning for joint readings beyond the limits (and --strict_limits), the
# note for columns a device adds (and --columns_strict), millimetres and the
# wide motion-capture form giving the same evaluation as the SI long form.
# Warnings and notes go to stdout; an error is one line on stderr, status 1.
#
# The example file of each device family in docs/formats.md is read as
# written there.
#
#   tests/measurement_files_cli_test.sh <build/apps dir> <data dir> <docs dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
docs="$(cd "$3" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

# 40 poses of the built-in PUMA, 1 mm noise.
"$apps/activecal_select" --algorithm=random --random_designs=20 \
  --num_poses=40 --certificate=false --poses_csv=poses.csv >/dev/null &&
  "$apps/activecal_simulate" --poses_csv=poses.csv --noise_m=0.001 --seed=4 \
    --out=m.csv >/dev/null || { fail "simulate"; exit 1; }
head -1 m.csv | grep -q '^type,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m$' ||
  fail "simulated header"

# --- Joint readings beyond the limits (joint 6: [-176, 356] deg). ---
# Line 3: q6 1 deg above its upper limit; line 5: 0.5 deg.
awk -F, -v OFS=, 'NR==3{$7=sprintf("%.17g", 357*atan2(0,-1)/180)} NR==5{$7=sprintf("%.17g", 356.5*atan2(0,-1)/180)} {print}' \
  m.csv >beyond.csv
expect_ok "readings within the tolerance: one warning" \
  "activecal_evaluate: warning: beyond.csv: 2 of 40 rows have joint readings beyond the joint limits, accepted within the tolerance (5 deg, 10 mm; strict limits refuse them): q6_rad (joint 6 (L6)) up to 0.0174533 rad above its upper limit 6.21337 rad in 2 rows (first: line 3)" \
  activecal_evaluate --measurements=beyond.csv
[ "$(grep -c warning out.txt)" -eq 1 ] && ok "one warning line per file" ||
  fail "one warning line per file"
expect_ok "identify warns the same" "activecal_identify: warning: beyond.csv: 2 of 40 rows" \
  activecal_identify --measurements=beyond.csv
expect_fail "--strict_limits" \
  "--measurements: beyond.csv:3: q6_rad: 6.23083 rad is 0.0174533 rad beyond joint 6 (L6)'s range [-3.07178, 6.21337] rad (strict limits: no reading may lie outside the range)" \
  activecal_evaluate --measurements=beyond.csv --strict_limits
expect_fail "--strict_limits in identify" "beyond.csv:3: q6_rad:" \
  activecal_identify --measurements=beyond.csv --strict_limits
awk -F, -v OFS=, 'NR==4{$7=sprintf("%.17g", 362*atan2(0,-1)/180)} {print}' m.csv >far.csv
expect_fail "reading beyond the tolerance" \
  "--measurements: far.csv:4: q6_rad: 6.31809 rad is 0.10472 rad beyond joint 6 (L6)'s range [-3.07178, 6.21337] rad, more than the tolerance of 0.0872665 rad for joint readings (wrong units, or a file of another robot?)" \
  activecal_evaluate --measurements=far.csv

# --- Columns a device adds. ---
awk -F, -v OFS=, 'NR==1{print $0, "temperature_C", "target"; next} {print $0, 20 + NR / 10, "P" NR}' \
  m.csv >extra.csv
expect_ok "device columns: one note" \
  "activecal_evaluate: note: extra.csv: ignored 2 columns activecal does not read: temperature_C, target" \
  activecal_evaluate --measurements=extra.csv
expect_fail "--columns_strict" \
  "--measurements: extra.csv:1: header: columns 'temperature_C', 'target' activecal does not read (strict columns: every column must be one activecal reads)" \
  activecal_evaluate --measurements=extra.csv --columns_strict
awk -F, -v OFS=, 'NR==1{print $0, "distance_m"; next} {print $0, (NR == 6 ? 0.5 : "")}' \
  m.csv >shifted.csv
expect_fail "a known column the row does not use" \
  "--measurements: shifted.csv:6: distance_m: a position measurement has no such value; leave it empty" \
  activecal_evaluate --measurements=shifted.csv --columns_strict

# --- Millimetres, degrees and the wide mocap form: the same evaluation. ---
awk -F, -v OFS=, 'NR==1{for(j=2;j<=7;j++) sub(/_rad$/, "_deg", $j); $8="x_mm"; $9="y_mm"; $10="z_mm"; print; next}
  {for(j=2;j<=7;j++) $j=sprintf("%.17g", $j*180/atan2(0,-1)); for(j=8;j<=10;j++) $j=sprintf("%.17g", $j*1000); print}' \
  m.csv >mm.csv
# Wide form: no type column, the one marker as x1_m, y1_m, z1_m.
awk -F, -v OFS=, 'NR==1{$8="x1_m"; $9="y1_m"; $10="z1_m"} {$1=""; sub(/^,/, ""); print}' \
  m.csv >wide.csv
for f in m mm wide; do
  "$apps/activecal_evaluate" --measurements=$f.csv --json_out=$f.json >$f.txt 2>&1 ||
    { fail "evaluate $f.csv"; cat $f.txt; }
done
python3 - <<'EOF' && ok "m, mm+deg and wide files evaluate alike" || fail "m, mm+deg and wide files evaluate alike"
import json
r = {f: json.load(open(f + ".json")) for f in ["m", "mm", "wide"]}
for f in ["mm", "wide"]:
    assert r[f]["num_measurements"] == 40, r[f]["num_measurements"]
    for k in ["rmse_m", "mean_m", "max_m"]:
        assert abs(r[f][k] - r["m"][k]) < 1e-12, (f, k, r[f][k], r["m"][k])
    for a, b in zip(r[f]["errors"], r["m"]["errors"]):
        assert max(abs(x - y) for x, y in zip(a["error_xyz_m"], b["error_xyz_m"])) < 1e-12
EOF
# A marker not seen (empty cells) is skipped and noted.
awk -F, -v OFS=, 'NR==7{$7=""; $8=""; $9=""} {print}' wide.csv >occluded.csv
expect_ok "a marker not seen" \
  "activecal_evaluate: note: occluded.csv: 1 marker position left empty (not seen) skipped: marker 1 in 1 row" \
  activecal_evaluate --measurements=occluded.csv --json_out=occluded.json
python3 -c "import json; assert json.load(open('occluded.json'))['num_measurements'] == 39" &&
  ok "occluded row skipped" || fail "occluded row skipped"

# A Windows export of the same: byte order mark, CRLF, quoted header and
# target names, the occluded marker's cells empty at the end of its row.
awk -F, -v OFS=, 'NR==1{printf "\xef\xbb\xbf\"target\","; for(i=1;i<=NF;i++) printf "\"%s\"%s", $i, (i<NF ? "," : "\r\n"); next}
  {printf "\"P%d, north\",%s\r\n", NR, $0}' occluded.csv >windows.csv
expect_ok "a Windows export (BOM, CRLF, quotes, empty last cells)" \
  "activecal_evaluate: note: windows.csv: ignored 1 column activecal does not read: target" \
  activecal_evaluate --measurements=windows.csv --json_out=windows.json
python3 - <<'PY' && ok "the Windows export evaluates as the plain file" || fail "the Windows export evaluates as the plain file"
import json
a, b = json.load(open("windows.json")), json.load(open("occluded.json"))
assert a["num_measurements"] == 39 and a["rmse_m"] == b["rmse_m"], (a["num_measurements"], a["rmse_m"], b["rmse_m"])
PY

# Mocap software ending every line with ',': an empty column, not a note.
sed 's/$/,/' occluded.csv >trailing.csv
"$apps/activecal_evaluate" --measurements=trailing.csv --json_out=trailing.json >out.txt 2>err.txt &&
  ! grep -q "ignored" out.txt &&
  python3 -c "import json; assert json.load(open('trailing.json'))['rmse_m'] == json.load(open('occluded.json'))['rmse_m']" &&
  ok "a ',' ending every line" || { fail "a ',' ending every line"; cat err.txt out.txt; }

# --- Bad input: one line, status 1. ---
awk -F, -v OFS=, 'NR==9{$9="1e200"} {print}' mm.csv >huge.csv
expect_fail "a length beyond any device's reach" \
  "--measurements: huge.csv:9: y_mm: 1e+200 mm is more than 1000 km: a corrupt cell or a wrong unit" \
  activecal_evaluate --measurements=huge.csv
tr ',' ';' <m.csv >semicolons.csv
expect_fail "semicolons" \
  "--measurements: semicolons.csv:1: header: the fields are separated by ';', not ','" \
  activecal_evaluate --measurements=semicolons.csv
sed '1s/x_m,y_m,z_m/x_mm,y_m,z_m/' m.csv >mixed.csv
expect_fail "metres and millimetres mixed" \
  "mixed.csv:1: header: the header has y_m,z_m but not x_m (the measured point)" \
  activecal_evaluate --measurements=mixed.csv
awk -F, -v OFS=, 'NR==1{print $0, "u95_mm"; next} {print $0, (NR == 8 ? -0.1 : 0.05)}' m.csv >u95.csv
expect_fail "negative U95" "u95.csv:8: u95_mm: a standard deviation must be > 0, got -0.1" \
  activecal_evaluate --measurements=u95.csv

# --- The example files of docs/formats.md, as written there. ---
# example <section title>: the first indented block after the title.
example() {
  awk -v title="### $1" '$0 == title {on = 1; next}
    on && /^### / {exit}
    on && /^    / {sub(/^    /, ""); print; found = 1; next}
    on && found {exit}' "$docs/formats.md"
}
example "Laser tracker" >tracker.csv
[ "$(wc -l <tracker.csv)" -eq 3 ] && ok "tracker example has 3 lines" ||
  fail "tracker example has 3 lines"
expect_ok "laser tracker example"   "activecal_evaluate: note: tracker.csv: ignored 2 columns activecal does not read: target, temperature_C"   activecal_evaluate --measurements=tracker.csv --json_out=tracker.json
python3 -c "import json; r = json.load(open('tracker.json')); assert r['num_position_measurements'] == 2, r" &&
  ok "tracker example: 2 positions" || fail "tracker example: 2 positions"
example "Camera and calibration board" >camera.csv
[ "$(wc -l <camera.csv)" -eq 3 ] && ok "camera example has 3 lines" ||
  fail "camera example has 3 lines"
expect_ok "camera example"   "activecal_evaluate: note: camera.csv: ignored 2 columns activecal does not read: image, reprojection_rms_px"   activecal_evaluate --robot="$data/ur10e.urdf" --tip_link=tool0   --measurements=camera.csv --json_out=camera.json
python3 -c "import json; r = json.load(open('camera.json')); assert r['orientation_rad']['count'] == 2, r" &&
  ok "camera example: 2 poses" || fail "camera example: 2 poses"
example "Motion capture (several markers per row)" >mocap.csv
[ "$(wc -l <mocap.csv)" -eq 3 ] && ok "mocap example has 3 lines" ||
  fail "mocap example has 3 lines"
# A torso and two arm joints, two markers on the last link.
cat >torso.urdf <<'URDF'
<robot name="torso_arm">
  <link name="base"/><link name="torso"/><link name="arm1"/><link name="arm2"/>
  <joint name="torso_lift_joint" type="prismatic"><parent link="base"/><child link="torso"/>
    <origin xyz="0 0 0.8"/><axis xyz="0 0 1"/><limit lower="0" upper="0.35" effort="1" velocity="1"/></joint>
  <joint name="arm_1_joint" type="revolute"><parent link="torso"/><child link="arm1"/>
    <origin xyz="0.1 0 0.2"/><axis xyz="0 0 1"/><limit lower="-2.7" upper="2.7" effort="1" velocity="1"/></joint>
  <joint name="arm_2_joint" type="revolute"><parent link="arm1"/><child link="arm2"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
</robot>
URDF
printf 'markers:\n  - {name: m1, xyz: [0.2, 0, 0]}\n  - {name: m2, xyz: [0.2, 0.05, 0]}\n' >markers.yaml
expect_ok "mocap example: the torso reading beyond its limit"   "activecal_evaluate: warning: mocap.csv: 1 of 2 rows have joint readings beyond the joint limits, accepted within the tolerance (5 deg, 10 mm; strict limits refuse them): torso_lift_joint_m (joint 1 (torso_lift_joint)) up to 0.00018 m above its upper limit 0.35 m in 1 row (first: line 2)" \
  activecal_evaluate --robot=torso.urdf --frames=markers.yaml \
  --measurements=mocap.csv --json_out=mocap.json
grep -qF "activecal_evaluate: note: mocap.csv: 1 marker position left empty (not seen) skipped: marker 1 in 1 row" out.txt &&
  grep -qF "activecal_evaluate: note: mocap.csv: ignored 2 columns activecal does not read: frame, time_s" out.txt &&
  ok "mocap example: notes" || { fail "mocap example: notes"; cat out.txt; }
python3 -c "import json; r = json.load(open('mocap.json')); assert r['num_position_measurements'] == 3, r" &&
  ok "mocap example: 3 marker positions" || fail "mocap example: 3 marker positions"

cli_end
