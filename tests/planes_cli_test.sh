#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Calibration without a tracker, planes: a simulated touch-probe session of
# a UR10e (type=plane rows, tests/make_plane_measurements.cc) run through
# the commands of docs/user_guide.md "Without a tracker": activecal_identify
# (the base frame held as having no effect, each plane's normal and offset
# printed and in the JSON with their std) and activecal_evaluate on another
# placement of the fixture (each plane refitted, its flatness printed as in
# the JSON and far below the nominal model's); bad input: status 1, one
# line naming the file and line, nothing written.
#
#   tests/planes_cli_test.sh <build/apps dir> <data dir> <make_plane_measurements>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
make="$3"
cli_begin "$1" "$2"

# The guide's files: 3 planes x 30 touches with a 3 mm probe ball (training),
# the fixture moved (placement seed 99), 3 x 12 touches; touches
# repeatable to 0.01 mm.
"$make" "$data/ur10e.urdf" tool0 touches.csv 3 0.003 3 30 4 1e-5 ||
  { echo "FAIL [make training]"; exit 1; }
"$make" "$data/ur10e.urdf" tool0 touches_moved.csv 3 0.003 3 12 99 1e-5 ||
  { echo "FAIL [make test]"; exit 1; }
head -1 touches.csv | grep -q '^type,plane,probe_radius_m,' &&
  ok "file columns" || fail "file columns: $(head -1 touches.csv)"

# --- the commands of docs/user_guide.md "Without a tracker" ---
robot=(--robot="$data/ur10e.urdf" --tip_link=tool0)
if "$apps/activecal_identify" "${robot[@]}" --measurements=touches.csv \
    --model_out=cal.yaml --json_out=cal.json >cal.txt 2>err.txt; then
  ok "identify planes"
else
  fail "identify planes: $(cat err.txt)"
fi
"$apps/activecal_evaluate" --robot=cal.yaml --measurements=touches_moved.csv \
  --json_out=after.json >after.txt 2>err.txt ||
  fail "evaluate calibrated: $(cat err.txt)"
"$apps/activecal_evaluate" "${robot[@]}" --measurements=touches_moved.csv \
  --json_out=before.json >before.txt 2>err.txt ||
  fail "evaluate nominal: $(cat err.txt)"
# --- end of the guide's commands ---

held_ok=1
for p in B.x B.y B.z B.rx B.ry B.rz; do
  grep -qE "^    $p +has no effect on these measurements" cal.txt || held_ok=0
done
[ "$held_ok" = 1 ] && ok "base frame held: no effect" ||
  { fail "base frame held: no effect"; cat cal.txt; }
grep -qE '^plane\.plane_0\.n +1 +-?0\.0[0-9]+, -?0\.0[0-9]+, 1\.000000 ' cal.txt &&
  grep -qE '^plane\.plane_1\.d +m +[-0-9.]+ +0\.0000[0-9]+ ' cal.txt &&
  ok "planes printed with std" || { fail "planes printed with std"; cat cal.txt; }
python3 - <<'PY' && ok "JSON planes" || fail "JSON planes"
import json, math
j = json.load(open("cal.json"))
p = j["planes"]
assert [e["label"] for e in p] == ["plane_0", "plane_1", "plane_2"], p
want = [(0, 0, 1), (-1, 0, 0), (0, 1, 0)]
for e, w in zip(p, want):
    n = e["normal"]
    assert abs(math.sqrt(sum(x * x for x in n)) - 1) < 1e-12, n
    assert sum(a * b for a, b in zip(n, w)) > 0.999, (n, w)
    assert all(0 < s < 1e-3 for s in e["normal_std_rad"]), e
    assert 0 < e["offset_std_m"] < 1e-4, e
assert len(j["planes_covariance"]) == 9
PY
python3 - <<'PY' && ok "flatness on another placement" || fail "flatness on another placement"
import json
a = json.load(open("after.json")); b = json.load(open("before.json"))
assert [p["label"] for p in a["planes"]] == ["plane_0", "plane_1", "plane_2"]
for pa, pb in zip(a["planes"], b["planes"]):
    assert pa["count"] == 12, pa
    # touches repeatable to 0.01 mm
    assert pa["rms"] < 3e-5, pa
    assert pb["rms"] > 5 * pa["rms"], (pa, pb)
rows = [r for r in a["errors"] if r["type"] == "plane"]
assert len(rows) == 36 and all(r["probe_radius_m"] == 0.003 for r in rows)
PY
python3 - <<'PY' && ok "printed flatness = JSON" || fail "printed flatness = JSON"
import json, re
a = json.load(open("after.json"))
text = open("after.txt").read()
for p in a["planes"]:
    m = re.search(r"^  plane %s \((\d+) rows, refitted: normal ([-0-9.]+), ([-0-9.]+), "
                  r"([-0-9.]+), offset ([-0-9.]+) m\): flatness RMS ([0-9.]+) mm, "
                  r"max ([0-9.]+) mm$" % p["label"], text, re.M)
    assert m, (p["label"], text)
    assert int(m.group(1)) == p["count"]
    for g, c in zip((2, 3, 4, 5), p["normal"] + [p["offset_m"]]):
        assert abs(float(m.group(g)) - c) <= 5e-7, (m.group(g), c)
    assert abs(float(m.group(6)) - p["rms"] * 1e3) <= 5e-4, (m.group(6), p)
    assert abs(float(m.group(7)) - p["max"] * 1e3) <= 5e-4, (m.group(7), p)
    assert 0 < p["rms"] <= p["max"], p
PY

# Bad input: one line, status 1, nothing written.
(head -3 touches.csv; grep ',plane_1,' touches.csv; grep ',plane_2,' touches.csv) >two.csv
sed '1s/^type,plane,/type,surface,/' touches.csv >nolabel.csv
sed '2s/,0\.003,/,-0.003,/' touches.csv >negative.csv
expect_fail "plane of two rows" "two.csv:2: row: plane 'plane_0' has 2 rows only" \
  activecal_identify "${robot[@]}" --measurements=two.csv --json_out=o.json
expect_fail "plane rows without a plane column" \
  "nolabel.csv:2: plane: a plane row needs the label of the plane it touched (column 'plane')" \
  activecal_identify "${robot[@]}" --measurements=nolabel.csv --json_out=o.json
expect_fail "negative probe radius" \
  "negative.csv:2: probe_radius_m: a probe radius must be >= 0, got -0.003" \
  activecal_identify "${robot[@]}" --measurements=negative.csv --json_out=o.json
expect_fail "evaluate: plane of two rows" "two.csv:2: row: plane 'plane_0' has 2 rows only" \
  activecal_evaluate --robot=cal.yaml --measurements=two.csv --json_out=o.json
[ ! -e o.json ] && ok "failed runs wrote nothing" || fail "failed runs wrote nothing"

cli_end
