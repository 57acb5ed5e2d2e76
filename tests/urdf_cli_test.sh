#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# The URDF workflow from the README on FIGAROH's UR10e data: URDF in, a
# calibrated URDF and frames out, evaluation with them; the programs' answers
# read back and checked for what they mean; bad URDF inputs end with status 1
# and one line.
#
#   tests/urdf_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

m="$data/figaroh_ur10e/measurements.csv"
# Identify the UR10e: registration of the unknown camera frame in closed
# form, the full parameter set reduced to what 23 6D poses separate (every
# one kept: model selection is accuracy_cli_test's).
expect_run "identify UR10e" identify.txt identify.err \
  activecal_identify --robot="$data/ur10e.urdf" --tip_link=tool0 \
  --model_selection=none \
  --measurements="$m" --rotation_weight=0.1 --urdf_out=cal.urdf \
  --frames_out=frames.yaml --model_out=cal.yaml --json_out=report.json
python3 - <<'EOF' && ok "identify report means what it says" || fail "identify report"
import json, math
r = json.load(open("report.json"))
assert r["parameter_set"] == "full", r["parameter_set"]
assert r["registered_base"] is True
held = {h["name"]: h["reason"] for h in r["held_fixed"]}
# The first joint's origin is the base frame's business.
for p in ["x", "y", "z", "rx", "ry", "rz", "offset"]:
    assert "B." in held["shoulder_pan_joint." + p], held["shoulder_pan_joint." + p]
free = [p["name"] for p in r["parameters"]]
assert len(free) == 30, len(free)
assert all(not n.startswith("shoulder_pan_joint.") for n in free)
assert all(("B." + c) in free for c in ["x", "y", "z", "rx", "ry", "rz"])
assert r["rms_residual_m"] < 0.004, r["rms_residual_m"]
assert r["termination_type"] == "CONVERGENCE"
EOF
grep -q "reloaded, it predicts every measured point within" identify.txt &&
  ok "urdf_out reload check printed" || fail "urdf_out reload check printed"
# Only joint origins changed in the calibrated URDF.
changed=$(diff "$data/ur10e.urdf" cal.urdf | grep '^>' | grep -vc '<origin')
[ "$changed" -eq 0 ] && ok "only <origin> lines changed" || fail "only <origin> lines changed"

# Evaluate the calibration with the URDF + frames and with the YAML model:
# the same predictions, the fit's residuals.
"$apps/activecal_evaluate" --robot=cal.urdf --tip_link=tool0 --frames=frames.yaml \
  --measurements="$m" --json_out=eval_urdf.json >/dev/null 2>eval.err || fail "evaluate URDF"
"$apps/activecal_evaluate" --robot=cal.yaml --measurements="$m" \
  --json_out=eval_yaml.json >/dev/null 2>>eval.err || fail "evaluate YAML"
"$apps/activecal_evaluate" --robot="$data/ur10e.urdf" --tip_link=tool0 \
  --measurements="$m" --json_out=eval_nominal.json >/dev/null 2>>eval.err ||
  fail "evaluate nominal"
python3 - <<'EOF' && ok "evaluation reports agree and mean what they say" || { fail "evaluation reports"; cat eval.err; }
import json, math
u = json.load(open("eval_urdf.json"))
y = json.load(open("eval_yaml.json"))
n = json.load(open("eval_nominal.json"))
assert u["num_measurements"] == 23 and u["num_position_measurements"] == 23
assert abs(u["rmse_m"] - y["rmse_m"]) < 1e-12, (u["rmse_m"], y["rmse_m"])
# rmse_m is the RMS of the per-row point errors; the axes add up to it.
rows = u["errors"]
rms = math.sqrt(sum(e["error_m"] ** 2 for e in rows) / len(rows))
assert abs(rms - u["rmse_m"]) < 1e-12
assert abs(math.sqrt(sum(v * v for v in u["rmse_xyz_m"])) - u["rmse_m"]) < 1e-12
assert u["max_m"] == max(e["error_m"] for e in rows)
assert u["p95_m"] <= u["max_m"] and u["mean_m"] <= u["rmse_m"]
assert u["rmse_m"] < 0.005, u["rmse_m"]
# The nominal model at the identity base frame is a metre off.
assert n["rmse_m"] > 0.5, n["rmse_m"]
assert u["orientation_rad"]["count"] == 23
EOF

# Registration alone tells a UR10e from a UR10: the UR10's link lengths leave
# residuals three times larger on the same data.
for r in ur10 ur10e; do
  "$apps/activecal_identify" --robot="$data/$r.urdf" --tip_link=tool0 \
    --measurements="$m" --rotation_weight=0.1 --parameter_set=registration \
    --json_out="reg_$r.json" >/dev/null 2>&1 || fail "registration $r"
done
python3 - <<'EOF' && ok "registration-only residuals: UR10 > 2 x UR10e" || fail "UR10 vs UR10e"
import json
a = json.load(open("reg_ur10.json"))["rms_residual_m"]
b = json.load(open("reg_ur10e.json"))["rms_residual_m"]
print("  registration-only RMS residual: UR10 %.2f mm, UR10e %.2f mm" % (a * 1e3, b * 1e3))
assert a > 2 * b, (a, b)
EOF

# Selecting 20 of the 23 measured poses for the UR10e ends (it once looped
# forever in the exchange step on such a small, nearly degenerate pool).
(echo "pose_index,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad"
 grep "^pose" "$m" | awk -F, '{print NR-1","$2","$3","$4","$5","$6","$7}') >pool.csv
if timeout 120 "$apps/activecal_select" --robot="$data/ur10e.urdf" --tip_link=tool0 \
  --pool_csv=pool.csv --num_poses=20 --measurement=pose --rotation_weight=0.1 \
  --algorithm=fedorov --restarts=8 --json_out=select.json >/dev/null 2>select.err; then
  python3 -c "
import json; j = json.load(open('select.json'))
assert len(j['pose_indices']) == 20 and len(set(j['pose_indices'])) == 20
assert j['efficiency_lower_bound'] > 0.5
" && ok "select 20 of 23 UR10e poses" || fail "select 20 of 23 UR10e poses (json)"
else
  fail "select 20 of 23 UR10e poses"; cat select.err
fi

# A 7-axis arm from a Sobol pool (a lattice of 5 levels would be 78,125
# poses): the design's poses are pool poses inside the limits, and the same
# on 1 and 2 threads.
for threads in 1 2; do
  if ! timeout 300 "$apps/activecal_select" --robot="$data/kuka_iiwa14.urdf" \
    --pool=sobol --pool_size=3000 --num_poses=60 --algorithm=fedorov \
    --threads=$threads --poses_csv=iiwa_$threads.csv \
    --json_out=iiwa_$threads.json >/dev/null 2>iiwa.err; then
    fail "iiwa Sobol pool ($threads threads)"; cat iiwa.err
  fi
done
python3 - <<'EOF2' && ok "iiwa Sobol pool" || fail "iiwa Sobol pool (json)"
import json, math
a = json.load(open("iiwa_1.json")); b = json.load(open("iiwa_2.json"))
assert a["pool"] == "sobol" and a["pool_size"] == 3000, a["pool"]
assert len(a["pose_indices"]) == 60 and len(set(a["pose_indices"])) == 60
assert all(0 <= i < 3000 for i in a["pose_indices"])
assert a["pose_indices"] == b["pose_indices"] and a["log10_det"] == b["log10_det"]
limits = [170, 120, 170, 120, 170, 120, 175]
for q in a["joint_angles_rad"]:
    assert len(q) == 7
    for v, l in zip(q, limits):
        assert abs(v) <= math.radians(l) + 1e-12, (v, l)
assert a["efficiency_lower_bound"] > 0.9, a["efficiency_lower_bound"]
EOF2
# Single precision: --pool_storage=float, and auto crossing its budget
# (--max_double_pool_mib=0: every pool is over it). The design's log det
# and the certificate are computed in double; the float run is the same on
# 1 and 2 threads.
for run in "float_1:--pool_storage=float --threads=1" \
           "float_2:--pool_storage=float --threads=2" \
           "auto:--max_double_pool_mib=0" "budget:--max_double_pool_mib=1000"; do
  name="${run%%:*}"
  # shellcheck disable=SC2086
  if ! timeout 300 "$apps/activecal_select" --robot="$data/kuka_iiwa14.urdf" \
    --pool=sobol --pool_size=3000 --num_poses=60 --algorithm=fedorov \
    ${run#*:} --json_out="iiwa_$name.json" >"iiwa_$name.out" 2>iiwa.err; then
    fail "iiwa float pool ($name)"; cat iiwa.err
  fi
done
python3 - <<'EOF2' && ok "iiwa single-precision pool" || fail "iiwa single-precision pool (json)"
import json
d = json.load(open("iiwa_1.json"))
f1 = json.load(open("iiwa_float_1.json")); f2 = json.load(open("iiwa_float_2.json"))
auto = json.load(open("iiwa_auto.json")); budget = json.load(open("iiwa_budget.json"))
assert d["pool_storage"] == "double" and budget["pool_storage"] == "double"
assert f1["pool_storage"] == "float" and auto["pool_storage"] == "float"
assert abs(f1["pool_storage_mib"] * 2 - d["pool_storage_mib"]) < 1e-9
# Thread count does not change a float run.
assert f1["pose_indices"] == f2["pose_indices"] and f1["log10_det"] == f2["log10_det"]
assert f1["pose_indices"] == auto["pose_indices"]
# Float storage changes the exchanges' path (a single-precision pool always
# swaps on the reduced pool and polishes in rounds, and rounding moves near
# ties), so the design may be another local optimum: measured 0 to +0.0087
# in log10 det over seeds 1-4 (docs/scaling.md). Its log det and
# certificate are computed in double from the exact blocks.
assert abs(f1["log10_det"] - d["log10_det"]) < 0.02, (f1["log10_det"], d["log10_det"])
assert f1["efficiency_lower_bound"] > 0.98, f1["efficiency_lower_bound"]
assert f1["log10_det_upper_bound"] >= f1["log10_det"]
assert budget["pose_indices"] == d["pose_indices"]
EOF2
grep -q "pool stored in single precision" iiwa_auto.out && ok "auto storage says so" \
  || fail "auto storage does not say it stored the pool in float"
expect_fail "float pool with eae" "--pool_storage=float needs --algorithm=fedorov or approx with the D criterion (got --algorithm=eae --criterion=det)" \
  activecal_select --pool_storage=float --algorithm=eae
expect_fail "bad pool storage" "--pool_storage must be auto, double or float, got 'half'" \
  activecal_select --pool_storage=half
expect_fail "unknown pool" "--pool must be lattice, sobol, random or measurable, got 'halton'" \
  activecal_select --pool=halton
expect_fail "empty pool" "--pool=sobol: pool size must be >= 1, got 0" \
  activecal_select --pool=sobol --pool_size=0
expect_fail "pool and pool_csv" "--pool=random and --pool_csv: choose one" \
  activecal_select --pool=random --pool_csv=pool.csv

# Issue #26, items 2, 10, 11, 12: --urdf_out on an arm whose joint origins
# sit at or near pitch 90 deg (rpy="1.5708 -1.5708 -1.5708", a prismatic
# first joint), as the edited file (URDF in) and as a URDF written from the
# model (its --model_out YAML in); then with a joint name holding an XML
# entity, and a YAML robot with a continuous joint and a link named like the
# generated fixed joint. Each written URDF must pass the reload check to
# 1e-9 m (the pitch-90 one missed it by 0.63 mm before the fix; the other
# three were refused). Measurements: the nominal arm's points (evaluate's
# errors against zeros) plus 0.3 mm of noise.
p90="$here/data/pitch90_arm.urdf"
python3 - <<'PY'
import math
rows = ["type,q1_m,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m"]
for i in range(30):
    q = [0.05 + 1.4 * ((i * 0.618034) % 1)]
    q += [2.0 * math.sin(1.3 * i + 0.9 * k) for k in range(5)]
    rows.append("position," + ",".join("%.6f" % v for v in q) + ",0,0,0")
open("p90_zero.csv", "w").write("\n".join(rows) + "\n")
PY
"$apps/activecal_evaluate" --robot="$p90" --measurements=p90_zero.csv \
  --json_out=p90_zero.json >/dev/null 2>p90.err || { fail "p90 nominal points"; cat p90.err; }
python3 - <<'PY'
import json, random
random.seed(1)
errors = json.load(open("p90_zero.json"))["errors"]  # predicted - 0
lines = open("p90_zero.csv").read().split("\n")
out = [lines[0]]
for row, e in zip(lines[1:], errors):
    point = [v + random.gauss(0, 3e-4) for v in e["error_xyz_m"]]
    out.append(",".join(row.split(",")[:7] + ["%.9f" % v for v in point]))
open("p90.csv", "w").write("\n".join(out) + "\n")
PY
# reload_ok <name> <stdout file>: the program passed its reload check, to
# 1e-9 m.
reload_ok() {
  local within
  within=$(sed -n 's/.*reloaded, it predicts every measured point within \([^ ]*\) m.*/\1/p' "$2")
  if [ -n "$within" ] &&
    python3 -c "import sys; sys.exit(0 if float('$within') <= 1e-9 else 1)"; then
    ok "$1 (reload within $within m)"
  else
    fail "$1"; cat "$2" p90.err
  fi
}
"$apps/activecal_identify" --robot="$p90" --measurements=p90.csv --parameter_set=offsets \
  --urdf_out=p90_cal.urdf --model_out=p90_cal.yaml --frames_out=p90_frames.yaml \
  >p90.out 2>p90.err
reload_ok "pitch-90 arm: --urdf_out of the URDF" p90.out
"$apps/activecal_identify" --robot=p90_cal.yaml --measurements=p90.csv --parameter_set=offsets \
  --urdf_out=p90_gen.urdf >p90_gen.out 2>p90.err
reload_ok "pitch-90 arm: --urdf_out of its YAML model" p90_gen.out
# The calibrated URDF (with its frames) and the YAML model predict the same
# points.
"$apps/activecal_evaluate" --robot=p90_cal.urdf --frames=p90_frames.yaml \
  --measurements=p90.csv --json_out=p90_eval_urdf.json >/dev/null 2>p90.err ||
  fail "evaluate p90 URDF"
"$apps/activecal_evaluate" --robot=p90_cal.yaml --measurements=p90.csv \
  --json_out=p90_eval_yaml.json >/dev/null 2>p90.err || fail "evaluate p90 YAML"
python3 - <<'PY' && ok "pitch-90 arm: calibrated URDF and YAML agree" || fail "pitch-90 URDF vs YAML"
import json
u = json.load(open("p90_eval_urdf.json")); y = json.load(open("p90_eval_yaml.json"))
assert u["num_measurements"] == y["num_measurements"] == 30
assert abs(u["rmse_m"] - y["rmse_m"]) < 1e-12, (u["rmse_m"], y["rmse_m"])
assert u["rmse_m"] < 1e-3, u["rmse_m"]
PY
sed 's/name="j2"/name="j2 \&amp; b"/' "$p90" >p90_entity.urdf
"$apps/activecal_identify" --robot=p90_entity.urdf --measurements=p90.csv --parameter_set=offsets \
  --urdf_out=p90_entity_cal.urdf >p90_entity.out 2>p90.err
reload_ok "joint name with an XML entity" p90_entity.out
grep -q 'name="j2 &amp; b"' p90_entity_cal.urdf && ok "entity name kept" || fail "entity name kept"
python3 - <<'PY'
import re
t = open("p90_cal.yaml").read()
t = t.replace("  - name: j3\n", "  - name: tip_fixed\n")
t = re.sub(r"(  - name: j4\n(?:    .*\n)*?    limits: )\[[^\]]*\]", r"\1[-.inf, .inf]", t)
open("p90_names.yaml", "w").write(t)
PY
"$apps/activecal_identify" --robot=p90_names.yaml --measurements=p90.csv --parameter_set=offsets \
  --urdf_out=p90_names.urdf >p90_names.out 2>p90.err
reload_ok "continuous joint and a link named tip_fixed" p90_names.out
if grep -q '<joint name="j4" type="continuous">' p90_names.urdf &&
  grep -q '<joint name="tip_fixed" type="revolute">' p90_names.urdf &&
  grep -q '<joint name="tip_fixed_2" type="fixed">' p90_names.urdf; then
  ok "continuous written as such, the generated joint's name unique"
else
  fail "continuous / unique names"; grep '<joint' p90_names.urdf
fi

# --- Bad input: one line, status 1. ---
printf '<robot name="x"><link name="a"></robot>' >bad.urdf
expect_fail "malformed URDF" "bad.urdf: not a valid URDF" \
  activecal_select --robot=bad.urdf
expect_fail "several leaves" "has 2 leaves (base, tool0): choose the chain's end with --tip_link" \
  activecal_select --robot="$data/ur10.urdf"
expect_fail "missing tip link" "no link named 'tool9'" \
  activecal_identify --robot="$data/ur10.urdf" --tip_link=tool9 --measurements="$m"
expect_fail "not a chain" "link 'base' is not below link 'tool0'" \
  activecal_evaluate --robot="$data/ur10.urdf" --base_link=tool0 --tip_link=base \
  --measurements="$m"
sed 's/name="elbow_joint" type="revolute"/name="elbow_joint" type="floating"/' \
  "$data/ur10.urdf" >floating.urdf
expect_fail "floating joint" "joint 'elbow_joint' on the chain is floating" \
  activecal_evaluate --robot=floating.urdf --tip_link=tool0 --measurements="$m"
expect_fail "chain links for a YAML robot" "--base_link and --tip_link choose a chain of a URDF file" \
  activecal_evaluate --robot="$data/puma560.yaml" --tip_link=tool0 --measurements="$m"
expect_fail "frames for the built-in PUMA" "--base_link, --tip_link and --frames need a --robot file" \
  activecal_select --frames=frames.yaml
expect_fail "frames for a DH robot" "--frames: frames.yaml:4:7: base: the robot's base is a hayati block, not a 6-DOF frame" \
  activecal_select --robot="$data/puma560.yaml" --frames=frames.yaml
grep -v '^#' "$m" | cut -d, -f1-6,8- >five_joints.csv
expect_fail "joint count" "five_joints.csv:1: header: the header has neither 'q6_rad' nor 'q6_deg' for joint 6" \
  activecal_evaluate --robot="$data/ur10e.urdf" --tip_link=tool0 --measurements=five_joints.csv
sed 's/^type,/type,marker,/; s/^pose,/pose,smr2,/' "$m" >markers.csv
expect_fail "unknown marker" "marker: 'smr2' is not a marker of the model (its markers: tool" \
  activecal_evaluate --robot="$data/ur10e.urdf" --tip_link=tool0 --measurements=markers.csv
expect_fail "unknown parameter set" "--parameter_set must be registration, offsets, full or file" \
  activecal_identify --robot="$data/ur10e.urdf" --tip_link=tool0 --measurements="$m" \
  --parameter_set=everything
expect_fail "evaluate without measurements" "--measurements is required" activecal_evaluate
sed 's/^type,/type,q7_rad,/; s/^pose,/pose,0,/' "$m" >seven.csv
expect_fail "a joint the robot does not have" "seven.csv:4: header: column 'q7_rad' is for joint 7, but robot 'ur10e' has 6 joints" \
  activecal_evaluate --robot="$data/ur10e.urdf" --tip_link=tool0 --measurements=seven.csv
printf '<robot name="x"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/><child link="b"/></joint></robot>' >nolimit.urdf
expect_fail "urdfdom's reason" "nolimit.urdf: not a valid URDF: Joint [j] is of type REVOLUTE but it does not specify limits" \
  activecal_select --robot=nolimit.urdf

cli_end
