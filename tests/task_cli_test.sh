#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Command-line tests of the task criterion (activecal_select
# --criterion=task_rms, --target_rms_m, --measured_csv) and of the active
# loop (activecal_active): reports read back and checked for their meaning,
# and every bad input answered with status 1 and one line on stderr.
#
#   tests/task_cli_test.sh <build/apps dir> <data dir> <check_task_json> <scripts dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
check="$(cd "$(dirname "$3")" && pwd)/$(basename "$3")"
scripts="$(cd "$4" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

json() {  # json <file> <python expression on j>
  python3 -c "import json,sys; j=json.load(open('$1')); print($2)"
}

S="$apps/activecal_select"
# --- A fixed size: the JSON's predicted RMS recomputed from its poses. ---
if "$S" --levels=3 --criterion=task_rms --num_poses=20 --noise_m=1e-4 \
    --json_out=task20.json --poses_csv=task20.csv >task20.txt; then
  "$check" task20.json && ok "task_rms 20 poses read back" || fail "task_rms 20 poses read back"
  grep -q "predicted task RMS" task20.txt && ok "printed" || fail "printed"
else
  fail "task_rms run"
fi
# The D-optimal design of the same size predicts a larger task RMS, and
# its report carries the same keys (recomputed too).
"$S" --levels=3 --criterion=d --algorithm=fedorov --num_poses=20 \
  --json_out=d20.json >/dev/null && "$check" d20.json && ok "d design read back" || fail "d design read back"
if [ "$(json task20.json "int(j['predicted_task_rms_m'] < json.load(open('d20.json'))['predicted_task_rms_m'])")" = 1 ]; then
  ok "task design predicts less than the D design of its size"
else
  fail "task design predicts less than the D design of its size"
fi
# Same design whatever the thread count.
"$S" --levels=3 --criterion=task_rms --num_poses=20 --threads=1 --json_out=t1.json >/dev/null
if [ "$(json t1.json "j['pose_indices']")" = "$(json task20.json "j['pose_indices']")" ]; then
  ok "threads"; else fail "threads"; fi

# --- The size from a target, the curve and its plot. ---
if "$S" --levels=3 --criterion=task_rms --target_rms_m=1.5e-4 --noise_m=1e-4 \
    --json_out=target.json --curve_csv=curve.csv >target.txt; then
  "$check" target.json && ok "target read back" || fail "target read back"
  # The curve CSV holds the JSON's curve.
  if [ "$(json target.json "len(j['predicted_task_rms_by_size_m'])")" = "$(($(wc -l <curve.csv) - 1))" ]; then
    ok "curve csv"; else fail "curve csv"; fi
  if command -v gnuplot >/dev/null; then
    "$scripts/plot_task_rms.sh" curve.csv 1.5e-4 curve.png task_rms && [ -s curve.png ] \
      && ok "curve plot" || fail "curve plot"
  fi
else
  fail "target run"
fi
# A target no design reaches: one line with the best reachable value.
expect_fail "unreachable target" "even all 729 pool poses together predict" \
  activecal_select --levels=3 --criterion=task_rms --target_rms_m=1e-9
expect_fail "target <= 0" "--target_rms_m must be > 0 (m), got 0" \
  activecal_select --levels=3 --criterion=task_rms --target_rms_m=0
expect_fail "negative target" "--target_rms_m must be > 0 (m), got -1" \
  activecal_select --levels=3 --criterion=task_rms --target_rms_m=-1
expect_fail "noise <= 0" "--noise_m must be > 0 (m), got 0" \
  activecal_select --levels=3 --criterion=task_rms --noise_m=0
expect_fail "unknown criterion" "--criterion must be det (d), svd or task_rms" \
  activecal_select --levels=3 --criterion=g
expect_fail "task algorithm" "--criterion=task_rms: --algorithm must be fedorov, greedy or approx" \
  activecal_select --levels=3 --criterion=task_rms --algorithm=eae

# --- Task poses: a subset of the lattice, and a file for another robot. ---
"$S" --levels=3 --algorithm=random --random_designs=1 --num_poses=40 \
  --poses_csv=task_poses.csv >/dev/null
"$S" --levels=3 --criterion=task_rms --num_poses=20 --task_poses_csv=task_poses.csv \
  --json_out=tp.json >/dev/null && ok "task poses csv" || fail "task poses csv"
if [ "$(json tp.json "j['num_task_poses']")" = 40 ]; then ok "task poses counted"; else fail "task poses counted"; fi
printf 'pose_index,q1_rad,q2_rad,q3_rad\n0,0.1,0.2,0.3\n' >three_joints.csv
expect_fail "task poses for another robot" "--task_poses_csv: three_joints.csv:1: header: the header has neither" \
  activecal_select --levels=3 --criterion=task_rms --task_poses_csv=three_joints.csv
printf 'pose_index,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,q7_rad\n0,0.1,0.2,0.3,0,0,0,0\n' >seven_joints.csv
expect_fail "task poses with a seventh joint" "--task_poses_csv: seven_joints.csv" \
  activecal_select --levels=3 --criterion=task_rms --task_poses_csv=seven_joints.csv

# --- Poses already measured count in M. ---
"$apps/activecal_simulate" --poses_csv=task20.csv --noise_m=1e-4 --seed=2 \
  --out=measured.csv >/dev/null
if "$S" --levels=3 --criterion=task_rms --num_poses=10 --measured_csv=measured.csv \
    --json_out=next.json >next.txt; then
  "$check" next.json && ok "next batch read back" || fail "next batch read back"
  # 20 measured + 10 new predict less than the 20 alone.
  if [ "$(json next.json "int(j['predicted_task_rms_m'] < json.load(open('task20.json'))['predicted_task_rms_m'])")" = 1 ]; then
    ok "measured poses count"; else fail "measured poses count"; fi
else
  fail "next batch run"
fi
# A next batch for a target, counting the measured poses.
t20=$(json task20.json "j['predicted_task_rms_m']")
target=$(python3 -c "print($t20 * 0.6)")
"$S" --levels=3 --criterion=task_rms --target_rms_m="$target" --measured_csv=measured.csv \
  --json_out=next_target.json >/dev/null && "$check" next_target.json \
  && ok "next batch for a target" || fail "next batch for a target"
if [ "$(json next_target.json "int(j['num_poses'] > 0 and j['predicted_task_rms_by_size_m'][0][0] == 0)")" = 1 ]; then
  ok "the measured poses alone are tried first"; else fail "the measured poses alone are tried first"; fi
# A target the measured poses already meet: no new pose.
"$S" --levels=3 --criterion=task_rms --target_rms_m="$(python3 -c "print($t20 * 1.01)")" \
  --measured_csv=measured.csv --json_out=none.json >/dev/null
if [ "$(json none.json "j['num_poses']")" = 0 ]; then ok "no new pose needed"; else fail "no new pose needed"; fi
# Per-measurement sigmas weight the rows: the same file with sigma 10x
# larger (per axis, as one sigma_m column, as u95_mm = 2 mm) predicts more,
# the three forms alike; a stated sigma equal to --noise_m changes nothing.
python3 - <<'PY'
import csv
rows = list(csv.DictReader(open('measured.csv')))
base = list(rows[0].keys())
for name, cols, val in (('measured_sigma.csv', ('sigma_x_m', 'sigma_y_m', 'sigma_z_m'), '0.001'),
                        ('measured_sigma_m.csv', ('sigma_m',), '0.001'),
                        ('measured_u95.csv', ('u95_mm',), '2'),
                        ('measured_noise.csv', ('sigma_m',), '0.0001')):
    w = csv.DictWriter(open(name, 'w', newline=''), fieldnames=base + list(cols), lineterminator='\n')
    w.writeheader()
    w.writerows([dict(r, **{c: val for c in cols}) for r in rows])
PY
for f in sigma sigma_m u95 noise; do
  "$S" --levels=3 --criterion=task_rms --num_poses=10 --measured_csv=measured_$f.csv \
    --json_out=next_$f.json >/dev/null || fail "measured with $f columns run"
done
if [ "$(json next_sigma.json "int(j['predicted_task_rms_m'] > 1.5 * json.load(open('next.json'))['predicted_task_rms_m'])")" = 1 ]; then
  ok "measurement sigmas weight the prior"; else fail "measurement sigmas weight the prior"; fi
if [ "$(json next_sigma.json "int(all(abs(j['predicted_task_rms_m'] - json.load(open(f))['predicted_task_rms_m']) <= 1e-9 * j['predicted_task_rms_m'] for f in ('next_sigma_m.json', 'next_u95.json')))")" = 1 ]; then
  ok "sigma_m and u95_mm columns weight as sigma_x/y/z_m"; else fail "sigma_m and u95_mm columns weight as sigma_x/y/z_m"; fi
if [ "$(json next_noise.json "int(abs(j['predicted_task_rms_m'] - json.load(open('next.json'))['predicted_task_rms_m']) <= 1e-9 * j['predicted_task_rms_m'])")" = 1 ]; then
  ok "a stated sigma equal to --noise_m"; else fail "a stated sigma equal to --noise_m"; fi
printf 'type,q1_rad,q2_rad,q3_rad,x_m,y_m,z_m\nposition,0.1,0.2,0.3,1,2,3\n' >wrong_robot.csv
expect_fail "measured rows for another robot" "--measured_csv: wrong_robot.csv" \
  activecal_select --levels=3 --criterion=task_rms --measured_csv=wrong_robot.csv
expect_fail "measured with the D criterion" "--measured_csv needs --criterion=task_rms" \
  activecal_select --levels=3 --measured_csv=measured.csv

# --- A URDF arm on a rail (7 revolute axes and a prismatic one), a pool
# from CSV: the printed design gives the rail in mm, the others in deg, and
# matches the JSON. ---
python3 - <<'PY'
import random
random.seed(3)
with open('rail_pool.csv', 'w') as f:
    f.write('pose_index,' + ','.join('q%d_rad' % i for i in range(2, 9)) + ',q1_m\n')
    for k in range(300):
        f.write('%d,' % k + ','.join('%.4f' % random.uniform(-2.0, 2.0) for _ in range(7))
                + ',%.3f\n' % random.uniform(0, 1.0))
PY
if "$S" --robot="$here/data/arm7_rail.urdf" --tip_link=tcp --pool_csv=rail_pool.csv \
    --criterion=task_rms --num_poses=30 --json_out=rail.json >rail.txt 2>/dev/null; then
  # (check_task_json recomputes for the built-in PUMA's lattice only.)
  python3 - <<'PY' && ok "7 axes on a rail: indices and joints" || fail "7 axes on a rail: indices and joints"
import csv, json
j = json.load(open('rail.json'))
rows = {int(r['pose_index']): r for r in csv.DictReader(open('rail_pool.csv'))}
assert j['num_poses'] == len(j['pose_indices']) == len(set(j['pose_indices'])) == 30
assert j['predicted_task_rms_m'] > 0 and 0 < j['efficiency_lower_bound'] <= 1
for index, q in zip(j['pose_indices'], j['joint_angles_rad']):
    r = rows[index]
    want = [float(r['q1_m'])] + [float(r['q%d_rad' % i]) for i in range(2, 9)]
    assert all(abs(a - b) < 1e-12 for a, b in zip(q, want)), (index, q, want)
PY
  python3 - <<'PY' && ok "rail printed in mm" || fail "rail printed in mm"
import json, math
j = json.load(open('rail.json'))
lines = open('rail.txt').read().splitlines()
h = [k for k, l in enumerate(lines) if 'joints (deg; prismatic mm)' in l]
assert h, 'no header naming the prismatic unit'
for k, (index, q) in enumerate(zip(j['pose_indices'], j['joint_angles_rad'])):
    f = lines[h[0] + 1 + k].split()
    assert int(f[1]) == index, (f, index)
    shown = [float(x) for x in f[2:]]
    want = [q[0] * 1000] + [v * 180 / math.pi for v in q[1:]]
    assert all(abs(a - b) < 2e-3 for a, b in zip(shown, want)), (shown, want)
PY
else
  fail "7 axes on a rail run"
fi

# --- The active loop: rounds read back. ---
A="$apps/activecal_active"
if "$A" --levels=3 --target_rms_m=1e-4 --compare --json_out=active.json >active.txt; then
  python3 - <<'PY' && ok "active loop report" || fail "active loop report"
import json
j = json.load(open('active.json'))
r = j['rounds']
assert j['termination_type'] == 'CONVERGENCE', j['message']
# Poses so far grow by the batch sizes: 12, then 6 per round.
assert [x['num_poses'] for x in r] == [12 + 6 * k for k in range(len(r))], r
assert all(len(x['batch']) == (12 if k == 0 else 6) for k, x in enumerate(r))
# Every pose is measured once.
m = j['measured_pose_indices']
assert len(m) == len(set(m)) == r[-1]['num_poses']
# The target is met by the last round only.
assert r[-1]['predicted_task_rms_m'] <= j['target_rms_m']
assert all(x['predicted_task_rms_m'] > j['target_rms_m'] for x in r[:-1])
# The first identification moves the model by about its nominal error;
# the true error then falls far below it.
assert abs(r[0]['parameter_change_task_rms_m'] - j['nominal_true_task_rms_m']) < 0.01 * j['nominal_true_task_rms_m']
assert r[-1]['true_task_rms_m'] < 1e-3 * j['nominal_true_task_rms_m']
# The prediction is of the right size: the true error within a factor 3.
assert all(x['true_task_rms_m'] < 3 * x['predicted_task_rms_m'] for x in r)
# The model fits: residual sigma about the noise, no round flagged.
assert all(x['residual_sigma_m'] is None or
           0.3 * j['noise_m'] < x['residual_sigma_m'] < 2 * j['noise_m'] for x in r), r
assert not any(x['residuals_exceed_noise'] for x in r)
for name in ('d_optimal_at_nominal', 'task_optimal_at_nominal', 'random'):
    o = j['one_shot'][name]
    assert o['num_poses'] == r[-1]['num_poses'], name
PY
else
  fail "active loop run"
fi
grep -v "true:" "$data/puma560.yaml" >notruth.yaml
expect_fail "active without true values" "--robot has no true values" \
  activecal_active --robot=notruth.yaml
expect_fail "active target <= 0" "activecal_active: error: --target_rms_m must be > 0" \
  activecal_active --levels=3 --target_rms_m=0
expect_fail "active noise <= 0" "activecal_active: error: --noise_m must be > 0" \
  activecal_active --levels=3 --noise_m=0
expect_fail "active first batch <= 0" "activecal_active: error: --first_batch must be > 0" \
  activecal_active --levels=3 --first_batch=0

cli_end
