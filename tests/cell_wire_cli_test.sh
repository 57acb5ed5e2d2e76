#!/usr/bin/env bash
# The cell where poses are planned besides activecal_select (issues #24 and
# #25, items 6): activecal_active --cell designs every batch from the
# feasible pool (every pose it measured passes the cell's checks, recomputed
# by activecal_select on those poses alone; without --cell some do not),
# its JSON counts; a cell that leaves no pose fails in one line, writing
# nothing; activecal_select's task criterion chooses feasible poses only;
# activecal_compensate --cell gives a configuration through the table status
# collision.
#
#   tests/cell_wire_cli_test.sh <build/apps dir> <data dir> <tests/data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
apps="$(cd "$1" && pwd)"
data="$(cd "$2" && pwd)"
tdata="$(cd "$3" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
failures=0
ok() { echo "ok   [$1]"; }
fail() { echo "FAIL [$1]"; failures=$((failures + 1)); }

source "$here/cli_lib.sh"

puma="$data/puma560.yaml"
cell="$tdata/puma_table_cell.yaml"
loop=(--robot="$puma" --levels=3 --max_rounds=3 --restarts=1 --threads=2)

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
expect_fail "active --resume without the cell" "was made with cell with content hash" \
  activecal_active "${loop[@]}" --session=s --resume
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

echo "cell_wire_cli_test: $failures failure(s)"
[ "$failures" -eq 0 ]
