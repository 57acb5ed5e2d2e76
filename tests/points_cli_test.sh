#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Calibration without a tracker end to end: a simulated socket session of a
# 7-axis arm (type=point rows, tests/make_point_measurements.cc) through
# activecal_identify (the base frame held as having no effect, the points'
# coordinates printed and in the JSON with their std; a known distance
# frees one more parameter, the scale) and activecal_evaluate on another
# placement of the block (each point's spread far below the nominal
# model's); bad input: status 1, one line naming the file and line, nothing
# written.
#
#   tests/points_cli_test.sh <build/apps dir> <data dir> <make_point_measurements>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
make="$3"
source "$here/cli_lib.sh"
cli_begin "$@"

robot=(--robot="$data/kuka_iiwa14.urdf" --tip_link=flange)
# Training: 3 sockets x 25 configurations, placements repeatable to 0.02 mm;
# test: the same robot, the block placed elsewhere (socket seed 99).
"$make" "$data/kuka_iiwa14.urdf" flange train.csv train.yaml 3 2e-5 3 25 ||
  { echo "FAIL [make training]"; exit 1; }
"$make" "$data/kuka_iiwa14.urdf" flange test.csv test.yaml 3 2e-5 3 25 99 ||
  { echo "FAIL [make test]"; exit 1; }

# Points only: the base frame (and joint 1's frame) moves with the points.
if "$apps/activecal_identify" "${robot[@]}" --measurements=train.csv \
    --json_out=plain.json --model_out=plain.yaml >plain.txt 2>err.txt; then
  ok "identify points only"
else
  fail "identify points only: $(cat err.txt)"
fi
held_ok=1
for p in B.x B.y B.z B.rx B.ry B.rz joint_a1.offset; do
  grep -qE "^    $p +has no effect on these measurements" plain.txt || held_ok=0
done
[ "$held_ok" = 1 ] && ok "base frame held: no effect" ||
  { fail "base frame held: no effect"; cat plain.txt; }
grep -qE '^point\.hole_2\.z +m +[-0-9.]+ +0\.0000[0-9]+ ' plain.txt &&
  ok "points printed with std" || fail "points printed with std"
python3 - <<'PY' && ok "JSON points" || fail "JSON points"
import json
j = json.load(open("plain.json"))
names = [p["name"] for p in j["points"]]
assert names == ["point.hole_%d.%s" % (k, a) for k in range(3) for a in "xyz"], names
assert all(0 < p["std"] < 1e-4 for p in j["points"]), j["points"]
assert len(j["points_covariance"]) == 9
PY

# A known distance: one parameter more (the scale), a length.
free() { sed -n 's/.*: \([0-9]*\) of [0-9]* parameters identified.*/\1/p' "$1"; }
"$apps/activecal_identify" "${robot[@]}" --measurements=train.csv \
  --points=train.yaml --model_out=cal.yaml >cal.txt 2>err.txt ||
  fail "identify with --points: $(cat err.txt)"
n0=$(free plain.txt); n1=$(free cal.txt)
[ -n "$n0" ] && [ "$n1" = $((n0 + 1)) ] && ok "distance frees the scale ($n0 -> $n1)" ||
  fail "distance frees the scale ($n0 -> $n1)"
freed=$(comm -23 <(sed -n 's/^    \([^ ]*\)  .*/\1/p' plain.txt | sort) \
                 <(sed -n 's/^    \([^ ]*\)  .*/\1/p' cal.txt | sort))
grep -qE "^$freed +m " cal.txt && ok "the freed one is a length ($freed)" ||
  fail "the freed one is a length ($freed)"

# Another placement: the points refitted, the calibrated model's spread
# about each far below the nominal's.
"$apps/activecal_evaluate" --robot=cal.yaml --measurements=test.csv \
  --points=test.yaml --json_out=after.json >after.txt 2>err.txt ||
  fail "evaluate calibrated: $(cat err.txt)"
"$apps/activecal_evaluate" "${robot[@]}" --measurements=test.csv \
  --points=test.yaml --json_out=before.json >before.txt 2>err.txt ||
  fail "evaluate nominal: $(cat err.txt)"
grep -qE '^  point hole_1 \(25 rows, refitted at' after.txt &&
  ok "spread line" || fail "spread line"
python3 - <<'PY' && ok "spread on another placement" || fail "spread on another placement"
import json
a = json.load(open("after.json")); b = json.load(open("before.json"))
assert [p["label"] for p in a["points"]] == ["hole_0", "hole_1", "hole_2"]
for pa, pb in zip(a["points"], b["points"]):
    assert pa["count"] == 25
    # placements repeatable to 0.02 mm per axis: 0.035 mm 3D
    assert pa["rms"] < 1e-4, pa
    assert pb["rms"] > 10 * pa["rms"], (pa, pb)
assert a["distance_m"]["count"] == 2 and a["distance_m"]["max"] < 2e-5, a["distance_m"]
PY
# What is printed is what the JSON holds: per point the mean distance to the
# point's mean (below its RMS), the RMS and the max; the known-distance error.
python3 - <<'PY' && ok "printed spread = JSON" || fail "printed spread = JSON"
import json, re
a = json.load(open("after.json"))
text = open("after.txt").read()
for p in a["points"]:
    m = re.search(r"^  point %s \((\d+) rows, refitted at ([-0-9.]+), ([-0-9.]+), "
                  r"([-0-9.]+) m\): distance to the point's mean ([0-9.]+) mm "
                  r"mean, RMS ([0-9.]+) mm, max ([0-9.]+) mm$" % p["label"],
                  text, re.M)
    assert m, (p["label"], text)
    assert int(m.group(1)) == p["count"]
    for g, c in zip((2, 3, 4), p["coordinates_m"]):
        assert abs(float(m.group(g)) - c) <= 5e-7, (m.group(g), c)
    for g, key in ((5, "mean"), (6, "rms"), (7, "max")):
        assert abs(float(m.group(g)) - p[key] * 1e3) <= 5e-4, (key, m.group(g), p)
    assert 0 < p["mean"] < p["rms"] <= p["max"], p
d = a["distance_m"]
m = re.search(r"distance \(2\): RMS ([0-9.]+) mm, max ([0-9.]+) mm", text)
assert m, text
assert abs(float(m.group(1)) - d["rms"] * 1e3) <= 5e-4, (m.group(1), d)
assert abs(float(m.group(2)) - d["max"] * 1e3) <= 5e-4, (m.group(2), d)
PY

# Bad input: one line, status 1, nothing written.
(cat train.csv; echo "point,lonely,0.1,0.2,0.3,0.4,0.5,0.6,0.7,,,") >one.csv
printf 'distances:\n  - {from: hole_0, to: nowhere, distance_m: 0.05}\n' >nowhere.yaml
printf 'distances:\n  - {from: hole_0, to: hole_1, distance_m: -0.05}\n' >negative.yaml
printf 'distances:\n  - {from: hole_0, to: hole_1, distance_m: 0.05}\nplanes: []\n' >key.yaml
(head -1 train.csv; sed -n 2p train.csv | sed 's/,,,$/,0.1,0.2,0.3/'
 sed -n '3,$p' train.csv) >coordinates.csv
expect_fail "point of one row" "one.csv:77: row: point 'lonely' has one row only" \
  activecal_identify "${robot[@]}" --measurements=one.csv --json_out=o.json
expect_fail "distance to an unknown point" \
  "nowhere.yaml:2: distances[0].to: a known distance to point 'nowhere', which no type=point row" \
  activecal_identify "${robot[@]}" --measurements=train.csv \
  --points=nowhere.yaml --json_out=o.json
expect_fail "negative distance" \
  "negative.yaml:2:5: distances[0].distance_m: must be > 0" \
  activecal_identify "${robot[@]}" --measurements=train.csv \
  --points=negative.yaml --json_out=o.json
expect_fail "unknown key" "key.yaml:3:1: planes: unknown field" \
  activecal_identify "${robot[@]}" --measurements=train.csv \
  --points=key.yaml --json_out=o.json
expect_fail "coordinates on a point row" \
  "coordinates.csv:2: x_m: a point measurement has no such value" \
  activecal_identify "${robot[@]}" --measurements=coordinates.csv \
  --json_out=o.json
expect_fail "cv with points" "model_selection=cv is not supported with fixed-point" \
  activecal_identify "${robot[@]}" --measurements=train.csv \
  --model_selection=cv --json_out=o.json
expect_fail "evaluate: distance to an unknown point" \
  "nowhere.yaml:2: distances[0].to: a known distance to point 'nowhere'" \
  activecal_evaluate --robot=cal.yaml --measurements=test.csv \
  --points=nowhere.yaml --json_out=o.json
expect_fail "evaluate: point of one row" "one.csv:77: row: point 'lonely' has one row only" \
  activecal_evaluate --robot=cal.yaml --measurements=one.csv --json_out=o.json
expect_fail "evaluate: negative distance" \
  "negative.yaml:2:5: distances[0].distance_m: must be > 0" \
  activecal_evaluate --robot=cal.yaml --measurements=test.csv \
  --points=negative.yaml --json_out=o.json
[ ! -e o.json ] && ok "failed runs wrote nothing" || fail "failed runs wrote nothing"

cli_end
