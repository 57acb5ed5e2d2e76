#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# --quiet's one result line of the programs other than identify and select
# (those are in output_cli_test.sh and select_cli_test.sh): the line is the
# last on stdout without --quiet and the only one with it, its figures are
# the JSON's, and the files written are byte-identical either way. The case
# is 6D (position + orientation): FIGAROH's UR10e measurements.
#
#   tests/quiet_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

m="$data/figaroh_ur10e/measurements.csv"

# --- activecal_evaluate ---
evaluate=("$apps/activecal_evaluate" --robot="$data/ur10e.urdf" --tip_link=tool0
  --measurements="$m")
if ! "${evaluate[@]}" --json_out=eval.json >out.txt 2>err.txt; then
  fail "evaluate runs"; cat err.txt
fi
"${evaluate[@]}" --quiet --json_out=eval_quiet.json >qout.txt 2>qerr.txt ||
  fail "evaluate --quiet runs"
[ "$(wc -l <qout.txt)" -eq 1 ] && [ ! -s qerr.txt ] &&
  ok "evaluate --quiet prints one line" ||
  { fail "evaluate --quiet prints one line"; cat qout.txt qerr.txt; }
[ "$(tail -1 out.txt)" = "$(cat qout.txt)" ] &&
  ok "evaluate: the --quiet line is the last line without it" ||
  { fail "evaluate: the --quiet line is the last line without it"; tail -1 out.txt; }
cmp -s eval.json eval_quiet.json && ok "evaluate --quiet writes the same JSON" ||
  fail "evaluate --quiet writes the same JSON"
# The line's figures are the JSON's (mm and deg, rounded as printed).
check=$(
  python3 - eval.json qout.txt <<'PY'
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
if rms <= 0 or rot <= 0: bad.append("zero")
print("ok" if not bad else "mismatch " + " ".join(bad) + ": " + line)
PY
)
[ "$check" = "ok" ] && ok "evaluate's line is the JSON's count, RMS, max, orientation" ||
  fail "evaluate's line is the JSON's count, RMS, max, orientation ($check)"

cli_end
