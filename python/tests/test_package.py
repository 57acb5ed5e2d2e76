# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""pip install of the checkout (pyproject.toml, setup.py) into a temporary
venv, then the README's Python example run there; the wheel of
`python3 -m build --no-isolation --wheel`. A ctest of its own
(python_package_test).

The wheel's extension comes from this test's CMake build directory
(ACTIVECAL_CMAKE_BUILD_DIR, brought up to date by setup.py), so that the
test takes seconds; a build of its own is what a user's `pip install .`
does (docs/python.md gives its time)."""
import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig
import zipfile

import pytest

from conftest import BUILD_DIR, SOURCE_DIR, readme_python_example

# Top-level entries of a checkout that are not source.
NOT_SOURCE = {".git", "paper_out", "out", "dist", "fuzz-findings"}


def copy_source(target):
    """The checkout without its build directories: pip's in-tree build
    writes under build/ of the tree it is given, not into the one under
    test."""
    def ignore(directory, names):
        top = pathlib.Path(directory) == SOURCE_DIR
        return [n for n in names if n == "__pycache__" or n.endswith(".egg-info")
                or (top and (n in NOT_SOURCE or n.startswith("build")))]
    shutil.copytree(SOURCE_DIR, target, ignore=ignore, symlinks=True)
    return target


def clean_env(**extra):
    """The environment without the build tree's PYTHONPATH (ctest sets it:
    it would hide the installed package)."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "PIP_INDEX_URL")}
    env.update(PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_NO_INPUT="1", **extra)
    return env


def make_venv(path):
    done = subprocess.run([sys.executable, "-m", "venv",
                           "--system-site-packages", str(path)],
                          capture_output=True, text=True)
    if done.returncode != 0 and "ensurepip" in done.stdout + done.stderr:
        pytest.skip("python3-venv is missing (Debian: apt-get install "
                    "python3-venv): no venv to pip install into")
    assert done.returncode == 0, done.stdout + done.stderr
    return path / "bin" / "python"


def check_cmake_build():
    if not (BUILD_DIR / "CMakeCache.txt").exists():
        pytest.skip(f"no CMake build directory at {BUILD_DIR}")


def run_readme_example(python):
    code, expected = readme_python_example()
    done = subprocess.run([str(python), "-c", code], cwd=SOURCE_DIR,
                          env=clean_env(), capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout == expected


def test_pip_install_into_a_venv(tmp_path):
    check_cmake_build()
    python = make_venv(tmp_path / "venv")
    source = copy_source(tmp_path / "src")
    done = subprocess.run(
        [str(python), "-m", "pip", "install", "--no-build-isolation",
         "--no-index", str(source)],
        env=clean_env(ACTIVECAL_CMAKE_BUILD_DIR=str(BUILD_DIR.resolve())),
        capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Successfully installed activecal-" in done.stdout
    # Imported from the venv, not from the build tree.
    where = subprocess.run(
        [str(python), "-c", "import activecal, numpy; "
         "print(activecal.__file__); print(activecal.__version__)"],
        cwd=tmp_path, env=clean_env(), capture_output=True, text=True)
    assert where.returncode == 0, where.stderr
    path, version = where.stdout.split()
    assert pathlib.Path(path).is_relative_to(tmp_path / "venv")
    assert version == "0.1.0"
    run_readme_example(python)
    # pip's build files stayed in the copy's build/wheel/.
    assert not list(source.glob("*.egg-info"))
    assert (source / "build" / "wheel").is_dir()


def python_build(kind, tmp_path, env):
    """python3 -m build <kind> (--wheel, --sdist) of a copy of the source
    into tmp_path/dist; skips when python3-build is missing. Returns the
    copy's folder and the finished run."""
    try:
        import build  # noqa: F401  (python3-build)
    except ImportError:
        pytest.skip("python3-build is missing (Debian: apt-get install "
                    "python3-build): no python3 -m build")
    source = copy_source(tmp_path / "src")
    done = subprocess.run(
        [sys.executable, "-m", "build", "--no-isolation", kind,
         "--outdir", str(tmp_path / "dist"), str(source)],
        env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    return source, done


def test_python_build_makes_a_wheel(tmp_path):
    check_cmake_build()
    _, done = python_build(
        "--wheel", tmp_path,
        clean_env(ACTIVECAL_CMAKE_BUILD_DIR=str(BUILD_DIR.resolve())))
    wheels = list((tmp_path / "dist").glob("activecal-0.1.0-*.whl"))
    assert len(wheels) == 1, done.stdout
    with zipfile.ZipFile(wheels[0]) as wheel:
        names = set(wheel.namelist())
        extension = "activecal/_activecal" + \
            sysconfig.get_config_var("EXT_SUFFIX")
        assert {"activecal/__init__.py", "activecal/_tables.py",
                "activecal/_build_info.py", extension} <= names, names
        metadata = wheel.read("activecal-0.1.0.dist-info/METADATA").decode()
        license_text = wheel.read(
            "activecal-0.1.0.dist-info/LICENSE").decode()
    assert "License: BSD-3-Clause" in metadata
    assert "Requires-Dist: numpy" in metadata
    assert license_text == (SOURCE_DIR / "LICENSE").read_text()
    # Installed from the wheel alone, it runs the README example.
    python = make_venv(tmp_path / "venv")
    done = subprocess.run(
        [str(python), "-m", "pip", "install", "--no-index", str(wheels[0])],
        env=clean_env(), capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    run_readme_example(python)


def test_sdist_holds_the_whole_source(tmp_path):
    # python3 -m build (sdist, then the wheel from it) needs every file the
    # CMake build reads: MANIFEST.in takes the whole checkout.
    source, _ = python_build("--sdist", tmp_path, clean_env())
    import tarfile
    with tarfile.open(tmp_path / "dist" / "activecal-0.1.0.tar.gz") as sdist:
        names = {n.split("/", 1)[1] for n in sdist.getnames() if "/" in n}
    expected = {str(p.relative_to(source)) for p in source.rglob("*")
                if p.is_file() and "build" not in p.relative_to(source).parts
                and not p.name.endswith(".pyc")}
    # In a git checkout, the files git tracks: a log or a scratch file left
    # in the tree is not source (a CI run's ctest.log failed this test).
    try:
        tracked = subprocess.run(
            ["git", "-C", str(SOURCE_DIR), "ls-files", "-z"],
            capture_output=True, text=True)
    except FileNotFoundError:  # no git: every file of the copy
        tracked = None
    if tracked is not None and tracked.returncode == 0 and tracked.stdout:
        expected &= set(tracked.stdout.rstrip("\0").split("\0"))
    missing = expected - names
    assert not missing, sorted(missing)[:20]


def test_setup_refuses_a_build_for_another_interpreter(tmp_path):
    # A build directory configured for another interpreter (here: a
    # made-up one) is refused in one line, not copied into the wheel.
    check_cmake_build()
    fake = tmp_path / "build"
    (fake / "python" / "activecal").mkdir(parents=True)
    (fake / "CMakeCache.txt").write_text("")
    (fake / "python" / "activecal" / "_build_info.py").write_text(
        'executable = "/opt/python2.99/bin/python2.99"\n'
        'version = "2.99.0"\n'
        'extension = "_activecal.cpython-299-x86_64-linux-gnu.so"\n')
    source = copy_source(tmp_path / "src")
    done = subprocess.run(
        [sys.executable, str(source / "setup.py"), "-q", "build_ext"],
        cwd=source, env=clean_env(ACTIVECAL_CMAKE_BUILD_DIR=str(fake)),
        capture_output=True, text=True)
    assert done.returncode != 0
    assert done.stderr.strip().splitlines()[-1] == (
        f"setup.py: {fake} builds activecal for /opt/python2.99/bin/python2.99"
        f" (extension *.cpython-299-x86_64-linux-gnu.so), not for "
        f"{sys.executable} (*{sysconfig.get_config_var('EXT_SUFFIX')}): "
        f"configure it with -DPython3_EXECUTABLE={sys.executable} or leave "
        "ACTIVECAL_CMAKE_BUILD_DIR unset")
