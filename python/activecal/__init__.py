# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""activecal: robot kinematic calibration (C++ core, pybind11 bindings).

Units are SI (m, rad); errors are ValueError (bad input) or RuntimeError (a
solver failed), with the library's one-line messages. See docs/python.md.

This package holds the extension module _activecal (everything the C++
library binds) and, in Python, the checks at import and the tables
(activecal._tables). Before loading the extension it checks that this
interpreter can: an extension tag it does not load (a build for another
Python) and a missing numpy (another interpreter without it) are one-line
ImportErrors naming the interpreter the build is for and the one running.
This file parses under any Python, 2.7 included, so that even an old
interpreter gets that line.
"""
import platform as _platform
import sys as _sys

from . import _build_info


def _extension_suffixes():
    try:
        from importlib.machinery import EXTENSION_SUFFIXES
        return list(EXTENSION_SUFFIXES)
    except ImportError:  # Python 2
        import imp
        return [s for s, _, kind in imp.get_suffixes()
                if kind == imp.C_EXTENSION]


def _interpreters():
    return "built for %s (Python %s), imported by %s (Python %s)" % (
        _build_info.executable, _build_info.version, _sys.executable,
        _platform.python_version())


def _interpreter_problem():
    """The one-line reason this interpreter cannot use the build, or None."""
    suffixes = _extension_suffixes()
    if _build_info.extension[len("_activecal"):] not in suffixes:
        return ("activecal: %s, which cannot load its extension %s (this "
                "interpreter loads *%s): build activecal for it (pip install "
                ". with it, or cmake -DPython3_EXECUTABLE=...) or run the "
                "other one" % (_interpreters(), _build_info.extension,
                               suffixes[0] if suffixes else "no extensions"))
    try:
        import numpy  # noqa: F401  (the bindings convert through it)
    except ImportError as e:
        lines = str(e).strip().splitlines()
        return ("activecal: %s, which cannot import numpy (%s): install "
                "numpy for this interpreter (Debian: python3-numpy) or run "
                "the other one" % (_interpreters(),
                                   lines[0] if lines else "ImportError"))
    return None


_problem = _interpreter_problem()
if _problem:
    # Raised outside the except clause: no "During handling..." chain.
    raise ImportError(_problem)

from . import _activecal  # noqa: E402
from ._activecal import *  # noqa: E402,F401,F403
from . import _tables  # noqa: E402

__version__ = _activecal.__version__

# The classes under their public name (repr, pickles: activecal.Robot).
for _value in list(vars(_activecal).values()):
    if isinstance(_value, type):
        _value.__module__ = __name__
del _value

_tables.attach(_activecal)
