#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# The learned residual end to end (activecal_identify --learned_residual):
# on a simulated PUMA with a smooth non-geometric error (0.1 mm, a function
# of the joints) auto keeps it, --model_out holds it, activecal_evaluate
# applies it (new poses: lower RMS than the parametric model alone) and
# activecal_compensate too; on a purely geometric robot auto does not keep
# it; --learned_residual=off changes nothing; bad flags and a bad field of
# the model file end with status 1 and one line.
#
#   tests/learned_residual_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

# poses <count> <awk seed> [<fraction of the ranges>]: random PUMA poses
# inside the joint ranges.
poses() {
  awk -v n="$1" -v s="$2" -v f="${3:-1}" 'BEGIN{srand(s);
    split("-2.5 -1.9 -2.3 -1.7 -2.4 -2.5", lo, " ");
    split("1.2 2.5 2.3 1.7 2.4 2.5", hi, " ");
    print "pose_index,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad";
    for (i = 0; i < n; i++) { printf "%d", i;
      for (j = 1; j <= 6; j++) printf ",%.6f", f * (lo[j] + (hi[j] - lo[j]) * rand());
      print "" } }'
}
# smooth <csv>: a 0.1 mm smooth function of the joints added to x, y, z.
smooth() {
  awk -F, 'BEGIN{OFS=","; CONVFMT="%.17g"} NR==1{print; next}
    {$8 += 1e-4*sin($2)*cos($3); $9 += 1e-4*cos($3+$4);
     $10 += 1e-4*sin($4)*sin($2-$5); print}' "$1"
}
puma=(--robot="$data/puma560.yaml")
poses 160 7 >train_poses.csv
poses 100 11 >new_poses.csv
"$apps/activecal_simulate" "${puma[@]}" --poses_csv=train_poses.csv \
  --noise_m=1e-5 --seed=3 --out=geometric.csv >/dev/null || fail "simulate"
"$apps/activecal_simulate" "${puma[@]}" --poses_csv=new_poses.csv \
  --noise_m=1e-5 --seed=4 --out=new_geometric.csv >/dev/null || fail "simulate"
smooth geometric.csv >smooth.csv
smooth new_geometric.csv >new_smooth.csv
fit=("${puma[@]}" --learned_features=100 --threads=2)

# A smooth non-geometric error: kept, written, applied.
"$apps/activecal_identify" "${fit[@]}" --measurements=smooth.csv \
  --learned_residual=auto --model_out=hybrid.yaml --urdf_out=hybrid.urdf \
  >auto.txt 2>auto.err || { fail "identify --learned_residual=auto"; cat auto.err; }
grep -q "learned residual (auto): 100 random Fourier features" auto.txt &&
  grep -q "kept (gain > 2 SE)" auto.txt &&
  grep -q "^learned_residual:" hybrid.yaml &&
  grep -q "^  features: 100$" hybrid.yaml &&
  ok "smooth error: auto keeps the correction, --model_out holds it" ||
  { fail "smooth error kept"; cat auto.txt; }
grep -q "the URDF holds the geometry only, not the learned correction" auto.txt &&
  ! grep -q learned hybrid.urdf &&
  ok "--urdf_out says the URDF lacks the correction" || fail "--urdf_out note"
"$apps/activecal_identify" "${fit[@]}" --measurements=smooth.csv \
  --model_out=parametric.yaml >off.txt 2>&1 || fail "identify (off)"
"$apps/activecal_identify" "${fit[@]}" --measurements=smooth.csv \
  --learned_residual=off --model_out=off.yaml >off2.txt 2>&1 || fail "identify off"
cmp -s off.txt off2.txt && cmp -s parametric.yaml off.yaml &&
  ! grep -q learned parametric.yaml &&
  ok "--learned_residual=off: the output and model file of no flag" ||
  fail "--learned_residual=off changes the output"

"$apps/activecal_evaluate" --robot=hybrid.yaml --measurements=new_smooth.csv \
  --before=none --json_out=hybrid.json >eval.txt 2>&1 || { fail "evaluate hybrid"; cat eval.txt; }
"$apps/activecal_evaluate" --robot=parametric.yaml --measurements=new_smooth.csv \
  --before=none --json_out=parametric.json >eval_p.txt 2>&1 || fail "evaluate parametric"
grep -q "after: --robot as given (no fitting), with its learned correction (100 random Fourier features, fitted on 160 measurements)" eval.txt ||
  { fail "evaluate names the correction"; cat eval.txt; }
python3 - <<'PY' && ok "evaluate applies it: new poses' RMS lower than the parametric model's" || fail "evaluate RMS"
import json
h = json.load(open("hybrid.json")); p = json.load(open("parametric.json"))
assert h["after"]["learned_correction"] and not p["after"]["learned_correction"]
print("  new poses: parametric %.4f mm, hybrid %.4f mm" % (p["rmse_m"] * 1e3, h["rmse_m"] * 1e3))
assert h["rmse_m"] < 0.8 * p["rmse_m"], (h["rmse_m"], p["rmse_m"])
PY
# A program away from the joint limits (the calibrated geometry is far
# from the nominal: near the limits some targets are out of reach).
poses 50 13 0.6 >program.csv
"$apps/activecal_compensate" --robot=hybrid.yaml --nominal="$data/puma560.yaml" \
  --poses_csv=program.csv --out=compensated.csv >comp.txt 2>&1 &&
  grep -q "with --robot's learned correction (100 random Fourier features)" comp.txt &&
  grep -q "50 targets: 50 converged" comp.txt &&
  ok "compensate applies it (every target reached on the corrected model)" ||
  { fail "compensate"; cat comp.txt; }

# Purely geometric: not kept, nothing written.
"$apps/activecal_identify" "${fit[@]}" --measurements=geometric.csv \
  --learned_residual=auto --model_out=geo.yaml >geo.txt 2>&1 || fail "identify geometric"
grep -q "not kept (gain <= 2 SE)" geo.txt && ! grep -q learned geo.yaml &&
  ok "geometric robot: auto does not keep it" || { fail "geometric not kept"; cat geo.txt; }

# Bad input: one line each.
expect_fail "bad --learned_residual" "--learned_residual" activecal_identify \
  "${puma[@]}" --measurements=geometric.csv --learned_residual=maybe
expect_fail "--learned_residual with --harmonics" "not supported" \
  activecal_identify "${puma[@]}" --measurements=geometric.csv \
  --learned_residual=on --harmonics=1
expect_fail "bad --learned_features" "--learned_residual" activecal_identify \
  "${puma[@]}" --measurements=geometric.csv --learned_residual=on \
  --learned_features=0
sed 's/inputs: \[periodic/inputs: [wavy/' hybrid.yaml >bad.yaml
expect_fail "bad learned_residual field" \
  "bad.yaml:" activecal_evaluate --robot=bad.yaml --measurements=new_smooth.csv
grep -q "learned_residual.inputs\[0\]: expected periodic or linear, got 'wavy'" err.txt ||
  { fail "the bad field is named"; cat err.txt; }

cli_end
