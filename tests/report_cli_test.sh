#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# The HTML report (--report_html) rendered in headless Chromium: its figures
# exist, its numbers equal the JSON report's, the "after" errors spread
# over several log bins, it prints to PDF; the warnings of the README's
# UR10e example and of the UR10's URDF on the UR10e's data.
#
#   tests/report_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

chromium_run() {
  timeout 120 chromium --headless --no-sandbox --disable-gpu \
    --disable-background-networking --no-first-run --disable-component-update \
    --disable-sync --user-data-dir="$(mktemp -d -p "$work")" "$@" 2>/dev/null
}

m="$data/figaroh_ur10e/measurements.csv"
# The README's UR10e example, with the report.
if "$apps/activecal_identify" --robot="$data/ur10e.urdf" --tip_link=tool0 \
  --measurements="$m" --rotation_weight=0.1 --json_out=ur10e.json \
  --urdf_out=cal.urdf --frames_out=frames.yaml \
  --report_html=ur10e.html >ur10e.txt 2>ur10e.err; then
  ok "identify UR10e with --report_html"
else
  fail "identify UR10e with --report_html"; cat ur10e.err
fi
# The README's evaluation of the calibrated URDF, with its report.
if "$apps/activecal_evaluate" --robot=cal.urdf --tip_link=tool0 \
  --frames=frames.yaml --measurements="$m" --nominal_robot="$data/ur10e.urdf" \
  --json_out=eval.json --report_html=eval.html >eval.txt 2>eval.err; then
  ok "evaluate UR10e with --report_html"
  # It estimates no parameter: a sentence, not a table of its header only.
  if grep -q 'class="parameters"' eval.html ||
    ! grep -q 'No parameters were estimated here' eval.html; then
    fail "evaluate's report: no empty parameters table"
  else
    ok "evaluate's report: no empty parameters table"
  fi
else
  fail "evaluate UR10e with --report_html"; cat eval.err
fi
# Simulated PUMA position data with held-out poses: every number of the
# report has a JSON counterpart.
if "$apps/activecal_identify" --num_poses=60 --validation_fraction=0.3 \
  --json_out=puma.json --report_html=puma.html >puma.txt 2>puma.err; then
  ok "identify PUMA with --report_html and held-out poses"
else
  fail "identify PUMA with --report_html"; cat puma.err
fi

for r in ur10e puma eval; do
  if chromium_run --dump-dom "file://$work/$r.html" >"$r.dom.html" &&
    grep -q "</svg>" "$r.dom.html"; then
    ok "$r: rendered by headless Chromium (--dump-dom)"
  else
    fail "$r: rendered by headless Chromium"
  fi
done
if chromium_run --print-to-pdf="$work/ur10e.pdf" "file://$work/ur10e.html" &&
  [ "$(head -c 4 ur10e.pdf)" = "%PDF" ] && [ "$(wc -c <ur10e.pdf)" -gt 20000 ]; then
  ok "ur10e: printed to PDF ($(wc -c <ur10e.pdf) bytes)"
else
  fail "ur10e: printed to PDF"
fi

if python3 - <<'PY'
import json, math
from html.parser import HTMLParser

class Dom(HTMLParser):
    """Figures by class, data-key cells (SI value and printed text)."""
    def __init__(self):
        super().__init__()
        self.svgs, self.bars, self.cells, self.points = [], [], {}, []
        self.key, self.text, self.links = None, "", []
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "svg":
            self.svgs.append(a.get("class"))
        if tag == "rect" and a.get("class") == "bar":
            self.bars.append((self.svgs[-1], len(self.svgs), int(a["data-series"]),
                              int(a["data-value"])))
        if tag == "circle" and a.get("class") == "point":
            self.points.append(a)
        if tag == "td" and "data-key" in a:
            self.key, self.text = a["data-key"], ""
            self.cells[self.key] = [float(a["data-value"]), None]
        for k in ("src", "href"):
            if tag != "a" and k in a:
                self.links.append(a[k])
    def handle_data(self, d):
        if self.key:
            self.text += d
    def handle_endtag(self, tag):
        if tag == "td" and self.key:
            self.cells[self.key][1] = self.text.strip()
            self.key = None

def parse(name):
    d = Dom()
    d.feed(open(name + ".dom.html").read())
    return d

def close(a, b, what):
    assert abs(a - b) <= 1e-12 * max(abs(a), abs(b), 1e-12), (what, a, b)

def printed(cell, scale, what):
    value, text = cell
    want = "%.3f" % (scale * value)
    assert text == ("0.000" if want == "-0.000" else want), (what, text, value)

for name in ("ur10e", "puma"):
    d = parse(name)
    j = json.load(open(name + ".json"))
    assert d.links == [], (name, "external resources", d.links)
    for figure in ("histogram", "heatmap"):
        assert figure in d.svgs, (name, figure, d.svgs)
    # Parameters: estimate and std as the JSON's, printed in mm / mrad.
    for p in j["parameters"]:
        for field in ("estimate", "std", "nominal"):
            c = d.cells["parameter.%s.%s" % (p["name"], field)]
            close(c[0], p[field], p["name"] + " " + field)
            printed(c, 1e3, p["name"])
    assert len([k for k in d.cells if k.startswith("parameter.")]) == \
        4 * len(j["parameters"])
    # The "after" errors of the fitted poses spread over several log bins
    # (the first histogram: fitted poses' position errors; series 1 after).
    first = min(i for (_, i, _, _) in d.bars)
    after = [c for (cls, i, s, c) in d.bars if i == first and s == 1]
    before = [c for (cls, i, s, c) in d.bars if i == first and s == 0]
    assert sum(after) == j["num_measurements"], (name, sum(after))
    assert sum(1 for c in after if c > 0) >= 3, (name, "after in", after)
    assert sum(before) == j["num_measurements"]
    if j["model_selection"]["curve"]:
        assert "curve" in d.svgs
        for pt in j["model_selection"]["curve"]:
            c = d.cells["selection.%d.training_rms" % pt["num_kept"]]
            close(c[0], pt["training_rms_m"], "curve")
            printed(c, 1e3, "curve")

# Position data: the norms of the report are the JSON's residuals.
d = parse("puma")
j = json.load(open("puma.json"))
close(d.cells["after.training.position.norm.rms"][0], j["rms_residual_m"],
      "after training rms")
printed(d.cells["after.training.position.norm.rms"], 1e3, "rms")
norms = [r["norm_m"] for r in j["residuals"]]
close(d.cells["after.training.position.norm.max"][0], max(norms), "max")
v = j["validation"]
close(d.cells["after.held_out.position.norm.rms"][0], v["rms_error_calibrated_m"],
      "held-out after")
close(d.cells["after.held_out.position.norm.max"][0], v["max_error_calibrated_m"],
      "held-out max")
close(d.cells["before.held_out.position.norm.rms"][0],
      v["rms_error_registration_only_m"], "held-out before")
close(d.cells["before.training.position.norm.rms"][0],
      j["registration_only"]["rms_residual_m"], "before training")
# Per-axis RMS combine to the norm's.
axes = sum(d.cells["after.training.position.%s.rms" % a][0] ** 2 for a in "xyz")
close(math.sqrt(axes), j["rms_residual_m"], "axes")
assert any(k.startswith("group.") for k in d.cells), "no posture groups"
# The UR10e's orientation errors in degrees beside the mm.
u = parse("ur10e")
assert "after.training.orientation.angle.rms" in u.cells
# The evaluation report: the numbers of evaluate's JSON.
e = parse("eval")
j = json.load(open("eval.json"))
assert e.svgs.count("histogram") == 2, e.svgs
for side in ("before", "after"):
    c = e.cells
    s = j[side]
    close(c[side + ".evaluated.position.norm.rms"][0], s["rmse_m"], side)
    printed(c[side + ".evaluated.position.norm.rms"], 1e3, side)
    close(c[side + ".evaluated.position.norm.p95"][0], s["p95_m"], side)
    close(c[side + ".evaluated.position.norm.max"][0], s["max_m"], side)
    for k, a in enumerate("xyz"):
        close(c[side + ".evaluated.position.%s.rms" % a][0], s["rmse_xyz_m"][k], a)
        close(c[side + ".evaluated.position.%s.mean" % a][0], s["mean_xyz_m"][k], a)
    o = s["orientation_rad"]
    close(c[side + ".evaluated.orientation.angle.rms"][0], o["rms"], side)
    printed(c[side + ".evaluated.orientation.angle.rms"], 180 / math.pi, side)
PY
then
  ok "report figures exist, numbers equal the JSON's, after spread over bins"
else
  fail "report numbers and figures"
fi

# The README's UR10e example: no outlier flagged below the RMS residual.
if python3 - <<'PY'
import json
j = json.load(open("ur10e.json"))
rms = j["rms_residual_m"]
low = [r["index"] for r in j["residuals"] if r["outlier"] and r["norm_m"] <= rms]
assert not low, ("outliers below the RMS", low)
PY
then
  ok "UR10e: no outlier with a residual below the RMS"
else
  fail "UR10e: no outlier with a residual below the RMS"
fi

# The right robot warns of nothing; the UR10's URDF on the UR10e's data
# (the README's command otherwise): the warnings still say what is wrong.
if grep -q "warning" ur10e.txt; then
  fail "UR10e: no warning"; grep warning ur10e.txt
else
  ok "UR10e: no warning"
fi
if "$apps/activecal_identify" --robot="$data/ur10.urdf" --tip_link=tool0 \
  --measurements="$m" --rotation_weight=0.1 \
  --json_out=ur10.json >ur10.txt 2>ur10.err &&
  grep -q "warning: .*moved from nominal by more than 5 mm / 10 mrad.*is the nominal model the right one?" ur10.txt; then
  ok "UR10 URDF on UR10e data: the moved-from-nominal warning"
else
  fail "UR10 URDF on UR10e data: the moved-from-nominal warning"; grep warning ur10.txt; cat ur10.err
fi

# Bad input: one line each, status 1, nothing written.
expect_fail "did you mean" "unknown command line flag 'num_pose' (did you mean --num_poses?)" \
  activecal_identify --num_pose=3
expect_fail "did you mean (evaluate)" "unknown command line flag 'measurement' (did you mean --measurements?)" \
  activecal_evaluate --measurement=m.csv
expect_fail "nothing close" "unknown command line flag 'frobnicate' (see --help)" \
  activecal_select --frobnicate
expect_fail "outlier probability" "outlier_probability must be in (0, 1), got 2" \
  activecal_identify --num_poses=40 --outlier_probability=2
expect_fail "report not writable" "--report_html: " \
  activecal_identify --num_poses=40 --report_html=/nonexistent/dir/r.html
if "$apps/activecal_identify" -h >help.txt 2>&1 || true; grep -q "report_html" help.txt; then
  ok "-h is --help"
else
  fail "-h is --help"; head help.txt
fi

cli_end
