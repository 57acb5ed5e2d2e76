#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# activecal_simulate for a robot without true values and in a cell (issues
# #29 item 6, #24): a URDF UR10e perturbed (--perturb_m, --perturb_rad,
# seeded) and simulated, the truth written (--true_model_out) and then
# recovered by activecal_identify within its reported standard deviations;
# with --cell only the poses the cell allows are measured, each of the
# targets it sees, and the rejected ones counted as activecal_select
# counts them; bad values give one line and write nothing.
#
#   tests/simulate_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

ur=(--robot="$data/ur10e.urdf" --tip_link=tool0)
perturb=(--perturb_m=0.001 --perturb_rad=0.001 --seed=1 --noise_m=1e-5)

# --- A URDF robot, perturbed, simulated, identified. ---
"$apps/activecal_select" "${ur[@]}" --pool=sobol --pool_size=3000 \
  --num_poses=40 --algorithm=fedorov --poses_csv=p.csv >sel.out 2>&1 ||
  { fail "select the poses"; cat sel.out; }
if "$apps/activecal_simulate" "${ur[@]}" --poses_csv=p.csv "${perturb[@]}" \
  --true_model_out=true.yaml --out=m.csv >sim.out 2>sim.err; then
  ok "simulate a URDF robot, perturbed"
else
  fail "simulate a URDF robot"; cat sim.err
fi
grep -qE "^activecal_simulate: wrote 40 position measurements of 'ur10e' to m.csv$" sim.out &&
  grep -qE "^wrote the true model \([0-9]+ free parameters, perturbed\) to true.yaml$" sim.out &&
  ok "simulate says what it wrote" || { fail "simulate's lines"; cat sim.out; }
# Seeded: the same seed, the same files; another seed, another truth.
"$apps/activecal_simulate" "${ur[@]}" --poses_csv=p.csv "${perturb[@]}" \
  --true_model_out=true_again.yaml --out=m_again.csv >/dev/null 2>&1
sed 1d true.yaml >a.yaml; sed 1d true_again.yaml >b.yaml
cmp -s m.csv m_again.csv && cmp -s a.yaml b.yaml &&
  ok "the same seed, the same truth and measurements" || fail "not reproducible"
"$apps/activecal_simulate" "${ur[@]}" --poses_csv=p.csv --perturb_m=0.001 \
  --perturb_rad=0.001 --seed=2 --true_model_out=true2.yaml --out=m2.csv \
  >/dev/null 2>&1
sed 1d true2.yaml >c.yaml
cmp -s a.yaml c.yaml && fail "another seed, the same truth" ||
  ok "another seed, another truth"
# The true model reads back as a robot; identify recovers it.
if "$apps/activecal_identify" --robot=true.yaml --parameter_set=full \
  --measurements=m.csv --json_out=id.json >id.out 2>id.err; then
  ok "identify --robot=<true model> on the simulated file"
else
  fail "identify on the simulated file"; cat id.err
fi
python3 - <<'PY' && ok "identify recovers the true model within 3 std" || fail "true model not recovered"
import json
d = json.load(open("id.json"))
ps = d["parameters"]
assert len(ps) >= 20, len(ps)
worst = max(abs(p["estimate"] - p["true"]) / p["std"] for p in ps)
# The perturbation is there to find: the nominal values are many std off.
off = max(abs(p["nominal"] - p["true"]) / p["std"] for p in ps)
print(f"  {len(ps)} parameters: worst |estimate - true| = {worst:.2f} std; "
      f"nominal up to {off:.0f} std off")
assert worst <= 3.0, worst
assert off > 10.0, off
PY

# --- A cell: the poses it allows, the targets each sees. ---
two_target_cell
"$apps/activecal_select" "${ur[@]}" --cell=two.yaml --pool=sobol \
  --pool_size=20000 --num_poses=30 --algorithm=fedorov --poses_csv=pc.csv \
  --rejected_csv=rc.csv >selc.out 2>&1 || { fail "select --cell"; cat selc.out; }
# The design's 30 feasible poses and 12 rejected ones, mixed.
python3 - <<'PY'
import csv
feasible = list(csv.DictReader(open("pc.csv")))
rejected = list(csv.DictReader(open("rc.csv")))[:12]
cols = ["q%d_rad" % j for j in range(1, 7)]
with open("mixed.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(cols)
    for k in range(42):
        r = feasible[k // 7 * 5 + k % 7] if k % 7 < 5 else rejected[k // 7 * 2 + k % 7 - 5]
        w.writerow([r[c] for c in cols])
PY
if "$apps/activecal_simulate" "${ur[@]}" --cell=two.yaml \
  --poses_csv=mixed.csv "${perturb[@]}" --out=mc.csv >simc.out 2>simc.err; then
  ok "simulate --cell"
else
  fail "simulate --cell"; cat simc.err
fi
python3 - <<'PY' && ok "only the feasible poses, each of the targets it sees; the rejected counted" || fail "simulate --cell measurements"
import collections, csv, re
feasible = list(csv.DictReader(open("pc.csv")))
rejected = list(csv.DictReader(open("rc.csv")))[:12]
cols = ["q%d_rad" % j for j in range(1, 7)]
key = lambda r: tuple(float(r[c]) for c in cols)
want = {key(r): sorted(r["targets"].split(";")) for r in feasible}
got = collections.defaultdict(list)
for r in csv.DictReader(open("mc.csv")):
    got[key(r)].append(r["marker"])
assert set(got) == set(want), (len(got), len(want))
for k in want:
    assert sorted(got[k]) == want[k], (got[k], want[k])
assert {m for ms in got.values() for m in ms} == {"smr", "side"}
out = open("simc.out").read()
line = re.search(r"cell: (\d+) of (\d+) poses feasible \([^)]*\); rejected: (.*)", out)
assert line and line.group(1) == "30" and line.group(2) == "42", out
counts = dict(re.findall(r"([a-z ]+?) (\d+)(?:, |$)", line.group(3)))
names = {"joint_margin": "joint margin", "self_collision": "self-collision",
         "out_of_range": "out of range", "facing_away": "target facing away",
         "line_of_sight": "line of sight blocked"}
n = collections.Counter()
for r in rejected:
    n["obstacle " + r["obstacle"] if r["reason"] == "obstacle" else names.get(r["reason"], r["reason"])] += 1
for reason, c in n.items():
    assert int(counts[reason]) == c, (reason, counts, n)
assert sum(int(v) for v in counts.values()) == 12, counts
PY

# --- Bad input: one line, nothing written. ---
expect_fail "negative perturbation" \
  "activecal_simulate: error: --perturb_m must be >= 0, got -0.001" \
  activecal_simulate "${ur[@]}" --poses_csv=p.csv --perturb_m=-0.001 \
  --true_model_out=t.yaml --out=bad.csv
expect_fail "non-finite perturbation" \
  "activecal_simulate: error: --perturb_rad must be >= 0, got nan" \
  activecal_simulate "${ur[@]}" --poses_csv=p.csv --perturb_rad=nan --out=bad.csv
expect_fail "true_model_out unwritable" \
  "activecal_simulate: error: --true_model_out: cannot write 'no_such_dir/t.yaml'" \
  activecal_simulate "${ur[@]}" --poses_csv=p.csv "${perturb[@]}" \
  --true_model_out=no_such_dir/t.yaml --out=bad.csv
expect_fail "no true values, no perturbation" \
  "has no true values to simulate from: add 'true:' entries to its blocks (docs/formats.md) or perturb it (--perturb_m, --perturb_rad)" \
  activecal_simulate "${ur[@]}" --poses_csv=p.csv --out=bad.csv
expect_fail "parameter_set without a perturbation" \
  "activecal_simulate: error: --parameter_set chooses the parameters --perturb_m and --perturb_rad move: give one of them" \
  activecal_simulate --poses_csv=p.csv --parameter_set=full --out=bad.csv
expect_fail "cell with a ballbar" \
  "activecal_simulate: error: --cell plans what a tracker, cameras or mocap see: not with --type=distance (a ballbar)" \
  activecal_simulate "${ur[@]}" --poses_csv=p.csv --cell=two.yaml \
  --type=distance --perturb_m=0.001 --out=bad.csv
expect_fail "cell leaving no pose" \
  "activecal_simulate: error: --cell: no pose of --poses_csv is left: 0 of " \
  activecal_simulate "${ur[@]}" --poses_csv=rc.csv --cell=two.yaml \
  --perturb_m=0.001 --true_model_out=t.yaml --out=bad.csv
[ ! -e bad.csv ] && [ ! -e t.yaml ] && ok "nothing written on bad input" ||
  fail "a failed run wrote a file"

cli_end
