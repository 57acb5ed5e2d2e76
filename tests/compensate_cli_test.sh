#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# activecal_compensate end to end: the PUMA loop select -> simulate ->
# identify -> compensate with the programs, the true robot's error at the
# compensated joints against what the program meant (before and after), the
# output CSV and JSON read back and checked for what they mean, Cartesian
# targets, thread-count independence, and bad input (status 1, one line).
#
#   tests/compensate_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

puma="$data/puma560.yaml"

# expect_one_line <name> <status> <expected status> <stderr file> <grep
# flags> <pattern>: the status is the expected one and the stderr file one
# line that matches the pattern.
expect_one_line() {
  if [ "$2" -eq "$3" ] && [ "$(wc -l <"$4")" -eq 1 ] && grep "$5" -- "$6" "$4"; then
    ok "$1: $(cut -c1-100 "$4")"
  else
    fail "$1 (status $2)"; cat "$4"
  fi
}

# all_converged <compensate JSON> <number of targets> <max joint change>:
# that many targets, all converged, no joint changed by more than that.
all_converged() {
  python3 - "$@" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j['all_converged'] and j['num_targets'] == int(sys.argv[2]), j['message']
assert j['max_joint_change'] <= float(sys.argv[3]), j['max_joint_change']
PY
}

# --- the loop -------------------------------------------------------------
"$apps/activecal_select" --robot="$puma" --algorithm=fedorov \
  --poses_csv=poses.csv >select.txt 2>&1 || { fail "select"; cat select.txt; }
"$apps/activecal_simulate" --robot="$puma" --poses_csv=poses.csv \
  --noise_m=0.0001 --seed=3 --out=meas.csv >/dev/null 2>&1 || fail "simulate"
"$apps/activecal_identify" --robot="$puma" --measurements=meas.csv \
  --model_out=calibrated.yaml >identify.txt 2>&1 || { fail "identify"; cat identify.txt; }

# A program of 2,000 random configurations inside the joint ranges, in the
# pendant's degrees, with labels of its own.
python3 - <<'EOF'
import random
random.seed(1)
lim = [(-250, 70), (-110, 170), (-133, 133), (-100, 100), (-142, 142), (-176, 356)]
with open("program.csv", "w") as f:
    f.write("pose_index," + ",".join("q%d_deg" % (j + 1) for j in range(6)) + "\n")
    for i in range(2000):
        f.write(str(5000 + 3 * i) + "," +
                ",".join(repr(lo + (hi - lo) * random.random()) for lo, hi in lim) + "\n")
EOF

"$apps/activecal_compensate" --robot=calibrated.yaml --nominal="$puma" \
  --poses_csv=program.csv --out=comp.csv --json_out=comp.json --threads=2 \
  >comp.txt 2>comp.err
status=$?
# Some targets of a program that spans the whole joint ranges need a joint
# beyond its limit on the real robot: exit 2, one line, files complete.
expect_one_line "compensate: exit 2 and one line when some targets fail" \
  "$status" 2 comp.err -q "targets are not converged, written with their status to comp.csv: [0-9]* limit (the first, target [0-9]*, pose_index [0-9]*: "
# The true robot at the program's and at the compensated joints (the poses
# CSV reader checks every compensated configuration against the limits).
"$apps/activecal_simulate" --robot="$puma" --poses_csv=program.csv --noise_m=0 \
  --out=true_program.csv >/dev/null 2>&1 || fail "simulate the program"
if "$apps/activecal_simulate" --robot="$puma" --poses_csv=comp.csv --noise_m=0 \
  --out=true_comp.csv >/dev/null 2>sim.err; then
  ok "every compensated configuration reads back inside the joint limits"
else
  fail "compensated configurations"; cat sim.err
fi
# The calibrated model's own error at the compensated joints, from
# activecal_evaluate: the target points as measurements.
python3 - <<'EOF'
import csv, json
rep = json.load(open("comp.json"))
rows = list(csv.DictReader(l for l in open("comp.csv") if not l.startswith("#")))
with open("targets_as_measurements.csv", "w") as f:
    f.write("type," + ",".join("q%d_rad" % (j + 1) for j in range(6)) + ",x_m,y_m,z_m\n")
    for r, t in zip(rows, rep["targets"]):
        if t["status"] == "converged":
            f.write("position," + ",".join(r["q%d_rad" % (j + 1)] for j in range(6)) + "," +
                    ",".join(repr(v) for v in t["target_m"]) + "\n")
EOF
"$apps/activecal_evaluate" --robot=calibrated.yaml \
  --measurements=targets_as_measurements.csv --json_out=eval.json >/dev/null 2>&1 ||
  fail "evaluate the compensated program"

python3 - <<'EOF' && ok "compensated CSV and JSON mean what they say; true error drops" || fail "compensation results"
import csv, json, math
rep = json.load(open("comp.json"))
rows = list(csv.DictReader(l for l in open("comp.csv") if not l.startswith("#")))
prog = list(csv.DictReader(open("program.csv")))
def points(fn):
    return [tuple(float(r[k]) for k in ("x_m", "y_m", "z_m"))
            for r in csv.DictReader(l for l in open(fn) if not l.startswith("#"))]
true_prog, true_comp = points("true_program.csv"), points("true_comp.csv")
t = rep["targets"]
assert rep["num_targets"] == 2000 and len(rows) == 2000 and len(t) == 2000
assert rep["match"] == "position" and rep["all_converged"] is False
counts = {}
for s in ("converged", "singular", "limit", "unreachable", "invalid"):
    counts[s] = sum(1 for x in t if x["status"] == s)
    assert counts[s] == rep["num_" + s], s
assert sum(counts.values()) == 2000
assert counts["converged"] >= 1600, counts
lims = [(-250, 70), (-110, 170), (-133, 133), (-100, 100), (-142, 142), (-176, 356)]
for i, (r, p, x) in enumerate(zip(rows, prog, t)):
    # Same labels, same order; JSON and CSV agree.
    assert r["pose_index"] == p["pose_index"] == str(x["pose_index"]), i
    assert r["status"] == x["status"], i
    assert abs(float(r["position_error_m"]) - x["position_error_m"]) <= 1e-15 + 1e-9 * x["position_error_m"]
    for j in range(6):
        q = float(r["q%d_rad" % (j + 1)])
        assert q == x["joints"][j], (i, j)
        # Pendant column in degrees, inside the limits.
        assert abs(float(r["q%d_deg" % (j + 1)]) - math.degrees(q)) < 1e-9
        assert lims[j][0] - 1e-9 <= math.degrees(q) <= lims[j][1] + 1e-9
        start = math.radians(float(p["q%d_deg" % (j + 1)]))
        assert abs(x["start_joints"][j] - start) < 1e-12
        assert abs(x["joint_change"][j] - (q - start)) < 1e-12
    assert abs(x["max_joint_change"] - max(abs(c) for c in x["joint_change"])) < 1e-15
    if x["status"] == "converged":
        assert x["position_error_m"] <= 1e-9 and x["message"] == ""
    else:
        assert x["position_error_m"] > 1e-9 and x["message"], x
conv = [i for i, x in enumerate(t) if x["status"] == "converged"]
def rms(v): return math.sqrt(sum(e * e for e in v) / len(v))
before = [math.dist(true_prog[i], t[i]["target_m"]) for i in conv]
after = [math.dist(true_comp[i], t[i]["target_m"]) for i in conv]
print("  PUMA: %d of 2000 converged (%s); true error RMS %.1f mm (max %.1f) before, %.4f mm (max %.4f) after"
      % (len(conv), counts, 1e3 * rms(before), 1e3 * max(before), 1e3 * rms(after), 1e3 * max(after)))
assert rms(before) > 0.1, rms(before)
assert rms(after) < 0.3e-3, rms(after)
# The calibrated model itself reaches the targets (activecal_evaluate).
ev = json.load(open("eval.json"))
assert ev["num_measurements"] == len(conv)
assert ev["max_m"] < 1e-8, ev["max_m"]
EOF

# Thread count does not change a byte.
"$apps/activecal_compensate" --robot=calibrated.yaml --nominal="$puma" \
  --poses_csv=program.csv --out=comp1.csv --threads=1 >/dev/null 2>&1
cmp -s comp.csv comp1.csv && ok "--threads=1 and 2 write the same file" || fail "thread count"

# Nominal == calibrated: the program is left unchanged, exit 0.
if "$apps/activecal_compensate" --robot="$puma" --nominal="$puma" \
  --poses_csv=poses.csv --out=same.csv --match=pose --json_out=same.json >same.txt 2>&1; then
  python3 - <<'EOF' && ok "identical models leave the program unchanged" || fail "identical models"
import csv, json
a = list(csv.DictReader(open("poses.csv")))
b = list(csv.DictReader(open("same.csv")))
assert len(a) == len(b)
for r, s in zip(a, b):
    assert r["pose_index"] == s["pose_index"] and s["status"] == "converged"
    for j in range(6):
        assert abs(float(r["q%d_rad" % (j + 1)]) - float(s["q%d_rad" % (j + 1)])) <= 1e-12
j = json.load(open("same.json"))
assert j["all_converged"] is True and j["max_joint_change"] <= 1e-12
EOF
else
  fail "identical models"; cat same.txt
fi

# A URDF robot with a frames file (base and two markers away from tool0),
# nominal == calibrated geometry: unchanged too. The markers are metrology
# like the base, so --frames applies to --nominal as well (without it the
# program meant tool0's origin and the joints moved by up to 0.6 rad).
ur="$data/ur10e.urdf"
cat >frames.yaml <<'EOF2'
angle_unit: rad
base: {xyz: [1.2, 0.3, 0.1], rpy: [0.01, -0.02, 1.0]}
markers:
  - {name: smr, xyz: [0.02, 0.01, 0.15]}
  - {name: smr2, xyz: [-0.05, 0.03, 0.1]}
EOF2
"$apps/activecal_select" --robot="$ur" --tip_link=tool0 --frames=frames.yaml \
  --algorithm=fedorov --num_poses=30 --poses_csv=ur_prog.csv >/dev/null 2>&1 ||
  fail "select on the UR10e"
for m in smr smr2; do
  if "$apps/activecal_compensate" --robot="$ur" --tip_link=tool0 --frames=frames.yaml \
    --nominal="$ur" --marker=$m --poses_csv=ur_prog.csv --out=ur_same.csv \
    --json_out=ur_same.json >ur_same.txt 2>&1 &&
    all_converged ur_same.json 30 1e-12; then
    ok "URDF + frames, marker $m: identical geometry leaves the program unchanged"
  else
    fail "URDF + frames, marker $m, identical geometry"; cat ur_same.txt
  fi
done

# Issue 26: forgetting --frames with a URDF robot moved joints by up to
# 3 deg without a word. Now the first line on stderr says what is assumed
# (and with --frames nothing is said).
"$apps/activecal_compensate" --robot="$ur" --tip_link=tool0 --nominal="$ur" \
  --poses_csv=ur_prog.csv --out=ur_noframes.csv >ur_noframes.txt 2>ur_noframes.err
nstatus=$?
expect_one_line "URDF without --frames: one note first on stderr" \
  "$nstatus" 0 ur_noframes.err -qF "activecal_compensate: note: --robot=$ur has no --frames: the device frame is taken as the chain's base link and the marker as the origin of the tip link 'tool0', with no offset"
"$apps/activecal_compensate" --robot="$ur" --tip_link=tool0 --frames=frames.yaml \
  --nominal="$ur" --poses_csv=ur_prog.csv --out=ur_frames.csv >/dev/null 2>ur_frames.err
[ ! -s ur_frames.err ] && ok "URDF with --frames: no note" ||
  { fail "URDF with --frames: stderr not empty"; cat ur_frames.err; }
# Cartesian targets: the meant points of the first 40 converged targets,
# with the program's joints as starts, give the same joints as the program
# path; without starts, each starts from the previous result.
python3 - <<'EOF'
import csv, json
rep = json.load(open("comp.json"))
t = [x for x in rep["targets"] if x["status"] == "converged"][:40]
with open("targets.csv", "w") as f:
    f.write("pose_index,x_m,y_m,z_m," + ",".join("q%d_rad" % (j + 1) for j in range(6)) + "\n")
    for x in t:
        f.write(",".join(str(v) for v in [x["pose_index"]] + x["target_m"] + x["start_joints"]) + "\n")
with open("points.csv", "w") as f:
    f.write("x_m,y_m,z_m\n")
    for x in t:
        f.write(",".join(repr(v) for v in x["target_m"]) + "\n")
EOF
"$apps/activecal_compensate" --robot=calibrated.yaml --targets_csv=targets.csv \
  --out=tcomp.csv --json_out=tcomp.json >/dev/null 2>&1 || fail "targets CSV"
"$apps/activecal_compensate" --robot=calibrated.yaml --targets_csv=points.csv \
  --out=pcomp.csv --json_out=pcomp.json >/dev/null 2>pcomp.err
pstatus=$?
python3 - <<'EOF' && ok "Cartesian targets: same joints as the joint program; a path without starts" || fail "Cartesian targets"
import json
rep = {x["pose_index"]: x for x in json.load(open("comp.json"))["targets"]}
t = json.load(open("tcomp.json"))
assert t["all_converged"] and t["num_targets"] == 40
for x in t["targets"]:
    y = rep[x["pose_index"]]
    assert max(abs(a - b) for a, b in zip(x["joints"], y["joints"])) < 1e-7, x["pose_index"]
p = json.load(open("pcomp.json"))
assert [x["pose_index"] for x in p["targets"]] == list(range(40))
assert p["num_converged"] + p["num_limit"] + p["num_unreachable"] + p["num_singular"] + p["num_iteration_cap"] == 40
assert p["num_converged"] >= 30, p["num_converged"]
for x in p["targets"]:
    assert "start_joints" not in x
    if x["status"] == "converged":
        assert x["position_error_m"] <= 1e-9
EOF

# Issue 26: the targets CSV dropped columns it did not know, start joints
# by joint name among them. It reads the measurements CSV's columns (here
# the UR10e's joints by name, mm), names the rest in a note, and refuses
# them with --columns_strict.
python3 - <<'EOF'
import json
rep = json.load(open("ur_same.json"))
names = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
         "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
with open("ur_targets.csv", "w") as f:
    f.write("pose_index,x_mm,y_mm,z_mm,temperature_c," +
            ",".join(n + "_rad" for n in names) + "\n")
    for t in rep["targets"][:5]:
        f.write(",".join(repr(v) for v in [t["pose_index"]] +
                         [1000 * x for x in t["target_m"]] + [21.5] +
                         t["start_joints"]) + "\n")
EOF
"$apps/activecal_compensate" --robot="$ur" --tip_link=tool0 --frames=frames.yaml \
  --marker=smr2 --targets_csv=ur_targets.csv --out=ur_t.csv --json_out=ur_t.json \
  >ur_t.txt 2>ur_t.err
tstatus=$?
if [ "$tstatus" -eq 0 ] && [ ! -s ur_t.err ] &&
  grep -q "activecal_compensate: note: ur_targets.csv: ignored 1 column activecal does not read: temperature_c" ur_t.txt &&
  # The start joints were read (by name): the program's own joints reach
  # the targets, so they are kept (to the mm rounding of the points).
  all_converged ur_t.json 5 1e-6; then
  ok "targets CSV: joints by name and mm read, temperature_c named in a note"
else
  fail "targets CSV with joint names (status $tstatus)"; cat ur_t.txt ur_t.err
fi
expect_fail "targets CSV column not read, --columns_strict" \
  "--targets_csv: ur_targets.csv:1: header: column 'temperature_c' activecal does not read (strict columns" \
  activecal_compensate --robot="$ur" --tip_link=tool0 --frames=frames.yaml \
  --marker=smr2 --targets_csv=ur_targets.csv --out=x.csv --columns_strict

# A target outside the workspace: reported per target, exit 2, one line.
printf 'pose_index,x_m,y_m,z_m\n7,0.3,19.9,0.2\n8,5,30,2\n' >far.csv
"$apps/activecal_compensate" --robot=calibrated.yaml --targets_csv=far.csv \
  --out=far_out.csv --json_out=far.json >/dev/null 2>far.err
fstatus=$?
if [ "$fstatus" -eq 2 ] && [ "$(wc -l <far.err)" -eq 1 ] &&
  grep -q "1 unreachable (the first, target 1, pose_index 8: out of reach" far.err &&
  python3 -c "
import json, csv
j = json.load(open('far.json'))['targets']
assert j[1]['status'] == 'unreachable' and 'out of reach' in j[1]['message'], j[1]
rows = list(csv.DictReader(open('far_out.csv')))
assert [r['pose_index'] for r in rows] == ['7', '8'] and rows[1]['status'] == 'unreachable'
"; then
  ok "target outside the workspace: $(cat far.err)"
else
  fail "target outside the workspace (status $fstatus)"; cat far.err
fi

# --- bad input: status 1, one line ----------------------------------------
rm -f written_first.csv
expect_fail "unwritable --json_out" "--json_out: cannot write 'no_such_dir/r.json'" \
  activecal_compensate --robot=calibrated.yaml --nominal="$puma" --poses_csv=program.csv \
  --out=written_first.csv --json_out=no_such_dir/r.json
[ ! -e written_first.csv ] && ok "unwritable --json_out: --out not written" ||
  fail "unwritable --json_out: --out was written before the failure"

printf 'x_m,y_m,z_m\n0.3,19.9,0.2\n0.3,nan,0.2\n' >nan.csv
expect_fail "NaN in a target" "nan.csv:3: y_m: must be finite, got 'nan'" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=nan.csv --out=x.csv
cut -d, -f1-6 program.csv >five.csv
expect_fail "program with 5 joints for a 6-joint robot" \
  "five.csv:1: header: the header has neither 'q6_rad' nor 'q6_deg' for joint 6" \
  activecal_compensate --robot=calibrated.yaml --nominal="$puma" --poses_csv=five.csv --out=x.csv
sed -e '1s/$/,q7_deg/' -e '2,$s/$/,0/' program.csv >seven.csv
expect_fail "program with 7 joints for a 6-joint robot" \
  "column 'q7_deg' is for joint 7, but robot 'puma560_sun_hollerbach' has 6 joints" \
  activecal_compensate --robot=calibrated.yaml --nominal="$puma" --poses_csv=seven.csv --out=x.csv
awk '/name: L3/{f=1} f&&/joint: revolute/{sub("revolute","prismatic");f=0} {print}' "$puma" >prismatic.yaml
expect_fail "calibrated and nominal models with different chains" \
  "--robot and --nominal: joint 3: the calibrated model's is revolute, the nominal model's prismatic: not the same robot" \
  activecal_compensate --robot=calibrated.yaml --nominal=prismatic.yaml --poses_csv=program.csv --out=x.csv
python3 - "$puma" <<'EOF'
import sys
text = open(sys.argv[1]).read()
a = text.index("  - name: L6")
b = text.index("# The measured point")
open("five_links.yaml", "w").write(text[:a] + text[b:])
EOF
expect_fail "a nominal model with 5 joints" \
  "--robot and --nominal: the calibrated model 'puma560_sun_hollerbach' has 6 joints, the nominal model 'puma560_sun_hollerbach' 5: not the same robot" \
  activecal_compensate --robot=calibrated.yaml --nominal=five_links.yaml --poses_csv=program.csv --out=x.csv
expect_fail "pose match without orientations" \
  "--match=pose needs the target orientations: --targets_csv points.csv has no rx_rad, ry_rad, rz_rad columns" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=points.csv --match=pose --out=x.csv
expect_fail "unknown match" "--match must be position or pose, got 'xyz'" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=points.csv --match=xyz --out=x.csv
expect_fail "no program" "give exactly one of --poses_csv (joint targets) and --targets_csv" \
  activecal_compensate --robot=calibrated.yaml --out=x.csv
expect_fail "joint program without nominal" "--poses_csv needs --nominal" \
  activecal_compensate --robot=calibrated.yaml --poses_csv=program.csv --out=x.csv
expect_fail "no output" "--out is required" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=points.csv
expect_fail "iteration cap 0" "max_iterations must be >= 1, got 0" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=points.csv --out=x.csv --max_iterations=0
expect_fail "joint weights of another robot" \
  "joint_weights: expected 6 weights (one per joint of 'puma560_sun_hollerbach'), got 2" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=points.csv --out=x.csv --joint_weights=1,2
expect_fail "a joint weight of 0" "joint_weights[2] must be finite and > 0, got 0" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=points.csv --out=x.csv --joint_weights=1,1,0,1,1,1
expect_fail "a joint weight not a number" "--joint_weights: 'x' is not a number" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=points.csv --out=x.csv --joint_weights=1,x,1,1,1,1
expect_fail "unknown marker" "--marker: 'smr9' is not a marker of robot" \
  activecal_compensate --robot=calibrated.yaml --targets_csv=points.csv --out=x.csv --marker=smr9
[ ! -e x.csv ] && ok "no output written on bad input" || fail "output written on bad input"

cli_end
