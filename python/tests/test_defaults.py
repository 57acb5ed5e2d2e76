# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""One set of defaults: every flag of activecal_select and activecal_simulate
that has a keyword twin in the module has the same default in both, and
the value calibration/defaults.h states."""
import re
import subprocess

import pytest

import activecal
from conftest import BUILD_DIR, SOURCE_DIR

# (program, flag, function, keyword argument)
TWINS = [("activecal_select", f, activecal.select, f) for f in (
    "algorithm", "criterion", "num_poses", "seed", "levels", "pool_size",
    "measurement", "rotation_weight", "auto_fix", "restarts",
    "initial_poses", "random_designs", "certificate", "approx_tolerance",
    "polish_pool_size", "pool_storage", "max_double_pool_mib", "noise_m")]
TWINS += [("activecal_select", "threads", activecal.select, "num_threads")]
TWINS += [("activecal_simulate", f, activecal.simulate, f)
          for f in ("noise_m", "seed", "type", "rotation_noise_rad")]


def python_default(function, name):
    match = re.search(r"\b%s: [\w.\[\]]+ = ([^,)]+)" % name, function.__doc__)
    assert match, "%s has no default for %s" % (function.__name__, name)
    return match.group(1).strip("'\"")


def flag_default(program, name):
    path = BUILD_DIR / "apps" / program
    if not path.exists():
        pytest.skip("%s not built" % program)
    text = subprocess.run([str(path), "--help"], capture_output=True,
                          text=True).stdout + ""
    match = re.search(r"^    -%s \(.*?\)\s+type: \w+\s+default: (\S+)" % name,
                      text, re.S | re.M)
    assert match, "%s --help lists no --%s" % (program, name)
    return match.group(1).strip('"')


def same(a, b):
    truth = {"true": "1", "false": "0", "True": "1", "False": "0"}
    a, b = truth.get(a, a), truth.get(b, b)
    try:
        return float(a) == float(b)
    except ValueError:
        return a == b


@pytest.mark.parametrize("program,flag,function,keyword", TWINS)
def test_flag_and_keyword_share_the_default(program, flag, function, keyword):
    cli = flag_default(program, flag)
    py = python_default(function, keyword)
    assert same(cli, py), "--%s of %s is %s, %s(%s=) is %s" % (
        flag, program, cli, function.__name__, keyword, py)


def test_the_defaults_are_those_of_the_header():
    header = (SOURCE_DIR / "calibration" / "include" / "activecal" /
              "calibration" / "defaults.h").read_text()
    values = dict(re.findall(r"constexpr \w+ (k\w+)(?:\[\])? = ([^;]+);",
                             header))
    assert values["kSelectAlgorithm"] == '"fedorov"'
    checks = [(activecal.select, "algorithm", "kSelectAlgorithm"),
              (activecal.select, "noise_m", "kDesignNoiseM"),
              (activecal.select, "rotation_weight", "kRotationWeightMPerRad"),
              (activecal.simulate, "noise_m", "kSimulationNoiseM"),
              (activecal.simulate, "rotation_noise_rad",
               "kSimulationRotationNoiseRad")]
    for function, keyword, constant in checks:
        assert same(python_default(function, keyword),
                    values[constant].strip('"')), (keyword, constant)
