#!/bin/bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# The active loop against a robot cell through a real pipe: activecal_active
# --driver with activecal_sim_cell (and the Python example driver), the
# session killed from either side and resumed to the same bytes, every
# measurement the cell served in the log exactly once, bad driver output
# named in one line with nothing lost, TCP, and the controller programs.
#
# Usage: driver_cli_test.sh <apps dir> <data dir> <examples dir>
set -u
apps="$1"
data="$2"
examples="$3"
. "$(dirname "$0")/cli_lib.sh"
cli_workdir

A="$apps/activecal_active"
CELL="$apps/activecal_sim_cell"
common=(--levels=3 --target_rms_m=1e-4 --noise_m=1e-4 --seed=3)
cell="$CELL --seed=3 --not_visible_fraction=0.1"
same_session() {  # same_session <dir a> <dir b>: the same bytes
  for f in measurements.csv excluded.jsonl state.json session.json; do
    cmp -s "$1/$f" "$2/$f" || { echo "  $1/$f and $2/$f differ"; return 1; }
  done
}

# --- The reference: one uninterrupted run. ---
if "$A" "${common[@]}" --driver="$cell --served_log=$work/served_ref.jsonl" \
    --session=ref --json_out=ref.json >ref.txt 2>ref.err; then
  python3 - <<'PY' && ok "loop against the cell" || fail "loop against the cell"
import json
j = json.load(open('ref.json'))
assert j['termination_type'] == 'CONVERGENCE', j['message']
assert j['measured_by'] == 'driver'
# A tenth of the poses are hidden: some were excluded, none measured.
ex = {e['pose_index'] for e in j['excluded_poses']}
assert ex and not ex & set(j['measured_pose_indices']), ex
assert all(e['status'] == 'not_visible' for e in j['excluded_poses'])
# Every batch was repaired to its size.
r = j['rounds']
assert all(len(x['batch']) == (12 if k == 0 else 6) for k, x in enumerate(r)), r
assert r[-1]['true_task_rms_m'] < 3 * r[-1]['predicted_task_rms_m']
PY
else
  fail "loop against the cell (exit $?)"; cat ref.err
fi
# One line per round as it happens: the rows are in the output.
rows=$(grep -cE '^  [0-9]+ +[0-9]+ ' ref.txt)
[ "$rows" -eq "$(python3 -c "import json; print(len(json.load(open('ref.json'))['rounds']))")" ] \
  && ok "a row per round" || fail "a row per round ($rows)"

# --- The driver killed twice: resumed to the same bytes. ---
"$A" "${common[@]}" --driver="$cell --die_after=10 --served_log=$work/served.jsonl" \
  --session=killed --json_out=killed.json >k1.txt 2>k1.err
s1=$?
grep -v "activecal_sim_cell:" k1.err >k1.act
if [ "$s1" -eq 1 ] && [ "$(wc -l <k1.act)" -eq 1 ] &&
   grep -q "exited with status 3 while activecal waited for the reply to measure 11" k1.act &&
   grep -q "continue it with --resume" k1.act; then
  ok "driver killed: one line, session kept"
else
  fail "driver killed: one line, session kept"; cat k1.err
fi
"$A" "${common[@]}" --driver="$cell --die_after=15 --served_log=$work/served.jsonl" \
  --session=killed --resume --json_out=killed.json >k2.txt 2>k2.err
[ $? -eq 1 ] && grep -q "continuing with round" k2.txt \
  && ok "driver killed again" || { fail "driver killed again"; cat k2.err; }
if "$A" "${common[@]}" --driver="$cell --served_log=$work/served.jsonl" \
    --session=killed --resume --json_out=killed.json --verbose >k3.txt 2>k3.err &&
   same_session ref killed && cmp -s ref.json killed.json; then
  ok "killed twice, resumed: the same bytes as uninterrupted"
else
  fail "killed twice, resumed: the same bytes as uninterrupted"; cat k3.err
fi
grep -q "(from the session log)" k3.txt && ok "verbose: answers from the log" \
  || fail "verbose: answers from the log"
# Every measurement the cell served is in the log exactly once.
python3 - <<'PY' && ok "served once, logged once" || fail "served once, logged once"
import collections, csv, json
served = [json.loads(l) for l in open('served.jsonl') if '"measurement"' in l]
ok = collections.Counter()
for s in served:
    if s['status'] == 'ok':
        ok[tuple(s['joints_rad']) + tuple(s['points_m'][0])] += 1
rows = list(csv.DictReader(open('killed/measurements.csv')))
logged = collections.Counter()
for r in rows:
    q = tuple(float(r['q%d_rad' % j]) for j in range(1, 7))
    logged[q + (float(r['x_m']), float(r['y_m']), float(r['z_m']))] += 1
assert ok == logged, (len(ok), len(logged))
assert max(logged.values()) == 1
excluded = [json.loads(l) for l in open('killed/excluded.jsonl')]
assert len(excluded) == sum(s['status'] != 'ok' for s in served)
assert len({e['pose_index'] for e in excluded}) == len(excluded)
PY

# --- activecal itself killed mid-round (SIGKILL), then resumed. ---
"$A" "${common[@]}" --driver="$cell --measure_delay_s=0.02" --session=crash \
  >c1.txt 2>&1 &
pid=$!
for _ in $(seq 1 500); do
  [ -f crash/measurements.csv ] && [ "$(wc -l <crash/measurements.csv)" -ge 16 ] && break
  sleep 0.01
done
kill -9 "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
if "$A" "${common[@]}" --driver="$cell" --session=crash --resume >c2.txt 2>c2.err &&
   same_session ref crash; then
  ok "activecal killed mid-round, resumed: the same bytes"
else
  fail "activecal killed mid-round, resumed: the same bytes"; cat c2.err
fi

# --- Bad driver output: one line naming it, nothing lost (the 4 answers
# before it logged), then resumed (two kinds: the others end the same way). ---
check_garbage() {  # <kind> <expected text> [flags]
  local kind="$1" want="$2"
  shift 2
  local dir="g_$kind"
  "$A" "${common[@]}" --driver="$cell --garbage=$kind --garbage_at=5" \
    --session="$dir" "$@" >"$dir.txt" 2>"$dir.err"
  local status=$?
  local answers
  answers=$(( $(wc -l <"$dir/measurements.csv") - 1 + $(cat "$dir/excluded.jsonl" 2>/dev/null | wc -l) ))
  if [ "$status" -eq 1 ] && [ "$(wc -l <"$dir.err")" -eq 1 ] &&
     grep -qF -- "$want" "$dir.err" && [ "$answers" -eq 4 ]; then
    ok "driver answers $kind: $(cut -c1-150 "$dir.err")"
  else
    fail "driver answers $kind (exit $status, $answers answers logged)"; cat "$dir.err"
  fi
  [ "$kind" = not_json ] || [ "$kind" = hang ] || return 0
  if "$A" "${common[@]}" --driver="$cell" --session="$dir" --resume >/dev/null 2>&1 &&
     same_session ref "$dir"; then
    ok "after $kind, resumed: the same bytes"
  else
    fail "after $kind, resumed: the same bytes"
  fi
}
check_garbage not_json "the reply to measure 5: not JSON: 'moving to pose 5'"
check_garbage nan "not JSON (NaN and Infinity are not JSON numbers"
check_garbage wrong_id "the reply to measure 5: id 6, expected 5"
check_garbage wrong_joints "joints_rad has 5 values, the robot has 6 joints"
check_garbage wrong_markers "points_m has 2 entries, one per marker expected (1"
check_garbage unknown_status "status 'done' is not ok, not_visible, unreachable or error"
check_garbage hang "no reply within 0.5 s while waiting for the reply to measure 5" \
  --driver_timeout_s=0.5

# --- Refusals, one line each. ---
expect_fail "resume with another seed" \
  "was made with seed 3, this run has 4: a session continues with the robot and options it was made with" \
  activecal_active --levels=3 --seed=4 --driver="$cell" --session=ref --resume
expect_fail "a new session over an old one" "holds a session already (session.json): continue it with --resume" \
  activecal_active "${common[@]}" --driver="$cell" --session=ref
expect_fail "resume without a session" "--resume: 'nothing' holds no session" \
  activecal_active "${common[@]}" --driver="$cell" --session=nothing --resume
expect_fail "a pipe in the driver command" "holds a character only a shell understands" \
  activecal_active "${common[@]}" --driver="$cell | tee log"
expect_fail "a driver that is not there" "cannot start 'no_such_driver': No such file or directory" \
  activecal_active "${common[@]}" --driver="no_such_driver --x"
expect_fail "compare with a driver" "--compare simulates one-shot designs" \
  activecal_active "${common[@]}" --driver="$cell" --compare
expect_fail "driver timeout <= 0" "--driver_timeout_s must be > 0, got 0" \
  activecal_active "${common[@]}" --driver="$cell" --driver_timeout_s=0

# --- TCP: the same cell listening; the same answers. ---
$CELL --seed=3 --not_visible_fraction=0.1 --listen=127.0.0.1:0 2>listen.err &
cell_pid=$!
port=""
for _ in $(seq 1 300); do
  port=$(sed -n 's/.*listening on 127.0.0.1:\([0-9]*\).*/\1/p' listen.err)
  [ -n "$port" ] && break
  sleep 0.01
done
if [ -n "$port" ] && "$A" "${common[@]}" --driver="tcp://127.0.0.1:$port" \
    --session=tcp >tcp.txt 2>tcp.err && same_session ref tcp; then
  ok "loop over TCP: the same measurements"
else
  fail "loop over TCP"; cat tcp.err listen.err
fi
kill "$cell_pid" 2>/dev/null
wait "$cell_pid" 2>/dev/null

# --- The Python example driver (no activecal import). ---
if "$A" --robot="$examples/driver_example_robot.yaml" --levels=3 \
    --driver="python3 $examples/driver_example.py" --noise_m=5e-5 \
    --target_rms_m=5e-5 --json_out=example.json --session=example \
    >example.txt 2>example.err; then
  python3 - <<'PY' && ok "the Python example driver" || fail "the Python example driver"
import json
j = json.load(open('example.json'))
assert j['termination_type'] == 'CONVERGENCE', j['message']
r = j['rounds'][-1]
# The fake cell is the robot file's truth: the true error is that predicted.
assert r['true_task_rms_m'] < 2 * r['predicted_task_rms_m'], r
assert j['nominal_true_task_rms_m'] > 100 * r['true_task_rms_m']
PY
else
  fail "the Python example driver"; cat example.err
fi

# --- The example adapted as a user would: an SDK that prints on stdout. ---
# Robot and tracker SDKs print ("connected", progress) and run programs that
# do; none of it may reach the protocol.
python3 - "$examples/driver_example.py" adapted_driver.py <<'PY'
import sys
text = open(sys.argv[1]).read()
old = "    return list(joints_rad)  # the fake robot reaches every pose exactly\n"
assert old in text
text = text.replace(old, "    print('sdk: moving to', joints_rad)\n"
                         "    os.system('echo sdk helper: settled')\n" + old)
text = text.replace("import json\n", "import json\nimport os\n", 1)
open(sys.argv[2], "w").write(text)
PY
if "$A" --robot="$examples/driver_example_robot.yaml" --levels=3 \
    --driver="python3 adapted_driver.py" --noise_m=5e-5 --max_rounds=2 \
    --target_rms_m=5e-5 --json_out=adapted.json >adapted.txt 2>adapted.err &&
   grep -q "sdk: moving to" adapted.err && grep -q "sdk helper: settled" adapted.err; then
  ok "the example with prints on stdout: they reach stderr, not the protocol"
else
  fail "the example with prints on stdout"; tail -3 adapted.err
fi

# --- A URDF cell with seeded perturbations; the design as a KRL program. ---
# The reflector on a bracket, off the flange axis (on the axis its offset
# could not be told from joint 7's).
printf 'markers:\n  - {name: smr, xyz: [0.06, 0.03, 0.1]}\n' >iiwa_frames.yaml
$CELL --robot="$data/kuka_iiwa14.urdf" --frames=iiwa_frames.yaml \
  --perturb_m=5e-4 --perturb_rad=5e-4 --seed=2 --truth_out=iiwa_truth.yaml \
  </dev/null >/dev/null 2>iiwa_cell.err
if [ -s iiwa_truth.yaml ] && grep -q "true:" iiwa_truth.yaml &&
   "$A" --robot=iiwa_truth.yaml --levels=3 --first_batch=16 --batch_size=8 \
     --target_rms_m=1.2e-4 --driver="$CELL --robot=iiwa_truth.yaml --seed=2" \
     --json_out=iiwa.json --program_out=iiwa_poses.src --program_language=krl \
     --controller="$data/controllers/kuka_iiwa14.yaml" >iiwa.txt 2>iiwa.err; then
  python3 - <<'PY' && ok "perturbed URDF cell, KRL program" || fail "perturbed URDF cell, KRL program"
import json, re
j = json.load(open('iiwa.json'))
assert j['termination_type'] == 'CONVERGENCE', j['message']
r = j['rounds'][-1]
assert r['true_task_rms_m'] < 3 * r['predicted_task_rms_m'], r
krl = open('iiwa_poses.src').read()
assert krl.startswith('DEF iiwa_poses( )')
moves = re.findall(r'PTP \{A1 ([-0-9.]+), A2 ([-0-9.]+).*E1 ([-0-9.]+)\}', krl)
assert len(moves) == len(j['measured_pose_indices']), len(moves)
assert krl.count('WAIT SEC') == len(moves)
PY
else
  fail "perturbed URDF cell, KRL program"; cat iiwa_cell.err iiwa.err
fi

cli_end
