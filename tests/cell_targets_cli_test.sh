#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Several targets per pose (issue #24, item 1): a cell with two reflectors
# back to back on the PUMA's flange, its targets the markers. The design's
# poses CSV says which targets each pose sees (the JSON's targets_seen), and
# activecal_active measures only those: simulated, and through
# activecal_sim_cell --cell (the driver request names the markers), no
# measurement of a marker the cell does not see at its pose.
#
#   tests/cell_targets_cli_test.sh <build/apps dir> <data dir> <tests/data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
tdata="$(cd "$3" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

puma=(--robot="$data/puma560.yaml")
cell="$tdata/puma_two_targets_cell.yaml"

# --- The design: a targets column as the JSON's targets_seen. ---
expect_run "select --cell with two targets" d.out d.err \
  activecal_select "${puma[@]}" --cell="$cell" --levels=3 \
  --num_poses=12 --algorithm=fedorov --json_out=d.json --poses_csv=p.csv
python3 - <<'PY' && ok "the poses CSV's targets are those seen" || fail "targets column"
import csv, json
d = json.load(open("d.json"))
rows = list(csv.DictReader(open("p.csv")))
assert [int(r["pose_index"]) for r in rows] == d["pose_indices"]
assert [r["targets"].split(";") for r in rows] == d["targets_seen"], \
    ([r["targets"] for r in rows], d["targets_seen"])
seen = {t for s in d["targets_seen"] for t in s}
assert seen == {"front", "back"}, seen  # both kinds of pose in the design
assert all(len(s) == 1 for s in d["targets_seen"])  # back to back
PY
# The poses CSV with its targets column reads back as a pool.
"$apps/activecal_select" "${puma[@]}" --pool_csv=p.csv --num_poses=12 \
  --algorithm=greedy >r.out 2>r.err &&
  ok "the poses CSV with targets reads back" || { fail "read back"; cat r.err; }

# --- The active loop measures the targets seen only. ---
loop=(--levels=3 --max_rounds=2 --restarts=1 --threads=2)
if "$apps/activecal_active" "${puma[@]}" "${loop[@]}" --cell="$cell" \
  --session=s --json_out=s.json >s.out 2>s.err; then
  ok "active --cell, simulated"
else
  fail "active --cell, simulated"; cat s.err
fi
if "$apps/activecal_active" "${puma[@]}" "${loop[@]}" --cell="$cell" \
  --session=w --json_out=w.json --verbose \
  --driver="$apps/activecal_sim_cell ${puma[*]} --cell=$cell --seed=3" \
  >w.out 2>w.err; then
  ok "active --cell through activecal_sim_cell --cell"
else
  fail "active --cell through the driver"; cat w.err
fi
python3 - <<'PY' && ok "every measurement is of a target its pose sees" || fail "unseen targets measured"
import csv, json
for name in ("s", "w"):
    d = json.load(open(name + ".json"))
    want = dict(zip(d["measured_pose_indices"], d["targets_seen"]))
    got = {}
    for r in csv.DictReader(open(name + "/measurements.csv")):
        got.setdefault(int(r["pose_index"]), []).append(r["marker"])
    assert set(got) == set(want), (name, sorted(got), sorted(want))
    for i, markers in got.items():
        assert markers == want[i], (name, i, markers, want[i])
    kinds = {m for ms in got.values() for m in ms}
    assert kinds == {"front", "back"}, (name, kinds)
PY

# activecal_sim_cell --cell alone: a request naming a marker it does not
# see gets null for it; a pose where neither is seen is not_visible.
python3 - "$apps/activecal_sim_cell" "$data/puma560.yaml" "$cell" <<'PY' && ok "sim_cell --cell reports the markers asked for and seen" || fail "sim_cell --cell"
import json, subprocess, sys
sim, robot, cell = sys.argv[1:]
hello = {"type": "hello", "protocol": 1, "markers": 2, "robot": "puma560",
         "joint_names": ["j%d" % i for i in range(1, 7)]}
# Pose 128 of the 3-level lattice sees the front reflector (tests above).
q = [-4.363323129985824, 0.5235987755982987, 0, 1.7453292519943295,
     -2.478367537831948, 6.213372137099813]
msgs = [hello,
        {"type": "measure", "id": 1, "joints_rad": q},
        {"type": "measure", "id": 2, "joints_rad": q, "markers": [1]},
        {"type": "measure", "id": 3, "joints_rad": q, "markers": [0, 1]},
        {"type": "measure", "id": 4, "joints_rad": [0, 0, 0, 0, 1.5707963, 0]},
        {"type": "bye"}]
out = subprocess.run([sim, "--robot=" + robot, "--cell=" + cell],
                     input="".join(json.dumps(m) + "\n" for m in msgs),
                     capture_output=True, text=True, check=True).stdout
r = [json.loads(l) for l in out.splitlines()]
assert r[1]["status"] == "ok" and r[1]["points_m"][0] and r[1]["points_m"][1] is None, r[1]
assert r[2]["status"] == "not_visible", r[2]  # back asked for, front seen only
assert r[3]["points_m"][0] and r[3]["points_m"][1] is None, r[3]
assert r[4]["status"] in ("ok", "not_visible"), r[4]
PY

cli_end
