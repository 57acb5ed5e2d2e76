# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Builds activecal's Python package with the project's CMake build.

pyproject.toml holds the metadata; this file adds the one step setuptools
cannot do alone: build the extension activecal._activecal with CMake (the
libraries it links, statically, and the bindings), then put it and the
generated _build_info.py beside the package's Python files in the wheel.
The C++ dependencies (Ceres, glog, yaml-cpp, urdfdom, ...) stay the
system's shared libraries: the wheel is for the machine (distribution) it
was built on, not a manylinux wheel.

Environment:
  ACTIVECAL_CMAKE_BUILD_DIR  an existing CMake build directory of this
      source (configured with -DPython3_EXECUTABLE for the interpreter that
      runs pip): its target activecal_python is brought up to date and
      used, instead of a build of its own. The tests use it to keep the
      wheel build to seconds.
  CMAKE_BUILD_PARALLEL_LEVEL  build jobs (default: all cores).
Otherwise the build directory is build/wheel/cmake under the source, a
Release build of the libraries and the module only (no programs, tests or
benchmarks), through ccache when it is installed.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = pathlib.Path(__file__).resolve().parent
# setuptools' own build files (build/lib..., build/bdist..., the egg-info)
# under one directory, out of the source tree's way.
BUILD_BASE = SOURCE_DIR / "build" / "wheel"


def project_version():
    text = (SOURCE_DIR / "CMakeLists.txt").read_text()
    match = re.search(r"project\(activecal VERSION ([0-9.]+)", text)
    if not match:
        sys.exit("setup.py: no 'project(activecal VERSION ...)' in "
                 "CMakeLists.txt")
    return match.group(1)


class CMakeBuild(build_ext):
    """build_ext for the one CMake-built extension."""

    def build_extension(self, ext):
        build_dir = os.environ.get("ACTIVECAL_CMAKE_BUILD_DIR")
        if build_dir:
            build_dir = pathlib.Path(build_dir).resolve()
            if not (build_dir / "CMakeCache.txt").exists():
                sys.exit(f"setup.py: ACTIVECAL_CMAKE_BUILD_DIR={build_dir} "
                         "is not a configured CMake build directory")
        else:
            build_dir = BUILD_BASE / "cmake"
            self.configure(build_dir)
        # _build_info.py is written when CMake generates the build: the
        # interpreter is checked before anything is built.
        package = build_dir / "python" / "activecal"
        if not (package / "_build_info.py").exists():
            sys.exit(f"setup.py: {build_dir} does not build the Python "
                     "module (configure it with -DACTIVECAL_BUILD_PYTHON=ON)")
        info = {}
        exec((package / "_build_info.py").read_text(), info)
        suffix = info["extension"][len("_activecal"):]
        wanted = sysconfig.get_config_var("EXT_SUFFIX")
        if suffix != wanted:
            sys.exit(f"setup.py: {build_dir} builds activecal for "
                     f"{info['executable']} (extension *{suffix}), not for "
                     f"{sys.executable} (*{wanted}): configure it with "
                     f"-DPython3_EXECUTABLE={sys.executable} or leave "
                     "ACTIVECAL_CMAKE_BUILD_DIR unset")
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL",
                              str(os.cpu_count() or 1))
        self.run_command_line(["cmake", "--build", str(build_dir),
                               "--target", "activecal_python", "-j", jobs])
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(package / info["extension"], target)
        shutil.copyfile(package / "_build_info.py",
                        target.parent / "_build_info.py")

    def configure(self, build_dir):
        args = ["cmake", "-S", str(SOURCE_DIR), "-B", str(build_dir),
                "-DCMAKE_BUILD_TYPE=Release",
                f"-DPython3_EXECUTABLE={sys.executable}",
                "-DACTIVECAL_BUILD_PYTHON=ON",
                "-DACTIVECAL_BUILD_APPS=OFF",
                "-DACTIVECAL_BUILD_TESTS=OFF",
                "-DACTIVECAL_BUILD_BENCHMARKS=OFF",
                "-DACTIVECAL_INSTALL=OFF"]
        if shutil.which("ccache") and "CMAKE_CXX_COMPILER_LAUNCHER" not in \
                os.environ:
            args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        self.run_command_line(args)

    @staticmethod
    def run_command_line(args):
        print("setup.py: " + " ".join(args), flush=True)
        done = subprocess.run(args)
        if done.returncode != 0:
            sys.exit(f"setup.py: '{' '.join(args[:2])} ...' failed with "
                     f"status {done.returncode}")


BUILD_BASE.mkdir(parents=True, exist_ok=True)
setup(
    version=project_version(),
    ext_modules=[Extension("activecal._activecal", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(BUILD_BASE)},
             "egg_info": {"egg_base": str(BUILD_BASE)}},
)
