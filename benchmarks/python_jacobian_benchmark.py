#!/usr/bin/env python3
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Per-pose time of the Python module's Robot.jacobian against the program's
pool kernel (PoolJacobians, the selection benchmark's
BM_PoolJacobians/threads:1/analytic:1), measured in one run, alternated.

    PYTHONPATH=build/python python3 benchmarks/python_jacobian_benchmark.py \
        [build_dir] [repeats]

Both evaluate a PUMA 560 5^6 = 15,625-pose lattice on one thread; the script prints ns per pose of each and their ratio
(best of `repeats`, default 5, of each side). Both are CPU times (the
benchmark's items/s are per CPU second; the module's call is timed by
process_time, its work running on the calling thread), so that a machine
shared with other jobs inflates neither.
"""
import itertools
import pathlib
import re
import subprocess
import sys
import time

import numpy as np

import activecal

here = pathlib.Path(__file__).resolve().parent.parent
build = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else here / "build"
repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
bench = build / "benchmarks" / "activecal_selection_benchmark"

robot = activecal.load_robot(str(here / "data" / "puma560.yaml"))
# A 5^6 lattice of joint values (the benchmark's pool size; the time per
# pose does not depend on which poses).
levels = [np.linspace(-1.0, 1.0, 5)] * robot.num_joints
joints = np.array(list(itertools.product(*levels)))


def python_ns_per_pose():
    start = time.process_time()
    J = robot.jacobian(joints)
    elapsed = time.process_time() - start
    assert J.shape == (len(joints), 3, robot.num_free)
    return 1e9 * elapsed / len(joints)


def program_ns_per_pose():
    out = subprocess.run(
        [str(bench), "--benchmark_filter=BM_PoolJacobians/threads:1/analytic:1$"],
        capture_output=True, text=True, check=True).stdout
    m = re.search(r"items_per_second=([0-9.]+)([kM]?)/s", out)
    scale = {"": 1, "k": 1e3, "M": 1e6}[m.group(2)]
    return 1e9 / (float(m.group(1)) * scale)


py, prog = [], []
for _ in range(repeats):
    prog.append(program_ns_per_pose())
    py.append(min(python_ns_per_pose() for _ in range(5)))
print(f"poses: {len(joints)}, free parameters: {robot.num_free}")
print(f"program kernel (BM_PoolJacobians/threads:1/analytic:1): "
      f"{min(prog):.0f} ns/pose")
print(f"Python Robot.jacobian: {min(py):.0f} ns/pose")
print(f"ratio Python / program: {min(py) / min(prog):.2f}")
