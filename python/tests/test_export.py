# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""What Python writes from an Estimate is what activecal_identify writes:
the calibrated URDF (--urdf_out, with its reload check), the frames file
(--frames_out); the frames for ROS 2 read back to the model's transforms."""
import pickle

import numpy as np
import pytest
import yaml

import activecal
from conftest import (PUMA, UR10, perturbed_session, program,
                      puma_measurements, run)


def rpy_matrix(rx, ry, rz):
    """R = Rz(rz) Ry(ry) Rx(rx), written out (the model's convention)."""
    cx, sx, cy, sy, cz, sz = (np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry),
                              np.cos(rz), np.sin(rz))
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def pose(values):
    T = np.eye(4)
    T[:3, :3] = rpy_matrix(*values[3:6])
    T[:3, 3] = values[:3]
    return T


def block(robot, estimate, prefix):
    """The six values of a base or marker block in the estimate's full
    vector, by parameter name ("B.x".."B.rz", "tool.x"..)."""
    names = robot.parameter_names
    return np.array([estimate.parameters[names.index(f"{prefix}.{k}")]
                     for k in ("x", "y", "z", "rx", "ry", "rz")])


@pytest.fixture(scope="module")
def ur10_fit(tmp_path_factory):
    ur10 = activecal.load_robot(UR10, tip_link="tool0")
    m, _ = perturbed_session(ur10, 1e-3, np.cos, num_poses=30, noise_m=5e-5,
                             pool_size=300)
    d = tmp_path_factory.mktemp("export")
    csv = d / "ur10.csv"
    activecal.write_measurements(ur10, csv, m)
    return ur10, m, csv, activecal.identify(ur10, m, model_selection="none")


def without_comments(path):
    return [line for line in path.read_text().splitlines()
            if not line.startswith("#")]


def test_urdf_and_frames_as_the_program_urdf_robot(ur10_fit, tmp_path):
    ur10, m, csv, estimate = ur10_fit
    run([program("activecal_identify"), f"--robot={UR10}", "--tip_link=tool0",
         f"--measurements={csv}", "--model_selection=none",
         f"--urdf_out={tmp_path / 'program.urdf'}",
         f"--frames_out={tmp_path / 'program_frames.yaml'}"])
    worst = estimate.write_urdf(tmp_path / "python.urdf")
    assert 0 <= worst <= 1e-9
    # Byte for byte: the same library functions on the same estimate.
    assert (tmp_path / "python.urdf").read_bytes() == \
        (tmp_path / "program.urdf").read_bytes()
    estimate.write_frames(tmp_path / "python_frames.yaml")
    assert without_comments(tmp_path / "python_frames.yaml") == \
        without_comments(tmp_path / "program_frames.yaml")
    # Reloaded with its frames, the URDF is the calibrated robot.
    back = activecal.load_robot(tmp_path / "python.urdf", tip_link="tool0",
                                frames=tmp_path / "python_frames.yaml")
    q = m.joints
    np.testing.assert_allclose(back.forward(q), estimate.robot.forward(q),
                               rtol=0, atol=1e-9)


def test_urdf_as_the_program_yaml_robot(tmp_path):
    puma, m = puma_measurements(30, 300)
    csv = tmp_path / "puma.csv"
    activecal.write_measurements(puma, csv, m)
    run([program("activecal_identify"), f"--robot={PUMA}",
         f"--measurements={csv}", "--model_selection=none",
         f"--urdf_out={tmp_path / 'program.urdf'}"])
    estimate = activecal.identify(puma, m, model_selection="none")
    assert estimate.write_urdf(str(tmp_path / "python.urdf")) <= 1e-9
    assert (tmp_path / "python.urdf").read_bytes() == \
        (tmp_path / "program.urdf").read_bytes()


def test_write_urdf_check_refuses_a_gain(tmp_path):
    # A joint gain other than 1 cannot be written in URDF: the reload
    # check finds the difference, nothing is written.
    puma = activecal.load_robot(PUMA)
    values = puma.nominal.copy()
    gains = [i for i, n in enumerate(puma.parameter_names)
             if n.endswith(".gain")]
    values[gains[1]] = 1.01
    puma.save(tmp_path / "gain.yaml", parameters=values)
    robot = activecal.load_robot(tmp_path / "gain.yaml")
    design = activecal.select(robot, levels=3, num_poses=30, seed=2,
                              pool_size=300)
    m = activecal.simulate(robot, design.joint_angles, noise_m=1e-4, seed=4)
    estimate = activecal.identify(robot, m, model_selection="none")
    out = tmp_path / "cal.urdf"
    with pytest.raises(ValueError) as e:
        estimate.write_urdf(out)
    name = puma.parameter_names[gains[1]].split(".")[0]
    assert str(e.value).startswith(
        "write_urdf: the written URDF predicts the measurements up to ")
    assert str(e.value).endswith(
        f"m away from the calibrated model (more than 1e-9 m): link "
        f"'{name}' has gain 1.01, which a URDF cannot hold: the URDF uses 1")
    assert not out.exists()


def test_write_urdf_checks_the_measurements_given(ur10_fit, tmp_path):
    ur10, m, _, estimate = ur10_fit
    assert estimate.write_urdf(tmp_path / "a.urdf", m[:5]) <= 1e-9
    with pytest.raises(ValueError, match="measurements: expected"):
        estimate.write_urdf(tmp_path / "b.urdf", measurements=[1, 2])
    assert not (tmp_path / "b.urdf").exists()


def test_ros_frames_read_back_to_the_model(ur10_fit, tmp_path):
    ur10, _, _, estimate = ur10_fit
    base = pose(block(ur10, estimate, "B"))
    tool = pose(block(ur10, estimate, "tool"))
    for fmt, name in (("yaml", "tf.yaml"), ("script", "tf.sh")):
        path = tmp_path / name
        estimate.write_ros_frames(path, format=fmt, device_frame="tracker")
        frames = activecal.read_ros_frames(path)
        assert [(f["frame_id"], f["child_frame_id"]) for f in frames] == [
            ("tracker", "base_link"), ("tool0", "tool")]
        assert np.abs(frames[0]["matrix"] - base).max() < 1e-12
        assert np.abs(frames[1]["matrix"] - tool).max() < 1e-12
        for f in frames:
            q = f["rotation"]
            assert q[3] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-15
            np.testing.assert_array_equal(f["translation"], f["matrix"][:3, 3])
    # ROS 2 reads the YAML with PyYAML: a TFMessage whose numbers are floats.
    message = yaml.safe_load((tmp_path / "tf.yaml").read_text())
    first = message["transforms"][0]
    assert first["header"] == {"stamp": {"sec": 0, "nanosec": 0},
                               "frame_id": "tracker"}
    assert first["child_frame_id"] == "base_link"
    for t in message["transforms"]:
        for part in ("translation", "rotation"):
            assert all(type(v) is float for v in t["transform"][part].values())
    script = (tmp_path / "tf.sh").read_text()
    assert script.startswith("#!/bin/sh\n# Metrology frames identified by "
                             "activecal (Python) from 30 measurements")
    assert script.count("ros2 run tf2_ros static_transform_publisher") == 2


def test_ros_frames_names_and_a_dh_base(ur10_fit, tmp_path):
    ur10, _, _, estimate = ur10_fit
    estimate.write_ros_frames(tmp_path / "tf.yaml", base_frame="ur_base",
                              tip_frame="flange")
    frames = activecal.read_ros_frames(tmp_path / "tf.yaml")
    assert [(f["frame_id"], f["child_frame_id"]) for f in frames] == [
        ("device", "ur_base"), ("flange", "tool")]
    with pytest.raises(ValueError) as e:
        estimate.write_ros_frames(tmp_path / "x.yaml", device_frame="my tracker")
    assert str(e.value) == ("write_ros_frames: device frame 'my tracker' has "
                            "' ': use letters, digits, '_', '-', '.' and '/'")
    with pytest.raises(ValueError, match="format must be yaml or script"):
        estimate.write_ros_frames(tmp_path / "x.yaml", format="xml")
    assert not (tmp_path / "x.yaml").exists()
    # The PUMA's base is DH geometry, not a registration: markers only,
    # below the tip of its URDF (UrdfFromModel's "tip").
    puma, m = puma_measurements(30, 300)
    e = activecal.identify(puma, m, model_selection="none")
    e.write_ros_frames(tmp_path / "puma.sh", format="script")
    frames = activecal.read_ros_frames(tmp_path / "puma.sh")
    assert [(f["frame_id"], f["child_frame_id"]) for f in frames] == [
        ("tip", "tool")]
    assert np.abs(frames[0]["matrix"] -
                  pose(block(puma, e, "tool"))).max() < 1e-12


def test_pickled_robot_keeps_its_chain(ur10_fit, tmp_path):
    # The chain's ends survive pickling: the tf frames are still named
    # after them.
    ur10, m, _, _ = ur10_fit
    other = activecal.load_robot(UR10, base_link="base_link_inertia",
                                 tip_link="flange")
    back = pickle.loads(pickle.dumps(other))
    e = activecal.identify(back, m, model_selection="none",
                           parameter_set="registration")
    e.write_ros_frames(tmp_path / "tf.yaml")
    frames = activecal.read_ros_frames(tmp_path / "tf.yaml")
    assert frames[0]["child_frame_id"] == "base_link_inertia"
    assert frames[1]["frame_id"] == "flange"


def test_read_ros_frames_errors(tmp_path):
    bad = tmp_path / "bad.sh"
    bad.write_text("#!/bin/sh\nros2 run tf2_ros static_transform_publisher "
                   "--x 1 --frame-id a\n")
    with pytest.raises(ValueError) as e:
        activecal.read_ros_frames(bad)
    assert str(e.value) == (f"{bad}:2: --frame-id and --child-frame-id are "
                            "required")
    with pytest.raises(ValueError, match="format must be yaml or script"):
        activecal.read_ros_frames(bad, format="json")
    with pytest.raises(ValueError, match="cannot"):
        activecal.read_ros_frames(tmp_path / "missing.yaml")
