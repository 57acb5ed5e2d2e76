#!/usr/bin/env bash
# The accuracy report end to end on FIGAROH's UR10e data and on the
# simulated PUMA: model selection (cv, validation), the registration-only
# baseline, sigma weighting, warnings, the evaluation before/after with
# posture groups and the plots; the JSON read back and checked for what it
# means; bad inputs end with status 1 and one line.
#
#   tests/accuracy_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
apps="$(cd "$1" && pwd)"
data="$(cd "$2" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
failures=0
ok() { echo "ok   [$1]"; }
fail() { echo "FAIL [$1]"; failures=$((failures + 1)); }
source "$here/cli_lib.sh"

m="$data/figaroh_ur10e/measurements.csv"
ur=(--robot="$data/ur10e.urdf" --tip_link=tool0 --rotation_weight=0.1)
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
python3 - <<'PY' && ok "cv report: curve minimum is the kept count; baseline = direct registration" || fail "cv report"
import json, math
r = json.load(open("cv1.json")); d = json.load(open("reg.json"))
ms = r["model_selection"]
assert ms["method"] == "cv" and ms["folds"] == 5 and ms["num_poses"] == 23
curve = ms["curve"]
pts = [c for c in curve if c["ok"]]
best = min(pts, key=lambda c: c["held_out_rms_m"])
assert ms["kept"] == best["num_kept"], (ms["kept"], best)
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
grep -q "^  registration only (nominal geometry, base and markers fitted): RMS" cv1.txt &&
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
assert ms["kept"] == min(pts, key=lambda c: c["held_out_rms_m"])["num_kept"]
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
assert ms["kept"] == min(pts, key=lambda p: p["held_out_rms_m"])["num_kept"]
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
    --model_selection=none --json_out=$f.json >/dev/null 2>$f.err || { fail "identify $f"; cat $f.err; }
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
expect_fail "unknown model selection" "--model_selection must be none, validation or cv, got 'aic'" \
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

echo "$failures failure(s)"
[ "$failures" -eq 0 ]
