#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Progress lines of identify's model selection (the cross-validation
# splits, as each finishes) and of activecal_active's rounds: on stderr, in
# order, none with --quiet, stdout the same either way. The 2 s after
# which a progress line appears is set to 0 (ACTIVECAL_PROGRESS_AFTER_S) so
# that short runs print them.
#
#   tests/progress_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"
export ACTIVECAL_PROGRESS_AFTER_S=0

joint_columns "$data/figaroh_ur10e/measurements.csv" p.csv
ur=(--robot="$data/ur10e.urdf" --tip_link=tool0)
"$apps/activecal_simulate" "${ur[@]}" --poses_csv=p.csv --perturb_m=0.001 \
  --perturb_rad=0.001 --noise_m=0.0001 --seed=2 --out=m.csv --quiet >/dev/null ||
  fail "simulate"

# --- identify: 5 folds and the whole training set, 6 splits. ---
identify=("$apps/activecal_identify" "${ur[@]}" --measurements=m.csv --model_selection=cv --folds=5)
"${identify[@]}" >id.out 2>id.err || { fail "identify runs"; cat id.err; }
"${identify[@]}" --quiet >idq.out 2>idq.err || { fail "identify --quiet runs"; cat idq.err; }
want=$(for k in 1 2 3 4 5 6; do echo "$k/6"; done)
got=$(sed -nE 's/^activecal_identify: model selection: splits fitted \(the training set and each fold\): ([0-9]+\/[0-9]+).*/\1/p' id.err)
[ "$got" = "$want" ] && ok "identify: a line per split, in order (1/6 ... 6/6)" ||
  { fail "identify: a line per split, in order"; cat id.err; }
[ ! -s idq.err ] && ok "identify --quiet: no progress line" ||
  { fail "identify --quiet: no progress line"; cat idq.err; }
grep -q "splits fitted" id.out && fail "identify: no progress line on stdout" ||
  ok "identify: no progress line on stdout"

# --- activecal_active: a line per round, as the rounds of the table. ---
active=("$apps/activecal_active" --levels=3 --target_rms_m=1e-4 --json_out=a.json)
"${active[@]}" >a.out 2>a.err || { fail "active runs"; cat a.err; }
"${active[@]}" --quiet >aq.out 2>aq.err || { fail "active --quiet runs"; cat aq.err; }
rounds=$(python3 -c "import json; print(len(json.load(open('a.json'))['rounds']))")
want=$(seq 0 $((rounds - 1)))
got=$(sed -nE 's/^activecal_active: round ([0-9]+) done: [0-9]+ poses, predicted task RMS .* m \([0-9.]+ s\)$/\1/p' a.err)
[ "$rounds" -ge 2 ] && [ "$got" = "$want" ] &&
  ok "active: a line per round, in order (0 ... $((rounds - 1)))" ||
  { fail "active: a line per round, in order ($rounds rounds)"; cat a.err; }
[ ! -s aq.err ] && ok "active --quiet: no progress line" ||
  { fail "active --quiet: no progress line"; cat aq.err; }

cli_end
