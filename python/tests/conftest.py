# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Shared fixtures of the activecal pytest suite.

Run by ctest (python_test) with PYTHONPATH=<build>/python and
ACTIVECAL_BUILD_DIR / ACTIVECAL_SOURCE_DIR set; by hand:

    PYTHONPATH=build/python python3 -m pytest -q python/tests
"""
import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

import activecal

SOURCE_DIR = pathlib.Path(
    os.environ.get("ACTIVECAL_SOURCE_DIR",
                   pathlib.Path(__file__).resolve().parents[2]))
BUILD_DIR = pathlib.Path(
    os.environ.get("ACTIVECAL_BUILD_DIR", SOURCE_DIR / "build"))
PUMA = str(SOURCE_DIR / "data" / "puma560.yaml")
UR10 = str(SOURCE_DIR / "data" / "ur10.urdf")


def readme_python_example():
    """The README's Python example: (code, what it prints)."""
    readme = (SOURCE_DIR / "README.md").read_text()
    block = re.search(
        r"<!-- python-example[^>]*-->\n```python\n(.*?)```\n\nprints\n\n"
        r"((?:    [^\n]*\n)+)", readme, re.S)
    assert block, "the README's Python example is gone"
    printed = "".join(line[4:] + "\n"
                      for line in block.group(2).splitlines())
    return block.group(1), printed


def program(name):
    """Path of a C++ program of the same build; skips when not built."""
    path = BUILD_DIR / "apps" / name
    if not path.exists():
        pytest.skip(f"{path} is not built (ACTIVECAL_BUILD_APPS=OFF?)")
    return str(path)


def perturbed_session(robot, amplitude, wave, num_poses, noise_m, **select):
    """Measurements of `robot` whose truth is its nominal with every
    parameter of the full set moved by amplitude * wave(index): at a design
    of num_poses poses (select(levels=3, seed=1, **select)), simulated with
    noise_m (seed 3). Returns (measurements, truth)."""
    full = robot.with_parameter_set("full")
    truth = robot.nominal + np.where(full.free, amplitude, 0.0) * wave(
        np.arange(robot.num_parameters))
    design = activecal.select(robot, levels=3, num_poses=num_poses, seed=1,
                              **select)
    m = activecal.simulate(robot, design.joint_angles, noise_m=noise_m,
                           seed=3, parameters=truth)
    return m, truth


def puma_measurements(num_poses, pool_size):
    """The PUMA file's robot and its nominal measured at a lattice design
    of num_poses poses (select(levels=3, seed=2, pool_size=pool_size)),
    simulated with 0.1 mm noise (seed 4). Returns (robot, measurements)."""
    puma = activecal.load_robot(PUMA)
    design = activecal.select(puma, levels=3, num_poses=num_poses, seed=2,
                              pool_size=pool_size)
    return puma, activecal.simulate(puma, design.joint_angles, noise_m=1e-4,
                                    seed=4)


def run(args):
    """Runs a program, failing the test with its stderr if it fails."""
    done = subprocess.run(args, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


@pytest.fixture(scope="session")
def puma():
    return activecal.load_robot(PUMA)


@pytest.fixture(scope="session")
def ur10():
    return activecal.load_robot(UR10, tip_link="tool0")
