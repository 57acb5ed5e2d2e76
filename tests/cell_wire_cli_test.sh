#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# The cell where poses are planned besides activecal_select (issues #24 and
# #25, items 6): activecal_active --cell designs every batch from the
# feasible pool (every pose it measured passes the cell's checks, recomputed
# by activecal_select on those poses alone; without --cell some do not),
# its JSON counts, --order=shortest per batch; a cell that leaves no pose
# fails in one line, writing nothing; activecal_select's task criterion chooses feasible poses only;
# activecal_compensate --cell gives a configuration through the table status
# collision.
#
#   tests/cell_wire_cli_test.sh <build/apps dir> <data dir> <tests/data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

puma_table_cell "$3"

# --- The active loop from the feasible pool. ---
if "$apps/activecal_active" "${loop[@]}" --cell="$cell" --session=s \
  --json_out=a.json >a.out 2>a.err; then
  ok "active --cell"
else
  fail "active --cell"; cat a.err
fi
"$apps/activecal_active" "${loop[@]}" --session=n --json_out=n.json \
  >n.out 2>n.err || { fail "active without --cell"; cat n.err; }
grep -q "cell: [0-9]* of 729 poses feasible" a.out &&
  grep -q "obstacle table [1-9][0-9]*, out of range 0" a.out &&
  [ "$(grep -c "poses feasible" a.out)" -eq 1 ] &&
  ok "the counts are printed once" || { fail "printed counts"; cat a.out; }
# The poses each loop measured (its session log), as a poses CSV.
python3 - <<'PY' || fail "the measured poses"
import csv, json
for name in ("s", "n"):
    seen, rows = set(), []
    for r in csv.DictReader(open(name + "/measurements.csv")):
        if r["pose_index"] in seen:
            continue
        seen.add(r["pose_index"])
        rows.append([r["pose_index"]] + [r["q%d_rad" % j] for j in range(1, 7)])
    with open(name + "_poses.csv", "w") as f:
        f.write("pose_index," + ",".join("q%d_rad" % j for j in range(1, 7)) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")
    open(name + "_count", "w").write(str(len(rows)))
d = json.load(open("a.json"))
assert d["cell"].endswith("puma_table_cell.yaml")
r = d["rejected"]
total = d["feasible_poses"] + sum(v for k, v in r.items() if k != "obstacle") \
    + sum(r["obstacle"].values())
assert total == 729, total
assert 0 < r["obstacle"]["table"] and d["feasible_poses"] < 729, r
assert len(set(d["measured_pose_indices"])) == int(open("s_count").read())
PY
# The cell's checks recomputed on the measured poses alone.
check_poses() {  # <poses CSV> -> "K of N" of the cell's verdict
  "$apps/activecal_select" --robot="$puma" --cell="$cell" --pool_csv="$1" \
    --num_poses=1 --threads=1 >check.out 2>&1
  sed -n 's/.*cell: \([0-9]* of [0-9]*\) poses feasible.*/\1/p' check.out
}
n_s=$(cat s_count 2>/dev/null)
got=$(check_poses s_poses.csv)
[ -n "$n_s" ] && [ "$got" = "$n_s of $n_s" ] &&
  ok "every pose active --cell measured passes the cell's checks ($got)" ||
  { fail "active --cell measured infeasible poses: $got (of $n_s)"; cat check.out; }
n_n=$(cat n_count 2>/dev/null)
got=$(check_poses n_poses.csv)
case "$got" in
  *" of $n_n") [ "${got%% *}" -lt "$n_n" ] &&
    ok "without --cell the loop measures poses the cell rejects ($got)" ||
    fail "without --cell every pose is feasible: the test proves nothing" ;;
  *) fail "recheck of the loop without --cell: '$got'"; cat check.out ;;
esac
# --order=shortest: each batch the same poses, run as a shorter tour.
if "$apps/activecal_active" "${loop[@]}" --cell="$cell" --order=shortest \
  --json_out=o.json >o.out 2>o.err; then
  ok "active --cell --order=shortest"
else
  fail "active --cell --order=shortest"; cat o.err
fi
grep -q -- "--order=shortest: [0-9]* batch tours, estimated motion time .* s -> .* s, [0-9]* blocked moves left" o.out &&
  ok "... the tour printed" || { fail "active tour line"; cat o.out; }
python3 - <<'PY' && ok "... the first batch the same poses in a tour no longer than the design's order" || fail "active --order=shortest"
import json
a, o = json.load(open("a.json")), json.load(open("o.json"))
b0, c0 = a["rounds"][0]["batch"], o["rounds"][0]["batch"]
assert sorted(b0) == sorted(c0) and b0 != c0, (b0, c0)
t = o["tour"]
assert t["batches"] == len(o["rounds"]) and t["moves_checked"] is True, t
assert 0 < t["motion_time_after_s"] <= t["motion_time_before_s"] + 1e-9, t
assert o["feasible_poses"] == a["feasible_poses"]
PY
expect_fail "active --order=fast" "--order must be none or shortest, got 'fast'" \
  activecal_active "${loop[@]}" --order=fast
# The same session with another cell (or none) is not continued.
expect_fail "active --resume without the cell" "--session: 's' was made with cell $cell (hash " \
  activecal_active "${loop[@]}" --session=s --resume
grep -qF "), this run has no cell: a session continues" err.txt &&
  ok "... saying this run has no cell" || { fail "resume without the cell: wording"; cat err.txt; }
"$apps/activecal_active" "${loop[@]}" --max_rounds=1 --session=nocell >nocell.out 2>nocell.err ||
  { fail "active --session without a cell"; cat nocell.err; }
expect_fail "active --resume of a session without a cell, with one" \
  "--session: 'nocell' was made with no cell, this run has $cell (hash " \
  activecal_active "${loop[@]}" --max_rounds=1 --cell="$cell" --session=nocell --resume
# Another cell: both files named, each with its hash.
sed 's/clearance_m: 0.02/clearance_m: 0.03/' "$cell" >changed.yaml
expect_fail "active --resume with a changed cell" \
  "this run's cell changed.yaml differs (hash " \
  activecal_active "${loop[@]}" --cell=changed.yaml --session=s --resume
grep -qF "session s was made with cell $cell (hash " err.txt &&
  ok "... naming the session's cell" || { fail "resume: the session's cell"; cat err.txt; }
# Only a target moved: the targets are the robot's markers, so the robot's
# hash changed too; the cell is what is named.
{ cat "$cell"; printf '%s\n' "device: {type: laser_tracker, xyz_m: [2.5, 0, 0.5]}" \
    "targets:" "  - {name: a, xyz_m: [0, 0, 0.05], normal: [1, 0, 0], acceptance_deg: 60}" \
    "  - {name: b, xyz_m: [0.05, 0, 0], normal: [1, 0, 0], acceptance_deg: 60}"; } >targets.yaml
sed 's/xyz_m: \[0.05, 0, 0\]/xyz_m: [0.06, 0, 0]/' targets.yaml >moved.yaml
"$apps/activecal_active" "${loop[@]}" --max_rounds=1 --cell=targets.yaml \
  --session=t >t.out 2>&1
[ -e t/session.json ] || { fail "active --cell=targets.yaml: no session"; cat t.out; }
expect_fail "active --resume with a target moved" \
  "session t was made with cell targets.yaml (hash " \
  activecal_active "${loop[@]}" --max_rounds=1 --cell=moved.yaml --session=t \
  --resume
# A cell that leaves no pose: one line with the counts, nothing written.
sed 's/offset_m: 0.3/offset_m: 5.0/' "$cell" >all.yaml
expect_fail "active --cell keeping no pose" \
  "--cell: no pose of the pool is left: 0 of 729 poses feasible; rejected: joint margin 0, self-collision 330, obstacle table 399" \
  activecal_active "${loop[@]}" --cell=all.yaml --session=none \
  --json_out=none.json
[ ! -e none.json ] && [ ! -e none ] && ok "... writing nothing" ||
  fail "a failed active --cell wrote files"
expect_fail "active --cell keeping fewer poses than the first batch" \
  "--first_batch=400: the feasible pool has only " \
  activecal_active "${loop[@]}" --cell="$cell" --first_batch=400

# --- The task criterion chooses from the feasible pool too (as every
# criterion: the pool is filtered before any design). ---
for target in none 3e-4; do
  extra=()
  [ "$target" = none ] || extra=(--target_rms_m=$target)
  if "$apps/activecal_select" --robot="$puma" --levels=3 --cell="$cell" \
    --criterion=task_rms --num_poses=12 "${extra[@]}" --threads=2 \
    --json_out=t_$target.json --rejected_csv=tr_$target.csv \
    >t.out 2>t.err; then
    ok "select --criterion=task_rms --cell (target $target)"
  else
    fail "select --criterion=task_rms --cell (target $target)"; cat t.err
  fi
done
"$apps/activecal_select" --robot="$puma" --levels=3 --criterion=task_rms \
  --num_poses=12 --threads=2 --json_out=t_free.json >/dev/null 2>&1 ||
  fail "select --criterion=task_rms without --cell"
python3 - <<'PY' && ok "the task designs take feasible poses only" || fail "task design with --cell"
import csv, json
rejected = {int(r["pose_index"]) for r in csv.DictReader(open("tr_none.csv"))}
for name in ("t_none.json", "t_3e-4.json"):
    d = json.load(open(name))
    assert d["criterion"] == "task_rms", d["criterion"]
    assert d["pool_size"] == d["feasible_poses"] == 729 - len(rejected), name
    assert d["pose_indices"] and not set(d["pose_indices"]) & rejected, name
free = json.load(open("t_free.json"))
assert set(free["pose_indices"]) & rejected, "the check proves nothing"
PY

# --- Compensation through the table. ---
# A program of a pose the cell keeps and one it rejects for the table
# (activecal_select's rejected CSV names it), compensated on the robot it
# was taught with: each converges to itself, and only the second collides.
"$apps/activecal_select" --robot="$puma" --levels=3 --cell="$cell" \
  --num_poses=12 --poses_csv=design.csv --rejected_csv=rejected.csv \
  --threads=2 >sel.out 2>sel.err || { fail "select --cell"; cat sel.err; }
python3 - <<'PY' || fail "the program"
import csv
table = [r for r in csv.DictReader(open("rejected.csv")) if r["obstacle"] == "table"]
kept = list(csv.DictReader(open("design.csv")))
cols = ["pose_index"] + ["q%d_rad" % j for j in range(1, 7)]
with open("program.csv", "w") as f:
    f.write(",".join(cols) + "\n")
    for r in (kept[0], table[0]):
        f.write(",".join(r[c] for c in cols) + "\n")
open("table_link", "w").write(table[0]["detail"])
PY
"$apps/activecal_compensate" --robot="$puma" --nominal="$puma" \
  --poses_csv=program.csv --out=free.csv --json_out=free.json >/dev/null 2>&1
"$apps/activecal_compensate" --robot="$puma" --nominal="$puma" \
  --poses_csv=program.csv --cell="$cell" --out=comp.csv \
  --json_out=comp.json >comp.out 2>comp.err
status=$?
link=$(cat table_link 2>/dev/null)
[ "$status" -eq 2 ] &&
  grep -q "1 of 2 targets are not converged, written with their status to comp.csv: 1 collision (the first, target 1, pose_index [0-9]*: obstacle table ($link))" comp.err &&
  ! grep -q "did not converge" comp.err &&
  ok "compensate --cell: the pose through the table is a collision (status 2)" ||
  { fail "compensate --cell (status $status)"; cat comp.err; }
python3 - <<'PY' && ok "... in the CSV and the JSON" || fail "compensate --cell outputs"
import csv, json
free = json.load(open("free.json"))
assert free["num_converged"] == 2 and free["num_collision"] == 0, free
d = json.load(open("comp.json"))
assert d["num_converged"] == 1 and d["num_collision"] == 1, d
assert d["cell"].endswith("puma_table_cell.yaml")
t = d["targets"]
assert t[0]["status"] == "converged" and t[1]["status"] == "collision", t
assert t[1]["message"].startswith("obstacle table ("), t[1]
rows = list(csv.DictReader(open("comp.csv")))
assert [r["status"] for r in rows] == ["converged", "collision"], rows
PY
# A joint margin the program's pose leaves (its joints sit on the limits).
sed 's/joint_margin_deg: 0/joint_margin_deg: 3/; s/offset_m: 0.3/offset_m: -5/' \
  "$cell" >margin.yaml
"$apps/activecal_compensate" --robot="$puma" --nominal="$puma" \
  --poses_csv=program.csv --cell=margin.yaml --out=m.csv >m.out 2>m.err
grep -q "targets are not converged, written with their status to m.csv: [12] collision (the first, target [01], pose_index [0-9]*: joint margin (L[1-6]))" m.err &&
  ok "compensate --cell: a joint margin left is a collision too" ||
  { fail "compensate --cell joint margin"; cat m.err; }

cli_end
