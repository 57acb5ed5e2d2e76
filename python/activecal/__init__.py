"""activecal: robot kinematic calibration (C++ core, pybind11 bindings).

Units are SI (m, rad); errors are ValueError (bad input) or RuntimeError (a
solver failed), with the library's one-line messages. See docs/python.md.

This package holds the extension module _activecal (everything the C++
library binds) and, in Python, the checks at import and the tables
(activecal._tables). Before loading the extension it checks that this
interpreter can: the extension's tag (built for another Python version) and
numpy (another interpreter without it) are one-line ImportErrors naming the
interpreter the build is for and the one running.
"""
import importlib.machinery as _machinery
import platform as _platform
import sys as _sys

from . import _build_info


def _interpreters():
    return (f"built for {_build_info.executable} (Python "
            f"{_build_info.version}), imported by {_sys.executable} "
            f"(Python {_platform.python_version()})")


def _check_interpreter():
    suffix = _build_info.extension[len("_activecal"):]
    if suffix not in _machinery.EXTENSION_SUFFIXES:
        raise ImportError(
            f"activecal: {_interpreters()}, which cannot load its extension "
            f"{_build_info.extension} (this interpreter loads "
            f"*{_machinery.EXTENSION_SUFFIXES[0]}): build activecal for it "
            "(pip install . with it, or cmake -DPython3_EXECUTABLE=...) or "
            "run the other one")
    try:
        import numpy  # noqa: F401  (the bindings convert through it)
    except ImportError as e:
        first_line = (str(e).strip().splitlines() or ["no numpy"])[0]
        raise ImportError(
            f"activecal: {_interpreters()}, which cannot import numpy "
            f"({first_line}): install numpy for this interpreter (Debian: "
            "python3-numpy) or run the other one") from None


_check_interpreter()

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
