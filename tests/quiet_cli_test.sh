#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# --quiet's one result line of the programs other than identify and select
# (those are in output_cli_test.sh and select_cli_test.sh): the line is the
# last on stdout without --quiet and the only one with it, its figures are
# the JSON's and of a plausible size, and the files written are
# byte-identical either way. The case is 6D (position + orientation): pose
# measurements of a perturbed UR10e at FIGAROH's 23 configurations.
#
#   tests/quiet_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

m="$data/figaroh_ur10e/measurements.csv"

# Runs "$@" here and, with --quiet, in q/ (input paths absolute, output
# paths relative: the same names in both); checks the one line, that it is
# the last line without --quiet, and that every listed file is
# byte-identical.  quiet_pair NAME "FILE..." PROGRAM ARGS...
mkdir -p q
quiet_pair() {
  local name="$1" files="$2" f; shift 2
  "$@" >"$name.out" 2>"$name.err" || { fail "$name runs"; cat "$name.err"; }
  (cd q && "$@" --quiet) >"$name.qout" 2>"$name.qerr" ||
    { fail "$name --quiet runs"; cat "$name.qerr"; }
  [ "$(wc -l <"$name.qout")" -eq 1 ] && [ ! -s "$name.qerr" ] &&
    ok "$name --quiet prints one line: $(cat "$name.qout")" ||
    { fail "$name --quiet prints one line"; cat "$name.qout" "$name.qerr"; }
  [ "$(tail -1 "$name.out")" = "$(cat "$name.qout")" ] &&
    ok "$name: the --quiet line is the last line without it" ||
    { fail "$name: the --quiet line is the last line without it"; tail -1 "$name.out"; }
  for f in $files; do
    cmp -s "$f" "q/$f" && ok "$name --quiet writes the same $f" ||
      fail "$name --quiet writes the same $f"
  done
}

# --- activecal_simulate, activecal_compensate, activecal_monte_carlo: on
# those 23 configurations, 6D (pose) measurements of a perturbed UR10e. ---
joint_columns "$m" p.csv
quiet_pair simulate "m.csv true.yaml" "$apps/activecal_simulate" \
  --robot="$data/ur10e.urdf" --tip_link=tool0 --poses_csv="$PWD/p.csv" --type=pose \
  --perturb_m=0.001 --perturb_rad=0.001 --noise_m=0.00005 --rotation_noise_rad=0.00005 \
  --seed=1 --true_model_out=true.yaml --out=m.csv
rows=$(grep -vc '^#\|^type' m.csv)
[ "$(cat simulate.qout)" = "activecal_simulate: wrote $rows pose measurements of 'ur10e' to m.csv" ] &&
  [ "$rows" -eq 23 ] && ok "simulate's line: the 23 rows of the CSV" ||
  fail "simulate's line: the $rows rows of the CSV"

# --- activecal_evaluate: the nominal UR10e on the measurements of the
# perturbed one (1 mm / 1 mrad): registered to the robot, the RMS is the
# model error, mm-level (FIGAROH's file read as a UR10e is 1.6 m off: not a
# figure a person would check). ---
quiet_pair evaluate "eval.json" "$apps/activecal_evaluate" \
  --robot="$data/ur10e.urdf" --tip_link=tool0 --measurements="$PWD/m.csv" \
  --json_out=eval.json
# The line's figures are the JSON's (mm and deg, rounded as printed).
check=$(
  python3 - eval.json evaluate.qout <<'PY'
import json, math, re, sys
j = json.load(open(sys.argv[1]))
line = open(sys.argv[2]).read().strip()
m = re.fullmatch(r"activecal_evaluate: (\d+) measurements, position RMS "
                 r"([0-9.]+) mm, max ([0-9.]+) mm, orientation RMS ([0-9.]+) deg",
                 line)
if not m:
    print("unexpected line: " + line); sys.exit()
n, rms, mx, rot = int(m[1]), float(m[2]), float(m[3]), float(m[4])
bad = []
if n != j["num_measurements"]: bad.append("count")
if abs(rms - j["rmse_m"] * 1e3) > 0.6e-4: bad.append("rms")
if abs(mx - j["max_m"] * 1e3) > 0.6e-4: bad.append("max")
if abs(rot - math.degrees(j["orientation_rad"]["rms"])) > 0.6e-5: bad.append("rot")
# Plausible for a 1 mm / 1 mrad error of a 1.3 m arm after registration.
if not 0.2 < rms < 10: bad.append("RMS %g mm is not mm-level" % rms)
if not rms <= mx < 30: bad.append("max %g mm" % mx)
if not 0.005 < rot < 0.5: bad.append("orientation RMS %g deg" % rot)
print("ok" if not bad else "mismatch " + " ".join(bad) + ": " + line)
PY
)
[ "$check" = "ok" ] && ok "evaluate's line is the JSON's count, RMS, max, orientation, mm-level: $(cat evaluate.qout)" ||
  fail "evaluate's line is the JSON's count, RMS, max, orientation ($check)"

# The nominal robot as a robot file (perturbed by 1e-12), and the robot
# calibrated from m.csv (a true.yaml holds the truth in 'true:' entries,
# its values are the nominal ones: compensating with it changes nothing),
# which the program is compensated for.
"$apps/activecal_simulate" --robot="$data/ur10e.urdf" --tip_link=tool0 \
  --poses_csv=p.csv --perturb_m=1e-12 --perturb_rad=1e-12 \
  --true_model_out=nominal.yaml --out=nominal.csv >/dev/null 2>&1 ||
  fail "the nominal UR10e as a robot file"
"$apps/activecal_identify" --robot="$data/ur10e.urdf" --tip_link=tool0 \
  --measurements=m.csv --model_out=cal.yaml --quiet >/dev/null ||
  fail "the UR10e calibrated from m.csv"
quiet_pair compensate "comp.csv comp.json" "$apps/activecal_compensate" \
  --robot="$PWD/cal.yaml" --nominal="$PWD/nominal.yaml" --poses_csv="$PWD/p.csv" \
  --match=pose --out=comp.csv --json_out=comp.json
check=$(
  python3 - comp.json compensate.qout eval.json <<'PY'
import json, math, re, sys
j = json.load(open(sys.argv[1]))
line = open(sys.argv[2]).read().strip()
m = re.fullmatch(r"activecal_compensate: (\d+) of (\d+) targets converged, "
                 r"correction max (\S+) mm, RMS (\S+) mm, max (\S+) deg, "
                 r"RMS (\S+) deg, IK residual max (\S+) mm", line)
if not m:
    print("unexpected line: " + line); sys.exit()
c = j["correction"]
bad = []
if int(m[1]) != j["num_converged"] or int(m[2]) != j["num_targets"]: bad.append("counts")
for k, key, scale, tol in [(3, "max_position_m", 1e3, 6e-4), (4, "rms_position_m", 1e3, 6e-4),
                           (5, "max_rotation_rad", 180 / math.pi, 6e-5),
                           (6, "rms_rotation_rad", 180 / math.pi, 6e-5)]:
    if abs(float(m[k]) - c[key] * scale) > tol: bad.append(key)
if abs(float(m[7]) - j["max_ik_residual_m"] * 1e3) > 6e-3 * abs(float(m[7])): bad.append("residual")
# The IK residual is ~0 (converged); the correction is the model error the
# program had: of the size evaluate measured (nominal vs. the same true
# robot, registered), not 0.
if not float(m[7]) < 1e-4: bad.append("IK residual not ~0")
ev = json.load(open(sys.argv[3]))
if not 0.3 < c["rms_position_m"] / ev["rmse_m"] < 3: bad.append(
    "correction RMS %g mm vs evaluate's %g mm" % (c["rms_position_m"] * 1e3, ev["rmse_m"] * 1e3))
if not c["rms_position_m"] <= c["max_position_m"]: bad.append("rms > max")
print("ok" if not bad else "mismatch " + " ".join(bad) + ": " + line)
PY
)
[ "$check" = "ok" ] && ok "compensate's line is the JSON's counts, correction and IK residual; the correction is evaluate's error's size" ||
  fail "compensate's line is the JSON's counts, correction and IK residual ($check)"

# Position measurements identify the joint offsets (not the full set).
"$apps/activecal_simulate" --robot="$data/ur10e.urdf" --tip_link=tool0 \
  --poses_csv=p.csv --perturb_m=0.001 --perturb_rad=0.001 --parameter_set=offsets \
  --true_model_out=offsets.yaml --out=offsets.csv >/dev/null 2>&1 ||
  fail "a UR10e with perturbed offsets"
# --- activecal_active: the built-in PUMA loop, simulated. ---
quiet_pair active "loop.json" "$apps/activecal_active" --levels=3 \
  --target_rms_m=5e-4 --json_out=loop.json
python3 - active.qout loop.json <<'PY' &&
import json, re, sys
line = open(sys.argv[1]).read().strip()
j = json.load(open(sys.argv[2]))
m = re.fullmatch(r"activecal_active: (\w+) after (\d+) rounds?, (\d+) poses "
                 r"measured, predicted task RMS (\S+) mm \(target (\S+) mm\)", line)
assert m, line
assert m.group(1) == j["termination_type"], (m.group(1), j["termination_type"])
assert int(m.group(2)) == len(j["rounds"])
assert int(m.group(3)) == len(j["measured_pose_indices"])
predicted = j["rounds"][-1]["predicted_task_rms_m"]
assert abs(float(m.group(4)) - 1e3 * predicted) <= 1e-3 * 1e3 * predicted
assert float(m.group(4)) <= float(m.group(5)) == 1e3 * j["target_rms_m"]
PY
  ok "active's line: the JSON's termination, rounds, poses and predicted RMS" ||
  fail "active's line: the JSON's termination, rounds, poses and predicted RMS"

quiet_pair monte_carlo "" "$apps/activecal_monte_carlo" \
  --robot="$PWD/offsets.yaml" --poses_csv="$PWD/p.csv" --trials=20 --threads=1 \
  --json_out=mc.json
# The JSON is the same but for its "timing" (seconds of this run).
strip_timing() { sed '/"timing": {/,/}/d' "$1"; }
[ -s mc.json ] && [ "$(strip_timing mc.json)" = "$(strip_timing q/mc.json)" ] &&
  ok "monte_carlo --quiet writes the same mc.json (but for its timing)" ||
  fail "monte_carlo --quiet writes the same mc.json (but for its timing)"
check=$(
  python3 - mc.json monte_carlo.qout <<'PY'
import json, re, sys
j = json.load(open(sys.argv[1]))
line = open(sys.argv[2]).read().strip()
m = re.fullmatch(r"activecal_monte_carlo: (\d+) trials \((\d+) failed\), log det "
                 r"ratio (\S+) \(expected (\S+)\), (\S+)% within 2 std", line)
if not m:
    print("unexpected line: " + line); sys.exit()
bad = []
if int(m[1]) != j["trials"] or int(m[2]) != j["failed"]: bad.append("counts")
if abs(float(m[3]) - j["log_det_ratio"]) > 0.6e-4: bad.append("log det")
if abs(float(m[4]) - j["expected_log_det_ratio"]) > 0.6e-4: bad.append("expected")
if abs(float(m[5]) - 100 * j["fraction_within_2_std"]) > 0.06: bad.append("within")
print("ok" if not bad else "mismatch " + " ".join(bad) + ": " + line)
PY
)
[ "$check" = "ok" ] && ok "monte_carlo's line is the JSON's trials, log det ratios, fraction" ||
  fail "monte_carlo's line is the JSON's trials, log det ratios, fraction ($check)"

# --- activecal_puma_paper: the paper's run, 500 random designs. The line's
# OI, OID ratio and count within 2 std are the JSON's and the CSV's. ---
quiet_pair puma_paper "po/identification.csv po/eae_history.csv" \
  "$apps/activecal_puma_paper" --random_designs=500 --certificate=false --out_dir=po
check=$(
  python3 - po/paper_run.json po/identification.csv puma_paper.qout <<'PY'
import csv, json, math, re, sys
j = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
line = open(sys.argv[3]).read().strip()
m = re.fullmatch(r"activecal_puma_paper: exchange-add-exchange OI (\S+) \(paper 0\.11798\), "
                 r"OID ratio to the best random design (\d+) \(paper 58306\); (\d+) of (\d+) "
                 r"identified errors within 2 std; files in po/", line)
if not m:
    print("unexpected line: " + line); sys.exit()
bad = []
if abs(float(m[1]) - j["eae"]["indices"]["oi"]) > 0.6e-5: bad.append("OI")
ratio = 10 ** (j["eae"]["log10_det"] - j["random"]["log10_det"])
if abs(int(m[2]) - ratio) > 0.5 + 1e-9 * ratio: bad.append("ratio %g" % ratio)
within = sum(abs(float(r["error"])) <= 2 * float(r["std"]) for r in rows)
if int(m[3]) != within or int(m[4]) != len(rows): bad.append("within")
if not 0 < within <= len(rows) or len(rows) != 27: bad.append("count")
print("ok" if not bad else "mismatch " + " ".join(bad) + ": " + line)
PY
)
[ "$check" = "ok" ] && ok "puma_paper's line is the JSON's OI and OID ratio, the CSV's errors" ||
  fail "puma_paper's line is the JSON's OI and OID ratio, the CSV's errors ($check)"

cli_end
