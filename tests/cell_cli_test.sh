#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# activecal_select with a cell (docs/formats.md "Cell file"): the README's
# UR10e-on-a-table example on a small Sobol pool, the JSON's feasible_poses
# and rejected counts, the rejected CSV, the tour, the measurable pool, the
# thread-count independence, and bad input ending with status 1 and one
# line.
#
#   tests/cell_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

ur=(--robot="$data/ur10e.urdf" --tip_link=tool0)
cell="$data/cells/ur10e_table.yaml"

# The example: a Sobol pool filtered by the cell, a design, the tour.
for threads in 1 2; do
  if "$apps/activecal_select" "${ur[@]}" --cell="$cell" --pool=sobol \
    --pool_size=4000 --num_poses=12 --algorithm=fedorov --order=shortest \
    --threads=$threads --json_out=d$threads.json --poses_csv=p$threads.csv \
    --rejected_csv=r$threads.csv >out$threads.txt 2>err$threads.txt; then
    ok "select --cell --order=shortest (threads $threads)"
  else
    fail "select --cell (threads $threads)"; cat err$threads.txt
  fi
done
grep -q "cell: [0-9]* of 4000 poses feasible" out1.txt &&
  grep -q "rejected: joint margin [0-9]*, self-collision [0-9]*, obstacle table [0-9]*, obstacle wall [0-9]*, out of range [0-9]*, target facing away [0-9]*, line of sight blocked [0-9]*" out1.txt &&
  grep -q "tour: 12 poses, estimated motion time" out1.txt &&
  ok "the counts and the tour are printed" || { fail "printed counts"; cat out1.txt; }
cmp -s r1.csv r2.csv && cmp -s p1.csv p2.csv &&
  ok "the rejected CSV and the design do not depend on the thread count" ||
  fail "thread-count independence"
python3 - <<'EOF' && ok "the JSON, the poses CSV and the rejected CSV agree" || fail "cell outputs"
import csv, json
d = json.load(open("d1.json"))
e = json.load(open("d2.json"))
assert d["pose_indices"] == e["pose_indices"] and d["rejected"] == e["rejected"]
assert d["drawn_pool_size"] == 4000
r = d["rejected"]
total = d["feasible_poses"] + sum(v for k, v in r.items() if k != "obstacle") \
    + sum(r["obstacle"].values())
assert total == 4000, total
assert set(r["obstacle"]) == {"table", "wall"}
assert d["pool_size"] == d["feasible_poses"], (d["pool_size"], d["feasible_poses"])
rows = list(csv.DictReader(open("r1.csv")))
assert len(rows) == 4000 - d["feasible_poses"]
reasons = {}
for row in rows:
    reasons[row["reason"]] = reasons.get(row["reason"], 0) + 1
    if row["reason"] == "obstacle":
        assert row["obstacle"] in ("table", "wall") and row["detail"], row
    elif row["reason"] == "self_collision":
        assert "|" in row["detail"], row
    elif row["reason"] == "joint_margin":
        assert row["detail"].endswith("_joint"), row
for k, v in r.items():
    if k == "obstacle":
        assert reasons.get("obstacle", 0) == sum(v.values())
    else:
        assert reasons.get(k, 0) == v, (k, v, reasons.get(k))
# No design pose was rejected; the poses CSV keeps the tour's order.
rejected = {int(row["pose_index"]) for row in rows}
assert not rejected & set(d["pose_indices"])
poses = [int(row["pose_index"]) for row in csv.DictReader(open("p1.csv"))]
assert poses == d["pose_indices"], (poses, d["pose_indices"])
t = d["tour"]
assert t["moves_checked"] is True and t["resolution_deg"] == 1.0
if t["blocked_moves_before"] == 0:
    assert t["motion_time_after_s"] <= t["motion_time_before_s"] + 1e-9, t
assert abs(t["velocities"][0] - 2.0943951023931953) < 1e-12
assert d["targets_seen"] == [["smr"]] * 12
assert d["efficiency_lower_bound"] > 0.5
EOF

# The measurable pool: every pose feasible, far fewer draws than poses.
expect_run "select --pool=measurable" m.txt m.err \
  activecal_select "${ur[@]}" --cell="$cell" --pool=measurable \
  --pool_size=300 --num_poses=12 --algorithm=fedorov --json_out=m.json
python3 - <<'EOF' && ok "the measurable pool is all feasible" || fail "measurable pool"
import json
d = json.load(open("m.json"))
assert d["pool"] == "measurable"
assert d["feasible_poses"] == 300 == d["drawn_pool_size"], d["feasible_poses"]
assert d["measurable_pool"]["draws_per_pose"] < 5, d["measurable_pool"]
EOF

# The issue's iiwa 40-pose lattice design with a 3 deg margin: the lattice
# spans the ranges inside the margins, so no pose is rejected for it and no
# design joint is within 3 deg of a stop (before: 2186 of 2187 rejected).
printf 'joint_margin_deg: 3\nself_clearance_m: 0.0\n' >iiwa_margin.yaml
expect_run "select --cell on the iiwa lattice" iiwa.out iiwa.err \
  activecal_select --robot="$data/kuka_iiwa14.urdf" --tip_link=flange \
  --cell=iiwa_margin.yaml --levels=3 --num_poses=40 --algorithm=fedorov \
  --restarts=2 --json_out=iiwa.json
python3 - <<'EOF' && ok "the iiwa lattice sits inside the margins" || fail "iiwa lattice margins"
import json, math
d = json.load(open("iiwa.json"))
r = d["rejected"]
assert d["drawn_pool_size"] == 2187 and r["joint_margin"] == 0, r
assert d["feasible_poses"] + r["self_collision"] == 2187, (d["feasible_poses"], r)
limits = [170, 120, 170, 120, 170, 120, 175]
least = min(math.radians(l) - abs(v) for q in d["joint_angles_rad"]
            for v, l in zip(q, limits))
assert least >= math.radians(3) - 1e-9, math.degrees(least)
assert len(d["joint_angles_rad"]) == 40
EOF

# The task criterion goes through the same (feasible) pool.
if "$apps/activecal_select" "${ur[@]}" --cell="$cell" --pool=sobol \
  --pool_size=3000 --num_poses=12 --criterion=task_rms --json_out=t.json \
  >t.txt 2>t.err; then
  python3 -c "
import json
d = json.load(open('t.json'))
assert d['criterion'] == 'task_rms'
assert d['num_task_poses'] == d['feasible_poses'] == d['pool_size'], d['num_task_poses']
" && ok "the task criterion over the feasible pool" || fail "task criterion pool"
else
  fail "select --cell --criterion=task_rms"; cat t.err
fi

# Bad input: one line each.
# expect_bad_cell <name> <text expected on stderr> <cell file> <its text, a
# printf format>: select refuses the cell in one line.
expect_bad_cell() {
  printf "$4" >"$3"
  expect_fail "$1" "$2" \
    activecal_select "${ur[@]}" --cell="$3" --pool=sobol --pool_size=100
}
expect_bad_cell "zero normal" "--cell: zero.yaml:2:38: targets[0].normal: a zero vector" zero.yaml \
  'device: {type: laser_tracker, xyz_m: [2, 0, 1]}\ntargets: [{xyz_m: [0, 0, 0], normal: [0, 0, 0], acceptance_deg: 30}]\n'
expect_bad_cell "acceptance angle" "targets[0].acceptance_deg: must be in (0, 90], got 95" angle.yaml \
  'device: {type: laser_tracker, xyz_m: [2, 0, 1]}\ntargets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 95}]\n'
expect_bad_cell "device inside an obstacle" "device.xyz_m: the device lies inside obstacle 'box'" inside.yaml \
  'obstacles: [{name: box, type: box, size_m: [1, 1, 1], xyz_m: [2, 0, 1]}]\ndevice: {type: laser_tracker, xyz_m: [2, 0, 1]}\ntargets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n'
expect_bad_cell "mesh that cannot be read" "obstacles[0].file: missing.stl: Unable to open file" mesh.yaml \
  'obstacles: [{name: m, type: mesh, file: missing.stl}]\n'
expect_fail "missing cell file" "--cell: nothing.yaml: cannot open the file" \
  activecal_select "${ur[@]}" --cell=nothing.yaml --pool=sobol --pool_size=100
expect_fail "measurable without a cell" "--pool=measurable needs --cell" \
  activecal_select "${ur[@]}" --pool=measurable --pool_size=100
expect_fail "rejected_csv without a cell" "--rejected_csv needs --cell" \
  activecal_select "${ur[@]}" --rejected_csv=r.csv
expect_fail "bad --order" "--order must be none or shortest, got 'fast'" \
  activecal_select --order=fast
# A solid below z = 10 m takes every pose of a 2-level lattice (the PUMA of
# data/puma560.yaml, with its collision capsules): none is left.
printf 'obstacles:\n  - {name: floor, type: plane, normal: [0, 0, 1], offset_m: 10}\n' >floor.yaml
expect_fail "empty feasible pool" "--cell: no pose of the pool is left: 0 of 64 poses feasible; rejected: joint margin 0, self-collision 16, obstacle floor 48" \
  activecal_select --robot="$data/puma560.yaml" --cell=floor.yaml --levels=2
# A pool CSV is checked as given (not narrowed to the margins): the PUMA's
# 3-level lattice, the middle level of joints 1-3 only feasible: 27 poses
# cannot identify the PUMA, and the message names what removed the others.
python3 - "$data/puma560.yaml" <<'EOF'
import itertools, sys, yaml
links = yaml.safe_load(open(sys.argv[1]))["links"]
levels = [[l["limits"][0], (l["limits"][0] + l["limits"][1]) / 2, l["limits"][1]]
          for l in links]
with open("lattice.csv", "w") as f:
    f.write("pose_index," + ",".join("q%d_rad" % (j + 1) for j in range(6)) + "\n")
    for i, q in enumerate(itertools.product(*levels)):
        f.write("%d,%s\n" % (i, ",".join(repr(v) for v in q)))
EOF
printf 'joint_margin_override_deg: {L1: 1, L2: 1, L3: 1}\n' >middle.yaml
expect_fail "unidentifiable feasible pool" "the feasible pool (27 of 729 poses feasible; rejected: joint margin 702" \
  activecal_select --cell=middle.yaml --pool_csv=lattice.csv
# With the lattice itself the ranges are narrowed to the margins: every
# pose is feasible.
activecal_select_ok() { "$apps/activecal_select" "$@" >ok.out 2>ok.err; }
if activecal_select_ok --cell=middle.yaml --levels=3 --num_poses=30 &&
  grep -q "cell: 729 of 729 poses feasible" ok.out; then
  ok "the lattice inside the margins is all feasible"
else
  fail "lattice inside the margins"; cat ok.out ok.err
fi
expect_fail "feasible pool smaller than the design" "--num_poses=200: the feasible pool has only" \
  activecal_select "${ur[@]}" --cell="$cell" --pool=sobol --pool_size=2000 --num_poses=200 --json_out=x.json
[ ! -e x.json ] && ok "a failed run writes nothing" || fail "a failed run wrote its JSON"

# A device inside the robot's fixed base (frame 0: it never moves out of the
# way): the URDF's base mesh, a robot file's base capsule; outside it (the
# tracker 2.2 m away, above) is accepted.
printf 'device: {type: laser_tracker, xyz_m: [0, 0, 0.05]}\ntargets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n' >inbase.yaml
expect_fail "device inside the UR's base" \
  "--cell: inbase.yaml:1:9: device.xyz_m: the device lies inside the robot's fixed link 'base_link_inertia' (its collision geometry in $data/ur10e.urdf)" \
  activecal_select "${ur[@]}" --cell=inbase.yaml --pool=sobol --pool_size=100
printf 'device: {type: mocap, min_cameras: 1, cameras: [{xyz_m: [2, 0, 1], fov_deg: 90, look_at_m: [0, 0, 0]}, {xyz_m: [0, 0, 0.3], fov_deg: 90, look_at_m: [1, 0, 0]}]}\ntargets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n' >inpuma.yaml
expect_fail "a camera inside the PUMA's base" \
  "device.cameras[1].xyz_m: the device lies inside the robot's fixed link 'base'" \
  activecal_select --robot="$data/puma560.yaml" --cell=inpuma.yaml --pool=sobol --pool_size=100
printf 'device: {type: laser_tracker, xyz_m: [0.15, 0, 0.3]}\ntargets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 90}]\n' >besidebase.yaml
"$apps/activecal_select" --robot="$data/puma560.yaml" --cell=besidebase.yaml --pool=sobol \
  --pool_size=200 --num_poses=8 --restarts=1 >beside.out 2>beside.err
grep -q "lies inside" beside.err && { fail "a device 5 cm beside the base capsule refused"; cat beside.err; } ||
  ok "a device 5 cm beside the base capsule is not refused as inside it"

cli_end
