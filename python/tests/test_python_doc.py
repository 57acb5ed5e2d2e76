# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""docs/python.md against the module: the behaviour a new user met that
the document got wrong or left out (argument types and ranges, pickling,
paths, indexing, messages, keyword typos, the example script).

Each test pins what the module does and that docs/python.md says so (the
document used to say otherwise, or nothing).
"""
import copy
import pathlib
import pickle
import re

import numpy as np
import pytest

import activecal
from conftest import SOURCE_DIR

DOC = re.sub(r"\s+", " ", (SOURCE_DIR / "docs" / "python.md").read_text())
KUKA = str(SOURCE_DIR / "data" / "kuka_iiwa14.urdf")


def documented(text):
    return re.sub(r"\s+", " ", text) in DOC


@pytest.fixture(scope="module")
def puma():
    return activecal.puma560()


@pytest.fixture(scope="module")
def measured(puma):
    rng = np.random.default_rng(0)
    lo, hi = puma.joint_limits.T
    q = lo + (hi - lo) * rng.random((40, 6))
    return activecal.simulate(puma, q, noise_m=1e-4, seed=1)


def test_sigma_columns_are_zero_not_nan_where_not_given(puma, measured):
    # The document said NaN for every column a row does not have; the
    # standard deviations are 0 ("not given"), as the library stores them.
    assert np.all(measured.sigma_m == 0)
    assert np.all(measured.sigma_rad == 0)
    assert np.all(np.isnan(measured.rotations))
    assert documented("`sigma_rad` (0 where not given")


def columns(m):
    return [m.types, m.joints, m.joints2, m.positions, m.rotations,
            m.distances, m.markers, m.sigma_m, m.sigma_rad, m.warnings,
            m.notes]


def test_robots_and_measurements_pickle_and_copy(puma, measured):
    # Finding 5: nothing could be pickled or copied.
    ur10 = activecal.load_robot(SOURCE_DIR / "data" / "ur10.urdf",
                                tip_link="tool0").with_parameter_set("full")
    for robot in (puma, ur10):
        back = pickle.loads(pickle.dumps(robot))
        assert (back.name, back.path, back.is_urdf, back.parameter_names) == (
            robot.name, robot.path, robot.is_urdf, robot.parameter_names)
        assert np.array_equal(back.nominal, robot.nominal)
        assert np.array_equal(back.free, robot.free)
        assert np.array_equal(back.joint_limits, robot.joint_limits)
        q = measured.joints[:5]
        assert np.array_equal(back.forward(q), robot.forward(q))
        assert np.array_equal(back.jacobian(q), robot.jacobian(q))
        assert copy.copy(robot) is robot and copy.deepcopy(robot) is robot
    back = pickle.loads(pickle.dumps(puma))
    assert np.array_equal(back.true_parameters, puma.true_parameters)
    a = activecal.select(puma, levels=3, num_poses=20, certificate=False)
    b = activecal.select(back, levels=3, num_poses=20, certificate=False)
    assert np.array_equal(a.pose_indices, b.pose_indices)
    distance = activecal.simulate(puma, measured.joints[:4], type="distance")
    pose = activecal.simulate(puma, measured.joints[:4], type="pose")
    for m in (measured, distance, pose, measured + distance, measured[:0]):
        for other in (pickle.loads(pickle.dumps(m)), copy.copy(m),
                      copy.deepcopy(m)):
            assert len(other) == len(m)
            for x, y in zip(columns(other), columns(m)):
                assert np.array_equal(x, y, equal_nan=True) if isinstance(
                    x, np.ndarray) else x == y
    # The results are not picklable: their arrays are.
    with pytest.raises(TypeError, match="cannot pickle"):
        pickle.dumps(a)
    assert documented("`Robot` and `Measurements` can be pickled")


def test_integer_arguments_given_non_integers_raise_value_error(puma,
                                                                 measured):
    # Finding 2: pybind11's cast raised RuntimeError("Unable to cast ...").
    with pytest.raises(ValueError,
                       match="markers: expected integers, got dtype float64"):
        activecal.Measurements("position", measured.joints,
                               positions=measured.positions,
                               markers=np.zeros(len(measured)))
    with pytest.raises(ValueError,
                       match="pose_indices: expected integers, got dtype "
                       "float64"):
        activecal.write_poses(puma, "/dev/null", measured.joints[:1],
                              pose_indices=[0.5])
    pool = measured.joints[:25]
    with pytest.raises(ValueError,
                       match="pool_indices: expected integers, got dtype "
                       "float64"):
        activecal.select(puma, pool=pool, pool_indices=np.arange(25.),
                         num_poses=20)
    # Issue 26: a pool's labels are integers >= 0, each once.
    with pytest.raises(ValueError, match=r"pool_indices: pose_indices\[3\] "
                       r"= -1: a pose label must be an integer"):
        activecal.select(puma, pool=pool, num_poses=20,
                         pool_indices=[0, 1, 2, -1] + list(range(4, 25)))
    with pytest.raises(ValueError, match=r"pool_indices: pose_indices\[24\] "
                       r"= 0, the same label as pose_indices\[0\]"):
        activecal.select(puma, pool=pool, num_poses=20,
                         pool_indices=list(range(24)) + [0])
    # An empty list labels no pose: one per pool pose or none at all.
    for labels in ([], list(range(24))):
        with pytest.raises(ValueError, match=r"pool_indices: expected 25 "
                           r"values \(one per pool pose\), got %d"
                           % len(labels)):
            activecal.select(puma, pool=pool, num_poses=20,
                             pool_indices=labels)
    with pytest.raises(ValueError, match=r"pose_indices\[0\] = -5: a pose "
                       "label"):
        activecal.compensate(puma, targets=np.array([[0.5, 0.2, 0.3]]),
                             pose_indices=[-5])
    with pytest.raises(ValueError, match="target_rms_m: expected a number "
                       r"\(m\), got '1e-4'"):
        activecal.select(puma, pool=pool, criterion="task_rms",
                         target_rms_m="1e-4")
    # Integer arrays of any integer dtype, and lists, still work.
    m = activecal.Measurements("position", measured.joints[:2],
                               positions=measured.positions[:2],
                               markers=np.zeros(2, dtype=np.uint8))
    assert list(m.markers) == [0, 0]
    assert documented("a float, bool or string array there is a "
                      "`ValueError` (`markers: expected integers, got dtype "
                      "float64`)")


def test_paths_may_be_pathlib(puma, tmp_path):
    # Finding 3: every path argument takes str, bytes or os.PathLike.
    path = SOURCE_DIR / "data" / "puma560.yaml"
    robot = activecal.load_robot(path)
    assert robot.name == puma.name and robot.path == str(path)
    robot.save(tmp_path / "r.yaml")
    assert activecal.load_robot(tmp_path / "r.yaml").name == puma.name
    q = puma.joint_limits.mean(axis=1)[None, :]
    activecal.write_poses(puma, tmp_path / "p.csv", q)
    joints, _ = activecal.read_poses(puma, tmp_path / "p.csv")
    assert np.array_equal(joints, q)
    m = activecal.simulate(puma, q, seed=1)
    activecal.write_measurements(puma, tmp_path / "m.csv", m)
    back = activecal.read_measurements(puma, tmp_path / "m.csv")
    assert np.array_equal(back.positions, m.positions)
    with pytest.raises(TypeError, match="os.PathLike"):
        activecal.load_robot(3)
    assert documented("Paths are `str`, `bytes` or any `os.PathLike` "
                      "(`pathlib.Path`)")


def test_indexing_always_gives_measurements(puma, measured, tmp_path):
    # Finding 8: m[[]] was refused, subsets lost the reader's warnings and
    # notes, an empty Measurements had joints of shape (0, 0).
    one = measured[0]
    assert isinstance(one, activecal.Measurements) and len(one) == 1
    assert len(measured[np.array([], dtype=int)]) == 0
    assert len(measured[[]]) == 0
    assert measured[[]].joints.shape == (0, 6)
    assert measured[:0].joints2.shape == (0, 6)
    empty = activecal.Measurements("position", np.zeros((0, 6)),
                                   positions=np.zeros((0, 3)))
    assert empty.joints.shape == (0, 6)
    assert (empty + measured[:2]).joints.shape == (2, 6)
    # A file whose reader notes and warns: subsets keep both.
    q = np.array(puma.joint_limits)[:, 1] + 0.01  # just beyond the limits
    m = activecal.simulate(puma, np.vstack([q, q * 0]), seed=1)
    path = tmp_path / "m.csv"
    activecal.write_measurements(puma, path, m)
    text = path.read_text().splitlines()
    text[0] += ",extra"
    text[1:] = [line + ",1" for line in text[1:]]
    path.write_text("\n".join(text) + "\n")
    read = activecal.read_measurements(puma, path)
    assert read.warnings and read.notes
    for sub in (read[:1], read[[0]], read[np.array([True, False])]):
        assert sub.warnings == read.warnings and sub.notes == read.notes
    assert documented("`m[[]]` is empty, as `m[np.array([], dtype=int)]`")


def test_complex_and_out_of_range_inputs_are_value_errors(puma, measured):
    # Finding 9.
    q = measured.joints[:2].astype(complex)
    with pytest.raises(ValueError,
                       match="q: expected real numbers, got dtype complex128"):
        puma.forward(q)
    with pytest.raises(ValueError, match=r"pool_size: a pool of 1000000000000 "
                       r"poses needs at least .* GiB"):
        activecal.select(puma, pool="sobol", pool_size=10**12)
    with pytest.raises(ValueError, match=r"levels=31: a pool of 887503681 "
                       r"poses needs at least .* GiB"):
        activecal.select(puma, levels=31)
    # polish_pool_size <= 0 means every pose, as the program's flag.
    a = activecal.select(puma, pool="sobol", pool_size=300, num_poses=20,
                         polish_pool_size=-1, certificate=False)
    b = activecal.select(puma, pool="sobol", pool_size=300, num_poses=20,
                         polish_pool_size=0, certificate=False)
    assert np.array_equal(a.pose_indices, b.pose_indices)
    bad = measured.joints[:2].copy()
    bad[1, 2] = np.nan
    with pytest.raises(ValueError, match="program row 1: "):
        activecal.compensate(puma, program=bad, nominal=puma)
    with pytest.raises(ValueError, match="starts row 1: "):
        activecal.compensate(puma, targets=measured.positions[:2],
                             starts=bad)
    assert documented("Complex arrays are a `ValueError`")
    assert documented("`polish_pool_size` <= 0: every pose")


def test_compensation_repr(puma, measured):
    # Finding 6.
    c = activecal.compensate(puma, program=measured.joints[:3], nominal=puma)
    assert re.fullmatch(r"<activecal\.Compensation: 3 targets, 3 converged, "
                        r"max position error \S+ m>", repr(c))


def test_marker_messages_number_markers_from_zero(puma, measured):
    # Finding 4: the library's messages count markers from 1; the module
    # checks them first, from 0 as its API, and refuses negative ones.
    bad = activecal.Measurements("position", measured.joints[:3],
                                 positions=measured.positions[:3],
                                 markers=[0, 5, 0])  # accepted when built
    msg = (r"measurements row 1: marker 5 is not a marker of the robot "
           r"\(it has 1, numbered from 0: 0\)")
    with pytest.raises(ValueError, match=msg):
        activecal.evaluate(puma, bad)
    with pytest.raises(ValueError, match=msg):
        activecal.identify(puma, bad)
    with pytest.raises(ValueError, match=msg):
        activecal.write_measurements(puma, "/dev/null", bad)
    with pytest.raises(ValueError,
                       match=r"markers: expected marker numbers >= 0 .*"
                       r"got -1 in row 0"):
        activecal.Measurements("position", measured.joints[:3],
                               positions=measured.positions[:3],
                               markers=[-1] * 3)
    assert documented("`measurements row 1: marker 5 is not a marker of the "
                      "robot (it has 1, numbered from 0: 0)`")


def test_keyword_typos_outside_options_are_type_errors(puma, measured):
    with pytest.raises(ValueError, match="compensate: unknown option"):
        activecal.compensate(puma, program=measured.joints[:1], nominl=puma)
    with pytest.raises(TypeError, match="incompatible function arguments"):
        activecal.evaluate(puma, measured, parameter=None)
    with pytest.raises(TypeError, match="incompatible function arguments"):
        activecal.select(puma, num_poses=20.0, levels=3)
    assert documented("raise pybind11's several-line `TypeError: ...(): "
                      "incompatible function arguments`")


def test_identify_option_messages_name_what_they_take(puma, measured):
    # Finding 7: "expected a number, got -1" for seed=-1; None refused.
    with pytest.raises(ValueError, match="identify: option seed: expected "
                       "a non-negative integer, got -1$"):
        activecal.identify(puma, measured, seed=-1)
    with pytest.raises(ValueError, match="identify: option folds: expected "
                       "an integer, got 2.5$"):
        activecal.identify(puma, measured, folds=2.5)
    with pytest.raises(ValueError, match="identify: option robust_loss: "
                       "expected a string, got 3$"):
        activecal.identify(puma, measured, robust_loss=3)
    with pytest.raises(ValueError, match="option outlier_probability: "
                       "expected a number, got '0.01'$"):
        activecal.identify(puma, measured, outlier_probability="0.01")
    # None is the default, as select's parameter_set=None.
    a = activecal.identify(puma, measured, model_selection="none")
    b = activecal.identify(puma, measured, model_selection="none",
                           parameter_set=None, seed=None, folds=None)
    assert np.array_equal(a.estimates, b.estimates)
    assert documented("`identify: option seed: expected a non-negative "
                      "integer, got -1`")


def test_urdf_design_log10_det_is_not_at_nominal():
    # A reduced set is linearised at a generic point: the nominal
    # Jacobians do not give the design's log10 det (they are singular).
    kuka = activecal.load_robot(KUKA)
    design = activecal.select(kuka, pool="sobol", pool_size=5000,
                              num_poses=40, seed=3)
    full = kuka.with_parameter_set("full")
    cols = [full.free_parameter_names.index(n)
            for n in design.free_parameters]
    X = full.jacobian(design.joint_angles)[:, :, cols].reshape(-1, len(cols))
    assert len(cols) == 31
    assert np.linalg.matrix_rank(X) == 29
    assert design.log10_det > 20
    assert documented("a generic point near the nominal values, which the "
                      "module does not return")


@pytest.mark.parametrize("robot", [["--robot", KUKA],
                                   ["--robot", str(SOURCE_DIR / "data" /
                                                   "ur10.urdf"),
                                    "--tip-link", "tool0"]])
def test_example_script_runs_on_the_urdf_robots(robot, tmp_path):
    # Finding 10: a URDF has no true values to simulate from, and the UR10
    # needs its tip link: the example perturbs the nominal values (seeded)
    # and takes --tip-link.
    import subprocess
    import sys
    done = subprocess.run(
        [sys.executable, str(SOURCE_DIR / "examples" / "calibrate.py"),
         "--levels", "3", "--out", str(tmp_path / "figures")] + robot,
        capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "simulating from the nominal values perturbed" in done.stdout
    rms = re.search(r"held-out RMS error: nominal (\S+) m, calibrated (\S+) m",
                    done.stdout)
    assert float(rms.group(2)) < float(rms.group(1)) / 5
    assert documented("`--robot data/ur10.urdf --tip-link tool0`")
