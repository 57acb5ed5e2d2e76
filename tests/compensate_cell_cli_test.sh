#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# activecal_compensate --cell with the robot file activecal_identify
# --model_out writes (no collision geometry), the form docs/compensation.md
# uses: the --nominal URDF's collision geometry (the same chain) is used, so
# the configurations through the table or the wall are collision, as with
# the URDF itself; with no geometry anywhere --cell is refused in one line.
# The summary and the stderr line count per status, the first of each by
# its target index (and pose_index).
#
#   tests/compensate_cell_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

urdf="$data/kuka_iiwa14.urdf"
cell="$data/cells/iiwa_table.yaml"
# 40 measurement poses and a 20-target program, inside 90% of the limits.
python3 - <<'PY'
import random
random.seed(5)
lim = [2.967, 2.094, 2.967, 2.094, 2.967, 2.094, 3.054]
def write(name, n):
    with open(name, "w") as f:
        f.write("pose_index," + ",".join("q%d_rad" % j for j in range(1, 8)) + "\n")
        for i in range(n):
            f.write(str(i) + "," + ",".join(repr(random.uniform(-0.9 * l, 0.9 * l))
                                          for l in lim) + "\n")
write("poses.csv", 40)
write("program.csv", 20)
PY
"$apps/activecal_simulate" --robot="$urdf" --poses_csv=poses.csv \
  --noise_m=0.0001 --perturb_m=0.001 --perturb_rad=0.001 --seed=2 \
  --out=m.csv >sim.out 2>&1 || { fail "simulate"; cat sim.out; }
"$apps/activecal_identify" --robot="$urdf" --measurements=m.csv \
  --model_selection=none --threads=1 --model_out=cal.yaml >id.out 2>&1 ||
  { fail "identify --model_out"; cat id.out; }
grep -q "^collision:" cal.yaml && fail "cal.yaml has collision geometry: the test proves nothing"

# The URDF itself (its <collision>), then the calibrated YAML with it as
# --nominal.
"$apps/activecal_compensate" --robot="$urdf" --nominal="$urdf" \
  --poses_csv=program.csv --cell="$cell" --out=u.csv --json_out=u.json \
  >u.out 2>u.err
[ $? -eq 2 ] || { fail "compensate the URDF --cell: status not 2"; cat u.err; }
"$apps/activecal_compensate" --robot=cal.yaml --nominal="$urdf" \
  --poses_csv=program.csv --cell="$cell" --out=y.csv --json_out=y.json \
  >y.out 2>y.err
status=$?
[ "$status" -eq 2 ] && [ "$(wc -l <y.err)" -eq 1 ] &&
  grep -q -- "--cell: note: cal.yaml has no collision geometry: that of .*kuka_iiwa14.urdf (the same chain) is used" y.out &&
  ok "compensate --robot=cal.yaml --cell: the nominal URDF's collision geometry (status 2)" ||
  { fail "compensate cal.yaml --cell (status $status)"; cat y.out y.err; }
python3 - <<'PY' && ok "... its collisions those of the URDF, the summary per status" || fail "collisions with --nominal's geometry"
import json, re
u, y = json.load(open("u.json")), json.load(open("y.json"))
assert u["num_collision"] > 0, u["num_collision"]
# mm-level calibration: the same targets collide.
cu = [t["status"] for t in u["targets"]]
cy = [t["status"] for t in y["targets"]]
assert cu == cy, (cu, cy)
assert y["collision_geometry"].endswith("kuka_iiwa14.urdf"), y["collision_geometry"]
n, c = y["num_targets"], y["num_collision"]
first = cy.index("collision")
label = y["targets"][first]["pose_index"]
reason = y["targets"][first]["message"]
want = ("%d of %d targets are not converged: %d collision (the first, target %d: %s)"
        % (n - y["num_converged"], n, c, first, reason))
assert want in open("y.out").read(), want
err = open("y.err").read()
want = ("activecal_compensate: %d of %d targets are not converged, written with "
        "their status to y.csv: %d collision (the first, target %d, pose_index %d: %s)"
        % (n - y["num_converged"], n, c, first, label, reason))
assert err.strip() == want, (err, want)
assert "refused by the cell" not in err and "did not converge" not in err
PY
# No collision geometry in either file: refused, nothing written.
expect_fail "compensate --cell without collision geometry" \
  "--cell: neither --robot=cal.yaml nor --nominal=cal.yaml has collision geometry" \
  activecal_compensate --robot=cal.yaml --nominal=cal.yaml \
  --poses_csv=program.csv --cell="$cell" --out=none.csv
[ ! -e none.csv ] && ok "... writing nothing" || fail "wrote none.csv"

cli_end
