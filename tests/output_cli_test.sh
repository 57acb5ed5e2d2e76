#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# What activecal_identify prints for a person, on the README's UR10e
# example: each held parameter named once (in the reduction's table or as a
# row of the model-selection curve), the parameter table aligned whatever
# the names' length, mm / deg beside SI, --quiet printing only the result,
# and the note when 6D data are fitted without --rotation_weight.
#
#   tests/output_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

m="$data/figaroh_ur10e/measurements.csv"
identify=("$apps/activecal_identify" --robot="$data/ur10e.urdf" --tip_link=tool0
  --measurements="$m")
if ! "${identify[@]}" --rotation_weight=0.1 --json_out=ur10e.json >out.txt 2>err.txt; then
  fail "UR10e example runs"; cat err.txt
fi

# --- Each held parameter named once. ---
python3 -c 'import json,sys; print("\n".join(json.load(open(sys.argv[1]))["auto_fixed"]))' \
  ur10e.json >held.txt
held_count=$(wc -l <held.txt)
[ "$held_count" -eq 41 ] && ok "41 held parameters in the JSON" ||
  fail "41 held parameters in the JSON, got $held_count"
twice=0
while read -r name; do
  # As the first cell of the reduction's table or the 'added' cell of the
  # curve; anywhere else in the output only inside a reason.
  n=$(awk -v n="$name" '($1 == n) || ($1 ~ /^[0-9]+$/ && $2 == n)' out.txt | wc -l)
  if [ "$n" -ne 1 ]; then
    echo "  $name listed $n times"; twice=$((twice + 1))
  fi
done <held.txt
[ "$twice" -eq 0 ] && ok "each held parameter listed once" ||
  fail "each held parameter listed once ($twice are not)"
# The old lists (the same names twice more) are gone.
if grep -q "holding them at their nominal values:\|held at their start values:" out.txt; then
  fail "no list repeating the held names"; grep -n "holding\|start values" out.txt
else
  ok "no list repeating the held names"
fi
grep -q "^  41 of 54 free parameters held fixed at their nominal values (not in 'free'): 24 by --parameter_set=full, 17 by --model_selection=cv, named above$" out.txt &&
  ok "held count grouped by stage" || { fail "held count grouped by stage"; tail -5 out.txt; }
grep -q "^  the 17 parameters added after '<- kept' are held at their start values$" out.txt &&
  ok "model selection's held parameters are the rows after '<- kept'" ||
  fail "model selection's held parameters are the rows after '<- kept'"

# --- The parameter table: aligned, mm / deg beside SI. ---
awk '/^parameter /{t=1} t&&/^$/{exit} t' out.txt >table.txt
rows=$(($(wc -l <table.txt) - 1))
[ "$rows" -eq 13 ] && ok "13 parameters in the table" ||
  { fail "13 parameters in the table, got $rows"; cat out.txt; }
# Every right-aligned column ends where its header ends, the longest name
# (wrist_1_joint.rx, 16 characters) included.
bad=$(
  python3 - table.txt <<'PY'
import re, sys
lines = open(sys.argv[1]).read().splitlines()
header = lines[0]
# The end of each right-aligned header (all but parameter, unit, in).
ends = [m.end() for m in re.finditer(r"\S+", header)][2:-1]
bad = 0
for line in lines[1:]:
    cells = [m.end() for m in re.finditer(r"\S+", line)]
    if cells[2:-1] != ends:
        bad += 1
print(bad)
PY
)
[ "$bad" = "0" ] && ok "table columns aligned under their headers" ||
  { fail "table columns aligned under their headers ($bad rows)"; cat table.txt; }
grep -q "^wrist_1_joint.rx  rad .* -0.4583 .* deg$" table.txt &&
  grep -q "^B.z  .* m .* 837.305 .* mm$" table.txt &&
  ok "mm and deg beside SI (B.z 0.837305 m = 837.305 mm, wrist_1_joint.rx -0.007999 rad = -0.4583 deg)" ||
  { fail "mm and deg beside SI"; cat table.txt; }

# --- The one-line result, last on stdout; --quiet prints only it. ---
result="activecal_identify: 13 of 54 parameters identified from 23 measurements, RMS position 3.181 mm, rotation 7.529 mrad (registration only 3.461 mm, 10.039 mrad)"
[ "$(tail -1 out.txt)" = "$result" ] && ok "result line last" ||
  { fail "result line last"; tail -2 out.txt; }
"${identify[@]}" --rotation_weight=0.1 --quiet --json_out=quiet.json >qout.txt 2>qerr.txt
[ "$(cat qout.txt)" = "$result" ] && [ ! -s qerr.txt ] &&
  ok "--quiet prints the result only" ||
  { fail "--quiet prints the result only"; cat qout.txt qerr.txt; }
cmp -s ur10e.json quiet.json && ok "--quiet writes the same JSON" ||
  fail "--quiet writes the same JSON"
# Errors still reach stderr, one line.
expect_fail "--quiet keeps errors" "--rotation_weight" activecal_identify \
  --robot="$data/ur10e.urdf" --tip_link=tool0 --measurements="$m" \
  --rotation_weight=-1 --quiet
[ ! -s out.txt ] && ok "--quiet failure prints nothing on stdout" ||
  { fail "--quiet failure prints nothing on stdout"; cat out.txt; }
# Every program has the flag.
missing=0
for p in activecal_select activecal_evaluate activecal_simulate activecal_active \
  activecal_compensate activecal_monte_carlo activecal_sim_cell activecal_puma_paper; do
  help=$("$apps/$p" --help 2>&1)
  [[ "$help" == *"-quiet (Print only errors"* ]] || { echo "  $p"; missing=$((missing + 1)); }
done
[ "$missing" -eq 0 ] && ok "every program lists --quiet" ||
  fail "every program lists --quiet ($missing do not)"

# --- 6D data without --rotation_weight: a note. ---
if grep -q "note: --rotation_weight" out.txt; then
  fail "no --rotation_weight note when the flag is given"
else
  ok "no --rotation_weight note when the flag is given"
fi
"${identify[@]}" >out1.txt 2>&1
note=$(grep "note: --rotation_weight not given" out1.txt)
echo "$note" | grep -q "weighted 1 m/rad and 22 parameters kept" &&
  ok "--rotation_weight note: $note" ||
  { fail "--rotation_weight note"; tail -5 out1.txt; }

# (The default delay, not cli_begin's.)
unset ACTIVECAL_PROGRESS_AFTER_S
# --- Progress lines: on stderr once a step has run 2 s (here a file, not a
# terminal), flushed as they happen; none on a short run; none with --quiet.
# One thread: the 117,649-pose PUMA lattice's 16 Fedorov restarts take
# 1.5-5 s of CPU; the long run's delay is 0.5 s (ACTIVECAL_PROGRESS_AFTER_S)
# so that a quick host prints its lines too (at 2 s it once printed none on
# a run of 3 s); the short run below keeps the 2 s default.
select=("$apps/activecal_select" --robot="$data/puma560.yaml" --num_poses=30
  --certificate=false --threads=1)
ACTIVECAL_PROGRESS_AFTER_S=0.5 "${select[@]}" --levels=7 >long.out 2>long.err
if grep -Eq "^activecal_select: fedorov restarts: [0-9]+/16 " long.err; then
  ok "progress lines on a long run: $(tail -1 long.err)"
else
  fail "progress lines on a long run"; cat long.err
fi
grep -q "restarts:" long.out && fail "no progress line on stdout" ||
  ok "no progress line on stdout"
# A progress line appears only after a step has run 2 s: a run that ends
# sooner prints none. (Under the sanitizers the same run can take longer
# than 2 s; then there is nothing to check.)
start_ns=$(date +%s%N)
"${select[@]}" --levels=3 >short.out 2>short.err
elapsed_ms=$((($(date +%s%N) - start_ns) / 1000000))
if [ "$elapsed_ms" -lt 2000 ]; then
  [ ! -s short.err ] && ok "no progress line on a short run (${elapsed_ms} ms)" ||
    { fail "no progress line on a short run (${elapsed_ms} ms)"; cat short.err; }
else
  ok "short run took ${elapsed_ms} ms here (>= 2 s): its progress lines not checked"
fi
"${select[@]}" --levels=7 --quiet >qlong.out 2>qlong.err
[ ! -s qlong.err ] && [ "$(wc -l <qlong.out)" -eq 1 ] &&
  [ "$(cat qlong.out)" = "$(tail -1 long.out)" ] &&
  grep -q "^activecal_select: 30 poses of 117649 (fedorov), log10 det " qlong.out &&
  ok "--quiet select: $(cat qlong.out)" ||
  { fail "--quiet select"; cat qlong.out qlong.err; }

cli_end
