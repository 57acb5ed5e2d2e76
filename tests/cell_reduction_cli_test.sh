#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# The active loop's parameter set with several cell targets (issue #24):
# activecal_active and activecal_sim_cell reduce --parameter_set on the
# markers each pose of the feasible pool sees (ReduceForPool), not on
# marker 0 alone. A UR10e (data/ur10e.urdf) in the table cell of
# data/cells/ur10e_table.yaml with a second target: seen on part of the
# pool, its offsets stay free; never seen (on the flange's back, facing the
# wrist), they are held with a reason that says so.
#
#   tests/cell_reduction_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

# The table cell without its targets, then two targets.
two_target_cell
{ cat base.yaml; cat <<'YAML'
targets:
  - {name: smr, xyz_m: [0, 0, 0.06], normal: [0, 0, 1], acceptance_deg: 30}
  - {name: back, xyz_m: [0, 0, -0.02], normal: [0, 0, -1], acceptance_deg: 10}
YAML
} >never.yaml

ur=(--robot="$data/ur10e.urdf" --tip_link=tool0)
run() {  # run <cell>: the loop through activecal_sim_cell in that cell
  "$apps/activecal_active" "${ur[@]}" --cell="$1.yaml" --levels=4 \
    --max_rounds=2 --restarts=1 --threads=2 --json_out="$1.json" \
    --driver="$apps/activecal_sim_cell ${ur[*]} --cell=$1.yaml --perturb_m=0.001 --perturb_rad=0.001 --seed=2" \
    >"$1.out" 2>"$1.err"
}

# --- The second target seen on part of the pool: its offsets are free. ---
if run two; then ok "active --cell with two targets"; else fail "active two"; cat two.err; fi
python3 - <<'PY' && ok "the second target is seen on part of the pool" || fail "second target's poses"
import json
d = json.load(open("two.json"))
seen = [s for s in d["targets_seen"]]
assert any("side" in s for s in seen) and any("side" not in s for s in seen), seen
PY
# The loop's lines come before its table; the simulated robot's on stderr.
sed '/^activecal active loop/,$d' two.out >two.set
if grep -q "held fixed: a combination of side\." two.set &&
  ! grep -q "side\.[xyz] held fixed" two.set; then
  ok "the loop identifies the second target's offsets"
else
  fail "the second target's offsets held"; cat two.set
fi
grep -q -- "--parameter_set=full: smr.x held" two.err two.set &&
  fail "the first target held" || ok "the first target's offsets free"
! grep -q "side\.[xyz] held fixed" two.err &&
  ok "the simulated robot's truth moves the second target too" ||
  { fail "sim_cell holds the second target"; grep side two.err; }

# --- The second target never seen: held, and the reason says so. ---
if run never; then ok "active --cell, a target never seen"; else fail "active never"; cat never.err; fi
sed '/^activecal active loop/,$d' never.out >never.set
for p in x y z; do
  if grep -qE "^  --parameter_set=full: back\.$p held fixed: marker 'back' is seen at none of the [0-9]+ poses of the pool$" never.set; then
    ok "back.$p held: never seen"
  else
    fail "back.$p held with its reason"; cat never.set
  fi
done
grep -q "smr\.[xyz] held fixed" never.set && fail "smr held" || ok "smr's offsets free"

cli_end
