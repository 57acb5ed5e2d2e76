#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# A German-locale tracker export (';' separators, decimal commas, mm, joints
# in degrees under the controller's names, orientation as intrinsic X-Y-Z
# Euler angles in degrees) read by activecal_identify through --column_map:
# the same calibration as the file converted to activecal's form; bad maps
# are one line on stderr; the orientation hint is printed for a wrong
# convention and not for the right one.
#
#   tests/column_map_cli_test.sh <build/apps dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

# 40 poses of the built-in PUMA, measured in position and orientation.
"$apps/activecal_select" --algorithm=random --random_designs=20 \
  --num_poses=40 --certificate=false --poses_csv=poses.csv >/dev/null &&
  "$apps/activecal_simulate" --poses_csv=poses.csv --type=pose --noise_m=0.0001 \
    --rotation_noise_rad=0.0001 --seed=4 --out=m.csv >/dev/null ||
  { fail "simulate"; exit 1; }

# The export, written as the tracker's PC would (Python's math only), and
# the same numbers converted by hand to activecal's columns.
python3 - <<'PY' || { fail "write the export"; exit 1; }
import csv, math
rows = list(csv.DictReader(open("m.csv")))
def rotation(v):  # rotation vector -> matrix (Rodrigues)
    t = math.sqrt(sum(x * x for x in v))
    if t == 0: return [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    k = [x / t for x in v]; c, s = math.cos(t), math.sin(t)
    return [[(c if i == j else 0) + k[i] * k[j] * (1 - c) + (0 if i == j else s * (-1 if (j - i) % 3 == 1 else 1) * k[3 - i - j])
             for j in range(3)] for i in range(3)]
def intrinsic_xyz_deg(R):  # R = Rx(a) Ry(b) Rz(c)
    b = math.asin(max(-1.0, min(1.0, R[0][2])))
    a = math.atan2(-R[1][2], R[2][2]); c = math.atan2(-R[0][1], R[0][0])
    return [math.degrees(x) for x in (a, b, c)]
def comma(x): return repr(x).replace(".", ",")
names = ["shoulder", "upper_arm", "elbow", "wrist_1", "wrist_2", "wrist_3"]
with open("leica.csv", "w") as f, open("mm.csv", "w") as g:
    f.write("Punkt;" + ";".join(names) + ";measurement_x;measurement_y;measurement_z;"
            "measurement_rx;measurement_ry;measurement_rz;Temperatur\r\n")
    g.write("q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm\n")
    for n, r in enumerate(rows):
        q = [math.degrees(float(r["q%d_rad" % (j + 1)])) for j in range(6)]
        p = [float(r[a + "_m"]) * 1000 for a in "xyz"]
        e = intrinsic_xyz_deg(rotation([float(r[a]) for a in ("rx_rad", "ry_rad", "rz_rad")]))
        f.write(";".join(["P%d" % n] + [comma(x) for x in q + p + e] + ["21,5"]) + "\r\n")
        g.write(",".join(repr(x) for x in q + p) + "\n")
PY
cat >leica.yaml <<'YAML'
# A Leica tracker export from a German-locale PC.
delimiter: ";"
decimal: ","
columns:
  q1_deg: shoulder
  q2_deg: upper_arm
  q3_deg: elbow
  q4_deg: wrist_1
  q5_deg: wrist_2
  q6_deg: wrist_3
  x_mm: measurement_x
  y_mm: measurement_y
  z_mm: measurement_z
orientation: {convention: XYZ, intrinsic: true, unit: deg, columns: [measurement_rx, measurement_ry, measurement_rz]}
YAML

# Through the map: the pose measurements of the export.
if "$apps/activecal_identify" --measurements=leica.csv --column_map=leica.yaml \
    --model_out=mapped.yaml >out.txt 2>err.txt && [ ! -s err.txt ] &&
  grep -q "ignored 2 columns activecal does not read: Punkt, Temperatur" out.txt; then
  ok "identify reads the German export through the map"
else
  fail "identify reads the German export through the map"; cat err.txt out.txt
fi
if grep -q "check the orientation convention" out.txt; then
  fail "no orientation hint for the right convention"; cat out.txt
else
  ok "no orientation hint for the right convention"
fi

# Positions only: the map and the hand conversion give the same fit, byte
# for byte (the orientation columns left unmapped are ignored).
sed '/^orientation:/d' leica.yaml >positions.yaml
"$apps/activecal_identify" --measurements=leica.csv --column_map=positions.yaml \
  --model_out=positions.yaml.out >/dev/null 2>err.txt &&
  "$apps/activecal_identify" --measurements=mm.csv --model_out=mm.yaml.out \
    >/dev/null 2>>err.txt || { fail "position fits"; cat err.txt; }
if cmp -s <(tail -n +2 positions.yaml.out) <(tail -n +2 mm.yaml.out); then
  ok "the map's fit is the hand conversion's, byte for byte"
else
  fail "the map's fit is the hand conversion's, byte for byte"
  diff positions.yaml.out mm.yaml.out | head
fi

# The wrong convention (extrinsic instead of intrinsic): the hint.
sed 's/intrinsic: true/intrinsic: false/' leica.yaml >wrong.yaml
"$apps/activecal_identify" --measurements=leica.csv --column_map=wrong.yaml \
  >out.txt 2>err.txt
if grep -q "check the orientation convention (measurement_rx, measurement_ry, measurement_rz as extrinsic XYZ, deg (wrong.yaml))" out.txt; then
  ok "the orientation hint for the wrong convention: $(grep 'check the orientation' out.txt)"
else
  fail "the orientation hint for the wrong convention"; cat err.txt out.txt
fi

# Bad maps and files: one line on stderr, status 1, nothing written.
printf 'delimiter: ";"\ndecimal: ","\ncolumns: {x_cm: measurement_x}\n' >bad1.yaml
expect_fail "unknown activecal column" \
  "--measurements: bad1.yaml:3: columns: x_cm: not an activecal column" \
  activecal_identify --measurements=leica.csv --column_map=bad1.yaml --model_out=x.yaml
printf 'delimiter: ";"\ncolumns: {x_mm: messung_x}\n' >bad2.yaml
expect_fail "mapped column not in the header" \
  "--measurements: leica.csv:1: messung_x: not in the header (column map bad2.yaml:2: columns: x_mm)" \
  activecal_identify --measurements=leica.csv --column_map=bad2.yaml --model_out=x.yaml
printf 'orientation: {convention: XYZ, intrinsic: true, unit: deg, columns: [a, b]}\n' >bad3.yaml
expect_fail "orientation with two columns" \
  "--column_map: bad3.yaml:1:69: orientation.columns: expected 3 columns" \
  activecal_identify --measurements=leica.csv --column_map=bad3.yaml --model_out=x.yaml
printf 'orientation: {convention: XYY, intrinsic: true, unit: deg, columns: [a, b, c]}\n' >bad4.yaml
expect_fail "unknown convention" \
  "--column_map: bad4.yaml:1:27: orientation.convention: unknown convention 'XYY'" \
  activecal_evaluate --measurements=leica.csv --column_map=bad4.yaml
printf 'delimiter: ","\ndecimal: ","\n' >bad5.yaml
expect_fail "decimal comma with comma delimiter" \
  "--column_map: bad5.yaml:2:10: decimal: ',' with ',' as the delimiter cannot be read" \
  activecal_identify --measurements=leica.csv --column_map=bad5.yaml --model_out=x.yaml
[ -e x.yaml ] && fail "a failed run wrote its model"

# Without the map, the export is refused in one line.
expect_fail "the export without a map" "leica.csv:1" \
  activecal_identify --measurements=leica.csv

cli_end
