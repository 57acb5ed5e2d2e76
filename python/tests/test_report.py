# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Estimate.write_report: the HTML report of activecal_identify
--report_html, through the same library call; its numbers are the
estimate's (in mm / mrad, SI in data-value)."""
import re

import numpy as np

import activecal


def test_write_report_holds_the_estimates(tmp_path):
    puma = activecal.puma560()
    rng = np.random.default_rng(0)
    lo, hi = puma.joint_limits.T
    q = lo + (hi - lo) * rng.random((40, 6))
    measured = activecal.simulate(puma, q, noise_m=1e-4, seed=1)
    estimate = activecal.identify(puma, measured, model_selection="none")
    path = tmp_path / "report.html"
    estimate.write_report(path, measurements="simulated")
    html = path.read_text()
    assert html.startswith("<!DOCTYPE html>")
    assert 'class="histogram"' in html and 'class="heatmap"' in html
    assert "<script" not in html and "http://" not in html.replace(
        'xmlns="http://www.w3.org/2000/svg"', "")
    for name, value, std in zip(estimate.parameter_names, estimate.estimates,
                                estimate.std):
        m = re.search(r'data-key="parameter\.%s\.estimate" '
                      r'data-value="([^"]+)">([^<]+)<' % re.escape(name), html)
        assert m, name
        assert float(m.group(1)) == value
        assert m.group(2) == "%.3f" % (1e3 * value)
        m = re.search(r'data-key="parameter\.%s\.std" data-value="([^"]+)"'
                      % re.escape(name), html)
        assert float(m.group(1)) == std
