# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""The README example, examples/calibrate.py and the installed module."""
import os
import pathlib
import re
import subprocess
import sys

import pytest

from conftest import BUILD_DIR, SOURCE_DIR, readme_python_example


def test_readme_example():
    code, expected = readme_python_example()
    done = subprocess.run([sys.executable, "-c", code], cwd=SOURCE_DIR,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    # It prints what the README says it prints.
    assert done.stdout == expected


def test_example_script(tmp_path):
    done = subprocess.run(
        [sys.executable, str(SOURCE_DIR / "examples" / "calibrate.py"),
         "--levels", "3", "--out", str(tmp_path / "figures")],
        capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "D-efficiency >=" in done.stdout
    assert "held-out RMS error" in done.stdout
    try:
        import matplotlib  # noqa: F401
        assert (tmp_path / "figures" / "calibration.png").stat().st_size > 0
    except ImportError:
        assert "matplotlib is not installed: no plots" in done.stdout


def cache_value(name):
    for line in (BUILD_DIR / "CMakeCache.txt").read_text().splitlines():
        if line.startswith(name + ":"):
            return line.split("=", 1)[1]
    return None


def test_cmake_install_puts_the_module_in_site_packages(tmp_path):
    if not (BUILD_DIR / "CMakeCache.txt").exists():
        pytest.skip("no CMake build directory")
    site = cache_value("ACTIVECAL_PYTHON_INSTALL_DIR")
    assert site and not site.startswith("/")
    # Python3_SITEARCH relative to the interpreter's prefix, e.g. Debian's
    # lib/python3/dist-packages or lib/python3.11/site-packages.
    assert re.fullmatch(r"lib(64)?/python3(\.\d+)?/(site|dist)-packages",
                        site), site
    prefix = tmp_path / "prefix"
    done = subprocess.run(
        ["cmake", "--install", str(BUILD_DIR), "--prefix", str(prefix),
         "--component", "python"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    env = dict(os.environ, PYTHONPATH=str(prefix / site))
    done = subprocess.run(
        [sys.executable, "-c",
         "import activecal; print(activecal.__file__); "
         "print(activecal.puma560().num_joints)"],
        cwd=tmp_path, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    path, joints = done.stdout.split()
    assert pathlib.Path(path).resolve().is_relative_to(prefix.resolve())
    assert joints == "6"
