#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Joint error terms end to end (activecal_identify --compliance
# --harmonics): on FIGAROH's UR10e data each candidate's held-out error in
# the JSON and the printout, the families kept exactly those whose paired
# gain exceeds the rule's standard errors; bad inputs end with status 1 and
# one line.
#
#   tests/accuracy_terms_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

figaroh_ur10e

"$apps/activecal_identify" "${ur[@]}" --measurements="$m" \
  --model_selection=none --compliance --payload_kg=1.0 \
  --payload_com_m=0,0,0.05 --harmonics=1 --json_out=terms.json \
  >terms.txt 2>terms.err || { fail "identify --compliance --harmonics"; cat terms.err; }
python3 - <<'PY' && ok "terms: every candidate's held-out error; kept = gain > 2 SE" || fail "terms report"
import json
r = json.load(open("terms.json"))["joint_error_terms"]
c = r["candidates"]
assert c[0]["name"] == "geometric" and c[0]["held_out_rms_m"] > 0, c[0]
assert len(c) >= 3, c
names = [x["name"] for x in c]
assert "geometric + compliance" in names and "geometric + periodic" in names, names
assert sum(x["chosen"] for x in c) == 1
# The rule: with nothing kept, no single family's gain exceeds the rule's
# standard errors; otherwise the chosen candidate's does.
rule = lambda x: x["ok"] and x["gain_m2"] > r["rule_standard_errors"] * x["gain_se_m2"]
chosen = [x for x in c if x["chosen"]][0]
if not r["kept"]:
    assert chosen["name"] == "geometric"
    assert not any(rule(x) for x in c if x["name"].count(" + ") == 1), c
else:
    assert rule(chosen) and chosen["name"].endswith(r["kept"][-1]), chosen
# Compliance of the vertical first axis is not identifiable.
assert any(d.startswith("shoulder_pan_joint.compliance") for d in r["not_identifiable"]), r["not_identifiable"]
kept_terms = [t["name"] for t in r["terms"]]
if "compliance" in r["kept"]:
    assert any(n.endswith(".compliance") for n in kept_terms)
else:
    assert not any(n.endswith(".compliance") for n in kept_terms)
PY
grep -q "joint error terms by held-out error" terms.txt &&
  grep -q "held-out RMS" terms.txt && ok "terms printed" ||
  { fail "terms printout"; cat terms.txt; }

printf 'type,q1_rad,q2_rad,x_m,y_m,z_m\nposition,0,0,1,0,0\n' >bare.csv
expect_fail "compliance on a URDF without inertials names the links" \
  "compliance needs link masses: no <inertial> with a mass > 0 on links b, c" \
  activecal_identify --robot="$here/data/massless_arm.urdf" --measurements=bare.csv \
  --compliance
expect_fail "compliance on a robot YAML without a payload" \
  "--compliance needs link masses: --robot $data/puma560.yaml is not a URDF" \
  activecal_identify --robot="$data/puma560.yaml" --compliance
expect_fail "a payload without mass" \
  "--payload_com_m needs --payload_kg > 0 (a payload without mass)" \
  activecal_identify "${ur[@]}" --measurements="$m" --compliance \
  --payload_com_m=0,0,0.1
expect_fail "a payload without compliance" \
  "--payload_kg is used by --compliance only" \
  activecal_identify "${ur[@]}" --measurements="$m" --payload_kg=2
expect_fail "gravity not three numbers" \
  "--gravity: expected 'x,y,z' in m/s^2, got '0,0'" \
  activecal_identify "${ur[@]}" --measurements="$m" --compliance --gravity=0,0
expect_fail "harmonics out of range" "--harmonics must be in [0, 8], got 9" \
  activecal_identify "${ur[@]}" --measurements="$m" --harmonics=9
expect_fail "terms with a MAP fit" \
  "joint error terms (compliance, harmonics) are chosen by held-out error, not with a MAP fit" \
  activecal_identify "${ur[@]}" --measurements="$m" --harmonics=1 \
  --prior_std_m=0.001 --model_selection=none

cli_end
