#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# The accuracy report end to end on FIGAROH's UR10e data and on the
# simulated PUMA: model selection (cv, validation), the registration-only
# baseline, sigma weighting, warnings, the evaluation before/after with
# posture groups and the plots; the JSON read back and checked for what it
# means; bad inputs end with status 1 and one line.
#
#   tests/accuracy_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

figaroh_ur10e
plot_flag=()
command -v gnuplot >/dev/null && plot_flag=(--selection_plot=curve.png)

# Cross-validation over the 23 poses, on 1 and 2 threads.
for t in 1 2; do
  "$apps/activecal_identify" "${ur[@]}" --measurements="$m" \
    --model_selection=cv --folds=5 --threads=$t --json_out=cv$t.json \
    --urdf_out=cal.urdf --frames_out=frames.yaml --model_out=cal.yaml \
    "${plot_flag[@]}" \
    >cv$t.txt 2>cv$t.err || { fail "identify cv threads=$t"; cat cv$t.err; }
done
cmp -s cv1.json cv2.json && ok "cv report identical on 1 and 2 threads" ||
  fail "cv report depends on the thread count"
# A direct registration: the registration set alone.
"$apps/activecal_identify" "${ur[@]}" --measurements="$m" \
  --parameter_set=registration --json_out=reg.json >/dev/null 2>reg.err ||
  { fail "registration run"; cat reg.err; }
python3 - <<'PY' && ok "cv report: the most within one SE of the curve's minimum is kept; baseline = direct registration" || fail "cv report"
import json, math
r = json.load(open("cv1.json")); d = json.load(open("reg.json"))
ms = r["model_selection"]
assert ms["method"] == "cv" and ms["folds"] == 5 and ms["num_poses"] == 23
assert ms["rule"] == "1se_most" and ms["requested"] == "cv"
curve = ms["curve"]
pts = [c for c in curve if c["ok"]]
best = min(pts, key=lambda c: c["held_out_rms_m"])
assert ms["minimum_kept"] == best["num_kept"], (ms["minimum_kept"], best)
assert ms["kept"] == max(c["num_kept"] for c in pts if c["within_one_se"])
assert ms["kept"] >= best["num_kept"]
assert len(r["parameters"]) == ms["kept"]
assert len(ms["dropped"]) == len(ms["ranking"]) - ms["kept"]
assert set(ms["dropped"]) <= set(r["auto_fixed"])
kept_names = [p["name"] for p in r["parameters"]]
assert sorted(kept_names) == sorted(ms["ranking"][:ms["kept"]])
# the curve starts at the registration-only fit
assert curve[0]["num_kept"] == ms["num_registration"] == 12 and curve[0]["added"] == ""
base = r["registration_only"]["rms_residual_m"]
assert abs(base - d["rms_residual_m"]) <= 1e-9 * base, (base, d["rms_residual_m"])
assert abs(curve[0]["training_rms_m"] - base) <= 1e-6 * base
# training RMS never rises along the curve (nested fits)
for a, b in zip(curve, curve[1:]):
    assert b["training_rms_m"] <= a["training_rms_m"] * (1 + 1e-6)
imp = r["registration_only"]["improvement_percent"]
assert abs(imp - 100 * (1 - r["rms_residual_m"] / base)) < 1e-9
assert r["weighted"] is False and r["implied_sigma_m"] == r["sigma_m"]
assert isinstance(r["warnings"], list)
PY
if [ ${#plot_flag[@]} -gt 0 ]; then
  [ -s curve.png ] && [ "$(head -c 4 curve.png | tail -c 3)" = "PNG" ] &&
    ok "selection curve plot" || fail "selection curve plot"
fi
grep -q "^  registration only (nominal geometry, the 12 base and marker parameters of the calibrated set fitted): RMS" cv1.txt &&
  ok "identify states the registration-only baseline" || fail "baseline line"

# Validation by another 'session': the first 15 poses train, the last 8
# validate (the camera frame refitted to them).
head -n 19 "$m" >train.csv
{ grep '^type' "$m"; tail -n 8 "$m"; } >valid.csv
"$apps/activecal_identify" "${ur[@]}" --measurements=train.csv \
  --model_selection=validation --validation=valid.csv --json_out=val.json \
  >val.txt 2>val.err || { fail "identify validation"; cat val.err; }
python3 - <<'PY' && ok "validation report" || fail "validation report"
import json
r = json.load(open("val.json")); ms = r["model_selection"]
assert ms["method"] == "validation" and ms["validation"] == "valid.csv"
pts = [c for c in ms["curve"] if c["ok"]]
assert ms["minimum_kept"] == min(pts, key=lambda c: c["held_out_rms_m"])["num_kept"]
assert ms["kept"] == max(c["num_kept"] for c in pts if c["within_one_se"])
assert r["num_measurements"] == 15
PY

# Evaluate: the calibrated URDF on its own training data (every posture
# repeated), and on the validation poses with the nominal robot before.
eplot=()
command -v gnuplot >/dev/null && eplot=(--plot=hist.png)
"$apps/activecal_evaluate" --robot=cal.urdf --tip_link=tool0 \
  --frames=frames.yaml --nominal_robot="$data/ur10e.urdf" --measurements="$m" \
  --training="$m" --rotation_weight=0.1 --json_out=eval_same.json \
  "${eplot[@]}" >eval_same.txt 2>eval.err || { fail "evaluate"; cat eval.err; }
"$apps/activecal_evaluate" --robot=cal.urdf --tip_link=tool0 \
  --frames=frames.yaml --nominal_robot="$data/ur10e.urdf" \
  --measurements=valid.csv --training=train.csv --json_out=eval_split.json \
  >/dev/null 2>>eval.err || { fail "evaluate split"; cat eval.err; }
python3 - <<'PY' && ok "evaluation before/after and posture groups" || fail "evaluation report"
import json, math
e = json.load(open("eval_same.json")); r = json.load(open("cv1.json"))
for part in ("before", "after"):
    s = e[part]
    assert abs(s["rmse_m"] ** 2 - sum(x * x for x in s["rmse_xyz_m"])) < 1e-12
    assert s["mean_m"] <= s["rmse_m"] <= s["max_m"] and s["p95_m"] <= s["max_m"]
    assert s["orientation_rad"]["count"] == 23
# before = the nominal UR10e with the frame and marker fitted to these
# measurements with the same rotation weight: identify's baseline residual.
assert abs(e["before"]["registration_rms_residual_m"] - r["registration_only"]["rms_residual_m"]) < 1e-9
assert e["after"]["rmse_m"] == e["rmse_m"]
# every posture is a training posture
g = e["groups"]
assert g["repeated"]["num_measurements"] == 23
assert g["new"]["num_measurements"] == 0 and g["out_of_range"]["num_measurements"] == 0
assert g["repeated"]["rmse_m"] == e["after"]["rmse_m"]
assert all(row["group"] == "repeated" for row in e["errors"])
s = json.load(open("eval_split.json"))
g = s["groups"]
n = sum(g[k]["num_measurements"] for k in ("repeated", "new", "out_of_range"))
assert n == 8 and g["repeated"]["num_measurements"] == 0
# each group's RMSE from the per-row errors
for k in ("new", "out_of_range"):
    rows = [x["error_m"] for x in s["errors"] if x["group"] == k]
    if rows:
        assert abs(math.sqrt(sum(v * v for v in rows) / len(rows)) - g[k]["rmse_m"]) < 1e-12
PY
if [ ${#eplot[@]} -gt 0 ]; then
  [ -s hist.png ] && ok "histogram plot" || fail "histogram plot"
fi

# The simulated PUMA: cv on 30 poses, and sigma weighting by a default.
"$apps/activecal_identify" --num_poses=30 --noise_m=0.001 --model_selection=cv \
  --json_out=puma_cv.json >/dev/null 2>puma.err || { fail "PUMA cv"; cat puma.err; }
"$apps/activecal_identify" --num_poses=30 --noise_m=0.001 --default_sigma_m=0.001 \
  --json_out=puma_w.json >/dev/null 2>>puma.err || { fail "PUMA weighted"; cat puma.err; }
"$apps/activecal_identify" --num_poses=30 --noise_m=0.001 \
  --json_out=puma_u.json >/dev/null 2>>puma.err || { fail "PUMA unweighted"; cat puma.err; }
python3 - <<'PY' && ok "PUMA: cv curve, weighted chi^2 / dof" || fail "PUMA reports"
import json
c = json.load(open("puma_cv.json")); ms = c["model_selection"]
pts = [p for p in ms["curve"] if p["ok"]]
assert ms["minimum_kept"] == min(pts, key=lambda p: p["held_out_rms_m"])["num_kept"]
assert ms["kept"] == max(p["num_kept"] for p in pts if p["within_one_se"])
w = json.load(open("puma_w.json")); u = json.load(open("puma_u.json"))
assert w["weighted"] and not u["weighted"]
# s^2 / sigma^2 with the same data and estimates
ratio = (u["sigma_m"] / 0.001) ** 2
assert abs(w["chi_square_per_dof"] - ratio) < 1e-6 * ratio
assert abs(w["implied_sigma_m"] - u["sigma_m"]) < 1e-9
assert w["degrees_of_freedom"] == 90 - len(w["parameters"])
# the stated sigma is used: std = unweighted std * 0.001 / s
for a, b in zip(w["parameters"], u["parameters"]):
    assert abs(a["std"] - b["std"] * 0.001 / u["sigma_m"]) < 1e-6 * a["std"]
PY

# Sigma columns of a measurements file reach the weights: simulated PUMA
# points with 0.5 mm noise, written in mm with a tracker's U95 of 1 mm
# (sigma 0.5 mm) and in m with sigma_m; chi^2 / dof near 1 for both, the
# same fit.
python3 -c "
import random
random.seed(5)
print('q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad')
for i in range(200): print(','.join('%.6f' % random.uniform(-1.2, 1.2) for _ in range(6)))
" >puma_poses.csv
"$apps/activecal_simulate" --robot="$data/puma560.yaml" --poses_csv=puma_poses.csv \
  --noise_m=0.0005 --out=puma_sim.csv >/dev/null 2>sim.err || { fail "simulate"; cat sim.err; }
awk -F, 'NR==1{print $0",sigma_m";next}{print $0",0.0005"}' puma_sim.csv >puma_sigma.csv
awk -F, 'BEGIN{OFS=","} NR==1{print "type,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_mm,y_mm,z_mm,u95_mm";next}
  {print $1,$2,$3,$4,$5,$6,$7,$8*1000,$9*1000,$10*1000,"1.0"}' puma_sim.csv >puma_u95.csv
for f in puma_sigma puma_u95; do
  "$apps/activecal_identify" --robot="$data/puma560.yaml" --measurements=$f.csv \
    --model_selection=none --json_out=$f.json >$f.txt 2>$f.err || { fail "identify $f"; cat $f.err; }
done
python3 - <<'PY' && ok "sigma_m and u95_mm columns weight the rows: chi^2/dof near 1" || fail "sigma columns"
import json
a = json.load(open("puma_sigma.json")); b = json.load(open("puma_u95.json"))
for r in (a, b):
    assert r["weighted"] is True
    assert r["degrees_of_freedom"] == 600 - len(r["parameters"])
    assert 0.8 < r["chi_square_per_dof"] < 1.25, r["chi_square_per_dof"]
    assert abs(r["implied_sigma_m"] - 0.0005) < 0.0001, r["implied_sigma_m"]
assert abs(a["chi_square_per_dof"] - b["chi_square_per_dof"]) < 1e-3 * a["chi_square_per_dof"]
PY

# Issue #26 item 4: the robot file names the free set (the paper's 27):
# identified as listed by default, every one within 4 std of the truth;
# the same in the README's loop (select, simulate, identify).
"$apps/activecal_identify" --num_poses=30 --seed=1 --json_out=p27.json \
  >p27.txt 2>p27.err || { fail "identify --num_poses=30 --seed=1"; cat p27.err; }
"$apps/activecal_select" --robot="$data/puma560.yaml" --algorithm=fedorov \
  --poses_csv=loop_poses.csv >/dev/null 2>loop.err &&
"$apps/activecal_simulate" --robot="$data/puma560.yaml" --poses_csv=loop_poses.csv \
  --noise_m=0.001 --seed=3 --out=loop_meas.csv >/dev/null 2>>loop.err &&
"$apps/activecal_identify" --robot="$data/puma560.yaml" --measurements=loop_meas.csv \
  --validation_fraction=0.2 --model_out=loop_cal.yaml --json_out=loop.json \
  >loop.txt 2>>loop.err || { fail "README loop"; cat loop.err; }
python3 - <<'PY' && ok "the file's 27 parameters identified, each within 4 std of the paper's truth" || fail "27 parameters"
import json
for f in ("p27.json", "loop.json"):
    r = json.load(open(f)); ms = r["model_selection"]
    assert ms["method"] == "none" and ms["requested"] == "auto", ms
    assert len(r["parameters"]) == 27 and r["auto_fixed"] == [], f
    for p in r["parameters"]:
        assert abs(p["estimate"] - p["true"]) <= 4 * p["std"], (f, p)
PY
grep -q "^  0 of 27 estimates lie more than 4 std from the truth" p27.txt &&
  ok "identify says 0 of 27 beyond 4 std" || fail "0 of 27 line"

# Item 6: the baseline frees only what the calibration has free (the PUMA
# file holds its tool point; the baseline freed it: "-8.0 % lower").
python3 - <<'PY' && ok "registration-only baseline: a subset of the calibrated free set" || fail "baseline subset"
import json
r = json.load(open("p27.json"))
names = [p["name"] for p in r["parameters"]]
base = r["registration_only"]["parameters"]
assert base == ["B.gamma", "B.alpha", "B.a", "B.beta"], base
assert set(base) <= set(names)
assert r["registration_only"]["improvement_percent"] > 0
PY

# Item 2: a failing output writes none of the others.
for bad in "--urdf_out=no_such_dir/cal.urdf" "--json_out=$work"; do
  rm -f all.yaml all.json all_frames.yaml all.urdf
  "$apps/activecal_identify" "${ur[@]}" --measurements="$m" --model_selection=none \
    --model_out=all.yaml --json_out=all.json --frames_out=all_frames.yaml \
    --urdf_out=all.urdf "$bad" >/dev/null 2>all.err
  st=$?
  left=$(ls all.yaml all.json all_frames.yaml all.urdf all.*.tmp 2>/dev/null | wc -l)
  [ $st -eq 1 ] && [ "$left" -eq 0 ] && [ "$(wc -l <all.err)" -eq 1 ] &&
    ok "failing $bad: status 1, one line, no file written" ||
    { fail "failing $bad: status $st, $left files left"; cat all.err; }
done
"$apps/activecal_identify" "${ur[@]}" --measurements="$m" --model_selection=none \
  --model_out=all.yaml --json_out=all.json --frames_out=all_frames.yaml \
  --urdf_out=all.urdf >/dev/null 2>all.err &&
  [ -s all.yaml ] && [ -s all.json ] && [ -s all_frames.yaml ] && [ -s all.urdf ] &&
  ! ls ./*.tmp >/dev/null 2>&1 && ok "a good run writes all four" || fail "good run outputs"

# Item 14: millimetres in x_m, y_m, z_m are refused, metres accepted.
awk -F, 'BEGIN{OFS=","} /^#/{next} $1=="pose"{$8*=1000;$9*=1000;$10*=1000} {print}' "$m" >mm_in_m.csv
expect_fail "millimetres in metre columns (UR10e, 6D)" \
  "more than the robot's reach at the measured poses (1.253 m): are the measured values in millimetres? x_m, y_m, z_m and distance_m are metres" \
  activecal_identify "${ur[@]}" --measurements=mm_in_m.csv --model_out=mm.yaml
[ ! -e mm.yaml ] && ok "nothing written for mm data" || fail "mm data wrote a model"
awk -F, 'BEGIN{OFS=","} NR==1{print;next} {$8*=1000;$9*=1000;$10*=1000; print}' puma_sim.csv >puma_mm_in_m.csv
expect_fail "millimetres in metre columns (PUMA, DH base)" "are the measured values in millimetres?" \
  activecal_identify --robot="$data/puma560.yaml" --measurements=puma_mm_in_m.csv
"$apps/activecal_identify" --robot="$data/puma560.yaml" --measurements=puma_sim.csv \
  >/dev/null 2>pm.err && ok "the same PUMA file in metres is accepted" || { fail "PUMA metres"; cat pm.err; }

# Item 21: stated sigmas 50 times too small: chi^2 / dof ~2500, outside
# its 99.9 % interval: said once, std_scaled = std * sqrt(chi^2 / dof) in
# the JSON and the table; the right sigma: inside, no std_scaled.
awk -F, 'NR==1{print $0",sigma_m";next}{print $0",0.00001"}' puma_sim.csv >puma_tiny.csv
"$apps/activecal_identify" --robot="$data/puma560.yaml" --measurements=puma_tiny.csv \
  --json_out=tiny.json >tiny.txt 2>tiny.err || { fail "identify tiny sigma"; cat tiny.err; }
python3 - <<'PY' && ok "chi^2 / dof outside its interval: std scaled, said once" || fail "chi^2 scaling"
import json, math
t = json.load(open("tiny.json")); a = json.load(open("puma_sigma.json"))
lo, hi = t["chi_square_per_dof_interval"]
assert lo < 1 < hi and not lo <= t["chi_square_per_dof"] <= hi
assert t["chi_square_plausible"] is False
f = math.sqrt(t["chi_square_per_dof"])
for p in t["parameters"]:
    assert abs(p["std_scaled"] - p["std"] * f) <= 1e-9 * p["std_scaled"], p
lo, hi = a["chi_square_per_dof_interval"]
assert lo <= a["chi_square_per_dof"] <= hi and a["chi_square_plausible"] is True
assert all("std_scaled" not in p for p in a["parameters"])
text = open("tiny.txt").read()
assert text.count("is outside the 99.9 % interval of chi-square") == 1, text
header = [l for l in text.splitlines() if l.startswith("parameter ")][0]
assert "std_scaled" in header
PY
grep -q "std_scaled" puma_sigma.txt && fail "std_scaled printed with plausible sigmas" || ok "no std_scaled column with plausible sigmas"

# Item 7: what 'before' is. Train on the first 15 FIGAROH poses, test on
# the last 8. Default with --training and --nominal_robot: the nominal
# geometry registered on the training poses (= identify's registration set
# on train.csv, evaluated as given); refit: registered to the test file
# itself (= identify's registration set on valid.csv); without
# --nominal_robot, a refit of --robot, labelled so.
"$apps/activecal_identify" "${ur[@]}" --measurements=train.csv \
  --urdf_out=tcal.urdf --frames_out=tframes.yaml >/dev/null 2>ev.err &&
"$apps/activecal_identify" "${ur[@]}" --measurements=train.csv \
  --parameter_set=registration --frames_out=treg.yaml >/dev/null 2>>ev.err &&
"$apps/activecal_identify" "${ur[@]}" --measurements=valid.csv \
  --parameter_set=registration --json_out=vreg.json >/dev/null 2>>ev.err &&
"$apps/activecal_evaluate" "${ur[@]}" --frames=treg.yaml --measurements=valid.csv \
  --json_out=ev_reg.json >/dev/null 2>>ev.err || { fail "evaluate setup"; cat ev.err; }
cal=(--robot=tcal.urdf --tip_link=tool0 --frames=tframes.yaml --rotation_weight=0.1
     --measurements=valid.csv --training=train.csv)
"$apps/activecal_evaluate" "${cal[@]}" --nominal_robot="$data/ur10e.urdf" \
  --json_out=ev_train.json >ev_train.txt 2>>ev.err &&
"$apps/activecal_evaluate" "${cal[@]}" --nominal_robot="$data/ur10e.urdf" \
  --before=refit --json_out=ev_refit.json >ev_refit.txt 2>>ev.err &&
"$apps/activecal_evaluate" "${cal[@]}" --json_out=ev_self.json >ev_self.txt 2>>ev.err ||
  { fail "evaluate kinds"; cat ev.err; }
python3 - <<'PY' && ok "evaluate: each 'before' is what it says" || fail "evaluate before kinds"
import json
t = json.load(open("ev_train.json")); r = json.load(open("ev_refit.json"))
s = json.load(open("ev_self.json")); reg = json.load(open("ev_reg.json"))
v = json.load(open("vreg.json"))
assert t["before"]["kind"] == "training" and t["before"]["fitted_on"] == "train.csv"
assert t["before"]["registration_only"] is True
# the registration fitted on the training poses, evaluated as given
for k in ("rmse_m", "max_m", "p95_m"):
    assert abs(t["before"][k] - reg["rmse_m" if k == "rmse_m" else k]) < 1e-7, (k, t["before"][k], reg[k])
assert r["before"]["kind"] == "refit" and r["before"]["fitted_on"] == "valid.csv"
assert abs(r["before"]["registration_rms_residual_m"] - v["rms_residual_m"]) < 1e-9
# refitted to the test file: never worse there than fitted elsewhere
assert r["before"]["rmse_m"] <= t["before"]["rmse_m"]
assert s["before"]["kind"] == "refit" and s["before"]["registration_only"] is False
assert s["before"]["robot"] == "tcal.urdf"
# 'after' is the model as given, the same in all three
assert t["after"]["rmse_m"] == r["after"]["rmse_m"] == s["after"]["rmse_m"] == t["rmse_m"]
assert t["after"]["description"] == "--robot as given (no fitting)"
PY
grep -q "^  before: registration only: --nominal_robot's geometry, base and markers fitted to --training (15 measurements)" ev_train.txt &&
  grep -q "^  before: --robot's own geometry, base and markers refitted to these measurements (no --nominal_robot: not a registration-only baseline)" ev_self.txt &&
  grep -q "give --nominal_robot for the registration-only baseline fitted on --training" ev_self.txt &&
  ok "evaluate states what 'before' is" || fail "evaluate labels"
expect_fail "before=training without a nominal robot" \
  "--before=training needs --training (the measurements the model was calibrated on) and --nominal_robot" \
  activecal_evaluate "${cal[@]}" --before=training
expect_fail "unknown --before" "--before must be auto, training, refit or none, got 'x'" \
  activecal_evaluate "${cal[@]}" --before=x

# Item 20: evaluate without --frames says so first, in one line, before
# any number.
"$apps/activecal_evaluate" --robot="$data/ur10e.urdf" --tip_link=tool0 \
  --measurements="$m" >noframes.txt 2>nf.err || { fail "evaluate without frames"; cat nf.err; }
note=$(grep -n "^note: no --frames: the robot's base frame is the identity" noframes.txt | cut -d: -f1)
first=$(grep -n "RMSE" noframes.txt | head -1 | cut -d: -f1)
[ -n "$note" ] && [ "$note" -eq 2 ] && [ "$note" -lt "$first" ] &&
  [ "$(grep -c "base frame is the identity" noframes.txt)" -eq 1 ] &&
  ok "no --frames: said first (line 2, after the robot line), once" ||
  { fail "no-frames note not first"; cat noframes.txt; }
"$apps/activecal_evaluate" "${cal[@]}" >withframes.txt 2>/dev/null
grep -q "base frame is the identity" withframes.txt && fail "note with --frames" ||
  ok "no such note with --frames"

# Bad input: one line, status 1.
awk -F, 'BEGIN{OFS=","} /^#/ {next} {NF=6; print}' "$m" >five.csv
expect_fail "validation file of another robot" "--validation: " \
  activecal_identify "${ur[@]}" --measurements="$m" --model_selection=validation --validation=five.csv
{ grep '^type' "$m"; tail -n 1 "$m"; } >valid_one.csv
expect_fail "a validation file too small to refit the registration" \
  "--validation: model selection: the base and markers could not be refitted to the 1 validation measurements: registration needs at least 3 measured points, got 1" \
  activecal_identify "${ur[@]}" --measurements="$m" --model_selection=validation --validation=valid_one.csv
expect_fail "too few poses for the folds" \
  "--model_selection: cross-validation: 30 folds need at least 30 distinct poses, the measurements have 23" \
  activecal_identify "${ur[@]}" --measurements="$m" --model_selection=cv --folds=30
expect_fail "unknown model selection" "--model_selection must be auto, none, validation or cv, got 'aic'" \
  activecal_identify --model_selection=aic
expect_fail "validation without a file" "--model_selection=validation needs --validation=FILE" \
  activecal_identify --model_selection=validation
expect_fail "one fold" "--folds must be >= 2, got 1" \
  activecal_identify --model_selection=cv --folds=1
expect_fail "prior and selection" "choose one" \
  activecal_identify --model_selection=cv --prior_std_m=0.001
expect_fail "negative prior" "--prior_std_m and --prior_std_rad must be finite and >= 0" \
  activecal_identify --prior_std_rad=-1
expect_fail "unknown ranking" "--selection_ranking must be significance or jacobian, got 'size'" \
  activecal_identify --model_selection=cv --selection_ranking=size
expect_fail "negative default sigma" "default_sigma_m and default_sigma_rad must be finite and >= 0" \
  activecal_identify --default_sigma_m=-0.001
if [ ${#plot_flag[@]} -gt 0 ]; then
  # A plot into a folder that does not exist: named, not a SIGPIPE (141).
  expect_fail "selection plot in a missing folder" \
    "--selection_plot: cannot write no_such_dir/curve.png" \
    activecal_identify "${ur[@]}" --measurements="$m" --selection_plot=no_such_dir/curve.png
  expect_fail "histogram plot in a missing folder" \
    "--plot: cannot write no_such_dir/hist.png" \
    activecal_evaluate "${ur[@]}" --measurements="$m" --plot=no_such_dir/hist.png
fi
# Ballbar distances only: no position error to draw (it drew every
# distance row as a 0 mm position error).
"$apps/activecal_simulate" --robot="$data/puma560.yaml" --poses_csv=puma_poses.csv \
  --noise_m=0.0005 --type=distance --out=puma_dist.csv >/dev/null 2>sim.err || { fail "simulate distances"; cat sim.err; }
expect_fail "histogram of distances only" \
  "--plot: the histograms are of position errors, and the measurements have none (distances only)" \
  activecal_evaluate --robot="$data/puma560.yaml" --measurements=puma_dist.csv --plot=dist.png
printf 'type,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m\nposition,0,0,0,0,0,0,0.1,0.2,0.3\n' >puma_one.csv
expect_fail "nominal robot of another chain" \
  "--nominal_robot: not the same robot as --robot: parameter 1 is B.gamma there and B.x in --robot (6 and 6 joints, " \
  activecal_evaluate --robot=cal.yaml --measurements=puma_one.csv \
  --nominal_robot="$data/puma560.yaml"

cli_end
