#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Several markers and the UR10e in activecal_active and activecal_sim_cell
# without a cell (#24's remainder, item 6): the parameter reduction counts
# every marker (each pose measures all), and the UR10e loop from its URDF
# runs past round 0.
#
#   tests/markers_loop_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

# --- Without a cell (#24's remainder, item 6). Several markers: the
# reduction counts every marker (each pose measures all), so the second
# marker's offsets are identified, in activecal_active and in
# activecal_sim_cell's truth; and the UR10e loop from its URDF (the marker at
# tool0's origin) runs past round 0 (its first batch was singular at the
# exact nominal: the loop now starts at the reduction's point). ---
ur=(--robot="$data/ur10e.urdf" --tip_link=tool0)
printf 'markers:\n  - {name: a, xyz: [0.06, 0.03, 0.1]}\n  - {name: b, xyz: [-0.05, 0.04, 0.08]}\n' >two_markers.yaml
"$apps/activecal_sim_cell" "${ur[@]}" --frames=two_markers.yaml --perturb_m=5e-4 \
  --perturb_rad=5e-4 --seed=2 --truth_out=two_truth.yaml </dev/null >/dev/null 2>tt.err
python3 - <<'PY' && ok "sim_cell: every marker's offsets in the truth" || { fail "sim_cell two markers"; cat tt.err; }
import re
text = open("two_truth.yaml").read()
b = text[text.index("- name: b"):]
assert re.search(r"free: \[x, y, z\]\n\s*true: \{x: ", b), b
PY
sim=(--perturb_m=5e-4 --perturb_rad=5e-4 --seed=2)
"$apps/activecal_active" "${ur[@]}" --frames=two_markers.yaml --levels=3 --max_rounds=2 \
  --restarts=1 --threads=2 --json_out=two.json \
  --driver="$apps/activecal_sim_cell ${ur[*]} --frames=two_markers.yaml ${sim[*]}" \
  >two.out 2>two.err || { fail "active, two markers"; cat two.err; }
! grep -q "b\.[xyz] held fixed" two.out && grep -q "a combination of .*b\.[xyz]" two.out &&
  ok "active: the second marker's offsets are not held fixed" || { fail "active two markers"; grep "held fixed" two.out; }
"$apps/activecal_active" "${ur[@]}" --levels=3 --max_rounds=2 --restarts=1 --threads=2 \
  --json_out=ur_loop.json --driver="$apps/activecal_sim_cell ${ur[*]} ${sim[*]}" \
  >ur_loop.out 2>ur_loop.err &&
  python3 -c 'import json; d = json.load(open("ur_loop.json")); assert len(d["rounds"]) == 2, d["rounds"]' &&
  ok "active: the UR10e loop without a cell runs its rounds" || { fail "UR10e active loop"; tail -2 ur_loop.err; }


cli_end
