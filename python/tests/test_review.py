"""A new user's review of the module: behaviour that docs/python.md got
wrong or left out, checked against the module and against the document.

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


def test_objects_cannot_be_pickled_or_copied(puma, measured):
    for obj in (puma, measured):
        with pytest.raises(TypeError, match="cannot pickle"):
            pickle.dumps(obj)
        with pytest.raises(TypeError, match="cannot pickle"):
            copy.copy(obj)
    assert documented("`TypeError: cannot pickle ...`")


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


def test_indexing_always_gives_measurements(measured):
    one = measured[0]
    assert isinstance(one, activecal.Measurements) and len(one) == 1
    assert len(measured[np.array([], dtype=int)]) == 0
    with pytest.raises(ValueError, match="measurements index"):
        measured[[]]
    assert documented("`m[[]]` is refused")


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
    with pytest.raises(ValueError, match="option outlier_threshold: "
                       "expected a number, got '4'$"):
        activecal.identify(puma, measured, outlier_threshold="4")
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
