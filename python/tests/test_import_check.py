# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""The import check (activecal/__init__.py): another interpreter, one that
cannot load the extension or has no numpy, gets one line naming the
interpreter the build is for and the one running, not a failure at the
first call."""
import glob
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

import activecal
from activecal import _build_info
from conftest import BUILD_DIR

PACKAGE = pathlib.Path(activecal.__file__).parent


def run_import(python, path, code="import activecal", args=()):
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME")}
    env["PYTHONPATH"] = str(path)
    return subprocess.run([python, *args, "-c", code], env=env, cwd="/",
                          capture_output=True, text=True)


def identity(python):
    """sys.executable and the version of interpreter `python`."""
    done = subprocess.run(
        [python, "-c", "import platform, sys; print(sys.executable); "
         "print(platform.python_version())"],
        capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout.split("\n")[:2]


def failure_line(done):
    """The ImportError line: the last line of stderr, the whole message."""
    assert done.returncode != 0, done.stdout
    lines = done.stderr.strip().splitlines()
    assert lines and lines[-1].startswith("ImportError: activecal: "), \
        done.stderr
    # Nothing chained after or before it ("During handling...").
    assert "During handling" not in done.stderr, done.stderr
    return lines[-1][len("ImportError: "):]


def expected_prefix(executable, version, built=_build_info):
    return (f"activecal: built for {built.executable} (Python "
            f"{built.version}), imported by {executable} (Python {version}), "
            "which ")


def test_build_info_names_this_interpreter():
    assert _build_info.extension.startswith("_activecal.")
    assert (PACKAGE / _build_info.extension).exists()
    assert os.path.realpath(_build_info.executable) == \
        os.path.realpath(sys.executable) or \
        os.path.samefile(_build_info.executable, sys.executable)


def test_numpy_missing_is_one_line():
    # numpy made unimportable in this interpreter.
    done = run_import(sys.executable, PACKAGE.parent,
                      "import sys; sys.modules['numpy'] = None; "
                      "import activecal")
    executable, version = identity(sys.executable)
    assert failure_line(done) == (
        expected_prefix(executable, version) +
        "cannot import numpy (import of numpy halted; None in sys.modules): "
        "install numpy for this interpreter (Debian: python3-numpy) or run "
        "the other one")


def test_extension_for_another_python_is_one_line(tmp_path):
    # A build for a made-up Python 2.99: its extension's tag is not one
    # this interpreter loads.
    package = tmp_path / "activecal"
    shutil.copytree(PACKAGE, package,
                    ignore=shutil.ignore_patterns("__pycache__"))
    other = "_activecal.cpython-299-x86_64-linux-gnu.so"
    (package / _build_info.extension).rename(package / other)
    (package / "_build_info.py").write_text(
        'executable = "/opt/python2.99/bin/python2.99"\n'
        'version = "2.99.0"\n'
        f'extension = "{other}"\n')
    done = run_import(sys.executable, tmp_path)
    executable, version = identity(sys.executable)
    from importlib.machinery import EXTENSION_SUFFIXES

    class Other:
        executable = "/opt/python2.99/bin/python2.99"
        version = "2.99.0"
    assert failure_line(done) == (
        expected_prefix(executable, version, Other) +
        f"cannot load its extension {other} (this interpreter loads "
        f"*{EXTENSION_SUFFIXES[0]}): build activecal for it (pip install . "
        "with it, or cmake -DPython3_EXECUTABLE=...) or run the other one")


def other_interpreters():
    """Real interpreters other than this one: pyenv's, python3 on PATH
    (pyenv's shims are scripts, its versions' binaries are not)."""
    found = []
    root = os.environ.get("PYENV_ROOT", os.path.expanduser("~/.pyenv"))
    found += sorted(glob.glob(os.path.join(root, "versions", "*", "bin",
                                           "python")))
    for name in ("python3", "python"):
        path = shutil.which(name)
        if path and "/shims/" not in path:
            found.append(path)
    mine = os.path.realpath(sys.executable)
    out, seen = [], {mine}
    for path in found:
        real = os.path.realpath(path)
        if real not in seen:
            seen.add(real)
            out.append(path)
    return out


OTHERS = other_interpreters()

# What an interpreter is, in one start: sys.executable, its version, the
# extension tag it loads (or none), whether it has numpy. Python 2 syntax.
PROBE = """
import platform, sys
try:
    from importlib.machinery import EXTENSION_SUFFIXES
    tag = EXTENSION_SUFFIXES[0]
except ImportError:
    tag = "none"
try:
    import numpy
    numpy = "numpy"
except ImportError:
    numpy = "no-numpy"
print(sys.executable + "\\n" + platform.python_version() + "\\n" + tag +
      "\\n" + numpy)
"""


@pytest.mark.skipif(not OTHERS, reason="no second Python interpreter on "
                    "this machine (pyenv or python3 on PATH)")
@pytest.mark.parametrize("python", OTHERS)
def test_second_interpreter(python):
    probe = subprocess.run([python, "-c", PROBE], capture_output=True,
                           text=True)
    assert probe.returncode == 0, probe.stderr
    executable, version, tag, numpy = probe.stdout.split("\n")[:4]
    loads_tag = _build_info.extension.endswith(tag)
    done = run_import(python, PACKAGE.parent,
                      "import activecal; print(activecal.puma560().num_joints)")
    if loads_tag and numpy == "numpy":
        # The same ABI with numpy: it works.
        assert done.returncode == 0, done.stderr
        assert done.stdout.strip() == "6"
        return
    line = failure_line(done)
    assert line.startswith(expected_prefix(executable, version)), line
    assert ("cannot load its extension" in line) == (not loads_tag), line
    assert ("cannot import numpy" in line) == loads_tag, line
