#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# What select and active --cell say about the cell (#24's remainder): the
# D-efficiency lost to the cell (1 for a cell that rejects nothing, < 1 for
# a table), what the tour's moves were checked against and the velocities
# assumed, blocked moves a count and a list in both programs, and a
# program's outputs written all or nothing (stale temporaries of a killed
# run removed by the next; two outputs on one file refused; a plot one of
# the outputs; sim_cell's --listen opened before --truth_out is written).
#
#   tests/cell_outputs_cli_test.sh <build/apps dir> <data dir> <tests/data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

puma_table_cell "$3"
"$apps/activecal_active" "${loop[@]}" --cell="$cell" --order=shortest \
  --json_out=o.json >o.out 2>o.err || { fail "active --cell --order=shortest"; cat o.err; }

# --- The D-efficiency lost to the cell (select --cell): 1 for a cell that
# rejects nothing (the robot without collision geometry, no margin: the
# feasible pool is the unconstrained one), < 1 for the table. ---
sed '/^collision:/,$d' "$puma" >nocoll.yaml
printf 'joint_margin_deg: 0\nclearance_m: 0.02\n' >empty_cell.yaml
sel=(--pool=sobol --pool_size=1000 --num_poses=12 --algorithm=fedorov --restarts=1 --threads=2)
"$apps/activecal_select" --robot=nocoll.yaml --cell=empty_cell.yaml "${sel[@]}" \
  --order=shortest --json_out=e1.json >e1.out 2>e1.err || { fail "select, empty cell"; cat e1.err; }
"$apps/activecal_select" --robot="$puma" --cell="$cell" "${sel[@]}" --order=shortest \
  --json_out=e2.json >e2.out 2>e2.err || { fail "select, table cell"; cat e2.err; }
python3 - <<'PY' && ok "D-efficiency lost to the cell: 1 without rejections, < 1 with the table; printed as in the JSON" || fail "cell D-efficiency"
import json, re
for name, expect_one in (("e1", True), ("e2", False)):
    d = json.load(open(name + ".json"))
    e = d["cell_d_efficiency"]
    p = e["num_parameters"]
    assert p == len(d["free_parameters"]), (p, d["free_parameters"])
    assert e["unconstrained_pool_size"] == d["feasible_poses"], (e, d["feasible_poses"])
    assert abs(e["log10_det_cell"] - d["log10_det"]) < 1e-12, (e, d["log10_det"])
    ratio = 10 ** ((e["log10_det_cell"] - e["log10_det_unconstrained"]) / p)
    assert abs(e["d_efficiency"] - ratio) < 1e-12, e
    if expect_one:
        assert d["feasible_poses"] == 1000, d["feasible_poses"]
        assert abs(e["d_efficiency"] - 1) < 1e-9, e
    else:
        assert d["feasible_poses"] < 1000 and e["d_efficiency"] < 0.999, e
    lines = [l for l in open(name + ".out") if "D-efficiency lost to the cell" in l]
    assert len(lines) == 1, lines
    m = re.search(r"lost to the cell: ([0-9.]+) = 10\^\(\(([-0-9.]+) - ([-0-9.]+)\) / (\d+)\) "
                  r"against an unconstrained sobol pool of (\d+) poses", lines[0])
    assert m, lines[0]
    assert float(m.group(1)) == round(e["d_efficiency"], 4), (lines[0], e)
    assert int(m.group(4)) == p and int(m.group(5)) == e["unconstrained_pool_size"]
PY

# The cell's targets as the markers (two reflectors back to back): the
# unconstrained design measures every target at every pose, so that the
# figure does not depend on the order the cell file lists them in (it was
# measured with the first target's rows only: 0.9309 listed front first).
two="$tdata/puma_two_targets_cell.yaml"
{ sed '/^targets:/,$d' "$two"; echo "targets:"; grep "name: back" "$two"; grep "name: front" "$two"; } >two_swapped.yaml
for c in two two_swapped; do
  f="$two"; [ $c = two_swapped ] && f=two_swapped.yaml
  "$apps/activecal_select" --robot="$puma" --cell="$f" --levels=3 --num_poses=12 \
    --algorithm=fedorov --restarts=1 --threads=2 --json_out=$c.json >$c.out 2>$c.err ||
    { fail "select, $c"; cat $c.err; }
done
python3 - <<'PY' && ok "D-efficiency with several targets: every target in the unconstrained design, whatever their order" || fail "cell D-efficiency, several targets"
import json
a = json.load(open("two.json"))["cell_d_efficiency"]
b = json.load(open("two_swapped.json"))["cell_d_efficiency"]
assert abs(a["log10_det_unconstrained"] - b["log10_det_unconstrained"]) < 1e-9, (a, b)
assert abs(a["d_efficiency"] - b["d_efficiency"]) < 1e-9, (a, b)
assert 0 < a["d_efficiency"] < 1, a
PY

# --- moves_checked says what was checked: a robot file without collision
# geometry (as activecal_simulate --true_model_out writes) checks none; the
# velocity limits missing, the 1 rad/s assumed is said once; blocked moves a
# count and a list in select's JSON as in active's. ---
"$apps/activecal_active" --robot=nocoll.yaml --levels=3 --max_rounds=2 --restarts=1 \
  --threads=2 --cell="$cell" --order=shortest --json_out=nc.json >nc.out 2>nc.err ||
  { fail "active --cell, no collision geometry"; cat nc.err; }
[ "$(grep -c "no velocity limit in the robot's file: taken at 1 rad/s for the motion-time estimate" nc.out)" -eq 1 ] &&
  grep -q "(moves not checked for collisions: no collision geometry)" nc.out &&
  ok "active: no collision geometry and the assumed velocities said once" ||
  { fail "active notes"; cat nc.out; }
python3 - <<'PY' && ok "... in the JSON: moves_checked false with the reason; blocked moves a count and a list in both programs" || fail "moves_checked / blocked_moves"
import json
t = json.load(open("nc.json"))["tour"]
assert t["moves_checked"] is False and t["moves_not_checked"] == "no collision geometry", t
assert t["blocked_moves"] == 0 and t["blocked"] == [], t
assert "1 rad/s" in t["velocity_note"], t
o = json.load(open("o.json"))["tour"]
assert o["moves_checked"] is True and "moves_not_checked" not in o, o
assert isinstance(o["blocked_moves"], int) and len(o["blocked"]) == o["blocked_moves"], o
for b in o["blocked"]:
    assert set(b) == {"batch", "from", "to", "from_pose_index", "to_pose_index", "reason"}, b
s = json.load(open("e2.json"))
st = s["tour"]
assert st["moves_checked"] is True, st
assert isinstance(st["blocked_moves"], int) and len(st["blocked"]) == st["blocked_moves"], st
assert st["blocked_moves"] > 0, st  # the table blocks some straight moves
for b in st["blocked"]:
    assert b["to"] == b["from"] + 1
    assert s["pose_indices"][b["from"]] == b["from_pose_index"], (b, s["pose_indices"])
    assert s["pose_indices"][b["to"]] == b["to_pose_index"]
e1 = json.load(open("e1.json"))["tour"]
assert e1["moves_checked"] is False and e1["moves_not_checked"] == "no collision geometry", e1
PY

# --- Outputs all-or-nothing: a select whose --json_out cannot be written
# (a directory) writes no poses CSV, no rejected CSV and no temporary; a
# killed run's temporaries are removed by the next run. ---
mkdir -p out_dir
rm -f set_p.csv set_r.csv
"$apps/activecal_select" --robot="$puma" --cell="$cell" "${sel[@]}" \
  --poses_csv=set_p.csv --rejected_csv=set_r.csv --json_out=out_dir >set.out 2>set.err
st=$?
left=$(ls set_p.csv set_r.csv ./*.tmp out_dir/* 2>/dev/null | wc -l)
[ $st -eq 1 ] && [ "$left" -eq 0 ] && [ "$(wc -l <set.err)" -eq 1 ] &&
  grep -q "cannot write 'out_dir': it is a directory" set.err &&
  ok "a select that cannot write its JSON writes nothing" ||
  { fail "select output set (status $st, $left files left)"; cat set.err; ls; }
echo partial >set_p.csv.activecal-999999999.tmp  # no such process
echo partial >set_r.csv.activecal-999999998.tmp
"$apps/activecal_select" --robot="$puma" --cell="$cell" "${sel[@]}" \
  --poses_csv=set_p.csv --rejected_csv=set_r.csv --json_out=set.json >set.out 2>set.err &&
  [ -s set_p.csv ] && [ -s set_r.csv ] && [ -s set.json ] &&
  ! ls ./*.tmp >/dev/null 2>&1 &&
  ok "the next run writes all three and removes the stale temporaries" ||
  { fail "select after a killed run"; cat set.err; ls; }


# Two outputs on one file (the same path, or two spellings of it): refused,
# nothing written (they shared one temporary: the second rename found it
# gone, and the run failed with one output replaced). active checks its
# outputs before the work and names both flags; select's --json_out is
# refused when it is written, before any rename.
rm -f same.csv ./*.tmp
"$apps/activecal_select" --robot="$puma" --pool=sobol --pool_size=300 --num_poses=12 \
  --algorithm=fedorov --restarts=1 --threads=2 --poses_csv=same.csv --json_out=./same.csv \
  >same.out 2>same.err
st=$?
[ $st -eq 1 ] && [ ! -e same.csv ] && ! ls ./*.tmp >/dev/null 2>&1 && [ "$(wc -l <same.err)" -eq 1 ] &&
  grep -q "cannot write './same.csv': it is the same file as 'same.csv', which is already an output of this run" same.err &&
  ok "two outputs on one file: select's --json_out on --poses_csv's file refused, nothing written" ||
  { fail "select, two outputs on one file (status $st)"; cat same.err; ls; }
"$apps/activecal_active" "${loop[@]}" --json_out=same.json --program_out=./same.json \
  >same.out 2>same.err
st=$?
[ $st -eq 1 ] && [ ! -e same.json ] && [ "$(wc -l <same.err)" -eq 1 ] &&
  grep -q "error: --json_out: 'same.json' is the file of --program_out ('./same.json')" same.err &&
  ok "two outputs on one file: active's --json_out on --program_out's refused before the work" ||
  { fail "active, two outputs on one file (status $st)"; cat same.err; ls; }

# A plot is one of the outputs: evaluate --plot with a --report_html it
# cannot write fails having written no figure (gnuplot's PNG was renamed
# over --plot at once, before the report failed).
if command -v gnuplot >/dev/null; then
  "$apps/activecal_select" --robot="$puma" --pool=sobol --pool_size=300 --num_poses=20 \
    --algorithm=fedorov --restarts=1 --threads=2 --poses_csv=ev_p.csv >/dev/null 2>&1 &&
    "$apps/activecal_simulate" --robot="$puma" --poses_csv=ev_p.csv --noise_m=0.0005 \
      --out=ev_m.csv >/dev/null 2>&1 || fail "select + simulate for evaluate"
  echo partial >ev.png.activecal-999999997.tmp  # a killed run's figure
  "$apps/activecal_evaluate" --robot="$puma" --measurements=ev_m.csv --plot=ev.png \
    --json_out=ev.json --report_html=no_such_dir/ev.html >ev.out 2>ev.err
  st=$?
  [ $st -eq 1 ] && [ ! -e ev.png ] && [ ! -e ev.json ] && ! ls ./*.tmp >/dev/null 2>&1 &&
    grep -q "cannot write 'no_such_dir/ev.html'" ev.err &&
    ok "evaluate: a failed run leaves no --plot figure (nor a killed run's)" ||
    { fail "evaluate --plot on a failed run (status $st)"; cat ev.err; ls; }
fi

# sim_cell --truth_out is committed before the cell serves (the client reads
# it): a --listen that is bad or whose port is taken fails before it, and
# nothing is written.
"$apps/activecal_sim_cell" --robot="$puma" --perturb_m=0.001 --truth_out=truth.yaml \
  --listen=abc </dev/null >sc.out 2>sc.err
st=$?
[ $st -eq 1 ] && [ ! -e truth.yaml ] && grep -q "error: --listen must be PORT or HOST:PORT, got 'abc'" sc.err &&
  ok "sim_cell: a bad --listen writes no --truth_out" ||
  { fail "sim_cell --listen=abc (status $st)"; cat sc.err; ls; }
python3 - "$apps/activecal_sim_cell" "$puma" <<'PY' && [ ! -e truth.yaml ] &&
import socket, subprocess, sys
s = socket.socket()
s.bind(("127.0.0.1", 0))
s.listen()
r = subprocess.run([sys.argv[1], "--robot=" + sys.argv[2], "--perturb_m=0.001",
                    "--truth_out=truth.yaml", "--listen=%d" % s.getsockname()[1]],
                   stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=20)
assert r.returncode == 1 and "--listen: listen on 127.0.0.1:" in r.stderr, (r.returncode, r.stderr)
PY
  ok "sim_cell: a --listen port in use writes no --truth_out" ||
  { fail "sim_cell --listen on a taken port"; ls; }

# --order_resolution_deg coarser than 10 deg checks little more than the
# end points: refused; without --cell the tour line says why no move is
# checked.
for prog in activecal_select activecal_active; do
  expect_fail "$prog --order_resolution_deg=45" \
    "--order_resolution_deg must be in (0, 10], got 45: a move is checked at joint steps of at most this many degrees" \
    $prog --robot="$puma" --levels=3 --order=shortest --cell="$cell" \
    --order_resolution_deg=45
done
"$apps/activecal_select" --robot="$puma" --levels=3 --num_poses=10 \
  --order=shortest --poses_csv=nocell.csv >nocell.out 2>&1 &&
  grep -q "tour: 10 poses, estimated motion time .*; no --cell: moves not checked" nocell.out &&
  ! grep -q "moves checked" nocell.out &&
  ok "select --order=shortest without --cell: says the moves are not checked" ||
  { fail "select --order=shortest without --cell"; cat nocell.out; }
cli_end
