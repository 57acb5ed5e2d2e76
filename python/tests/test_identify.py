# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""identify: the same estimates as activecal_identify, and what they mean."""
import json

import numpy as np
import pytest

import activecal
from conftest import PUMA, SOURCE_DIR, UR10, perturbed_session, program, run


@pytest.fixture(scope="module")
def puma_data(puma, tmp_path_factory):
    design = activecal.select(puma, levels=3, num_poses=30, seed=2,
                              restarts=2)
    m = activecal.simulate(puma, design.joint_angles, noise_m=1e-4, seed=4)
    path = tmp_path_factory.mktemp("identify") / "measurements.csv"
    activecal.write_measurements(puma, str(path), m)
    return m, path


def program_report(tmp_path, robot_args, measurements, *flags):
    json_out = tmp_path / "report.json"
    model_out = tmp_path / "model.yaml"
    run([program("activecal_identify"), *robot_args,
         f"--measurements={measurements}", f"--json_out={json_out}",
         f"--model_out={model_out}", *flags])
    return json.loads(json_out.read_text()), model_out


def assert_same_as_program(estimate, report):
    params = report["parameters"]
    assert estimate.parameter_names == [p["name"] for p in params]
    # Bit for bit (JSON numbers read back exactly).
    assert list(estimate.estimates) == [p["estimate"] for p in params]
    assert list(estimate.std) == [p["std"] for p in params]
    assert estimate.correlation.tolist() == report["correlation"]
    assert estimate.covariance.tolist() == report["covariance"]
    assert estimate.rms_before_m == report["initial_rms_residual_m"]
    assert estimate.rms_after_m == report["rms_residual_m"]
    assert estimate.held_fixed == report["auto_fixed"]
    assert estimate.warnings == report["warnings"]
    assert estimate.iterations == report["iterations"]


@pytest.mark.parametrize("model_selection", ["cv", "none", None])
def test_same_estimates_as_the_program(puma, puma_data, tmp_path,
                                       model_selection):
    # None: both with their defaults (the same).
    m, path = puma_data
    flags = [] if model_selection is None else [
        f"--model_selection={model_selection}"]
    options = {} if model_selection is None else {
        "model_selection": model_selection}
    report, model_out = program_report(
        tmp_path, [f"--robot={PUMA}"], path, *flags, "--seed=5")
    estimate = activecal.identify(puma, activecal.read_measurements(
        puma, str(path)), seed=5, **options)
    assert_same_as_program(estimate, report)
    assert (estimate.registration_only_rms_m ==
            report["registration_only"]["rms_residual_m"])
    # save() writes the same calibrated model as --model_out (but for the
    # comment line).
    mine = tmp_path / "mine.yaml"
    estimate.save(str(mine))
    strip = lambda p: [l for l in p.read_text().splitlines()
                       if not l.startswith("#")]
    assert strip(mine) == strip(model_out)


def test_same_estimates_as_the_program_urdf(ur10, tmp_path):
    # A URDF robot: the full set reduced to what the data separate, the
    # base registered in closed form; simulated from perturbed values.
    m, _ = perturbed_session(ur10, 1e-3, np.cos, num_poses=40, noise_m=5e-5,
                             restarts=2)
    path = tmp_path / "ur10.csv"
    activecal.write_measurements(ur10, str(path), m)
    report, _ = program_report(tmp_path, [f"--robot={UR10}", "--tip_link=tool0"],
                               path, "--model_selection=none")
    estimate = activecal.identify(ur10, m, model_selection="none")
    assert_same_as_program(estimate, report)
    assert estimate.registered_base == report["registered_base"]
    assert estimate.parameter_set == "full"
    assert estimate.held_fixed  # the full set is reduced


def test_estimate_meaning(puma, puma_data, tmp_path):
    m, _ = puma_data
    e = activecal.identify(puma, m, model_selection="none")
    k = len(e.parameter_names)
    assert e.estimates.shape == e.std.shape == (k,)
    assert e.correlation.shape == e.covariance.shape == (k, k)
    # correlation = cov / (std std^T), unit diagonal; std = sqrt(diag cov).
    np.testing.assert_allclose(np.diag(e.correlation), 1.0, rtol=0,
                               atol=1e-12)
    np.testing.assert_allclose(e.std, np.sqrt(np.diag(e.covariance)),
                               rtol=1e-12)
    np.testing.assert_allclose(e.correlation,
                               e.covariance / np.outer(e.std, e.std),
                               rtol=0, atol=1e-12)
    # The estimates are the free entries of the full vector, near the truth
    # (simulated from it), and the fit explains the data to the noise.
    index = [puma.parameter_names.index(n) for n in e.parameter_names]
    np.testing.assert_array_equal(e.parameters[index], e.estimates)
    truth = puma.true_parameters[index]
    assert np.all(np.abs(e.estimates - truth) < 6 * e.std)
    assert e.rms_after_m < 3e-4 < e.rms_before_m
    assert e.termination_type == "CONVERGENCE"
    np.testing.assert_array_equal(e.nominal, puma.nominal[index])
    # The calibrated robot predicts the measurements as the fit does.
    calibrated = e.robot
    np.testing.assert_array_equal(calibrated.nominal, e.parameters)
    errors = np.linalg.norm(calibrated.forward(m.joints) - m.positions, axis=1)
    np.testing.assert_allclose(errors, e.residual_norms, rtol=1e-9, atol=1e-15)
    ev = activecal.evaluate(calibrated, m)
    assert ev["position"]["rms"] == pytest.approx(e.rms_after_m, rel=1e-9)
    err = ev["position_errors_m"]
    np.testing.assert_allclose(np.linalg.norm(err, axis=1), errors,
                               rtol=1e-12)
    np.testing.assert_allclose(err, calibrated.forward(m.joints) - m.positions,
                               rtol=0, atol=1e-15)
    np.testing.assert_allclose(ev["rmse_xyz_m"], np.sqrt(np.mean(err**2, 0)),
                               rtol=1e-12)
    np.testing.assert_allclose(ev["mean_xyz_m"], np.mean(err, 0), rtol=1e-9,
                               atol=1e-18)
    assert ev["position"]["max"] == pytest.approx(errors.max(), rel=1e-12)
    assert ev["position"]["count"] == ev["num_measurements"] == len(m)
    assert ev["rotation"]["count"] == ev["distance"]["count"] == 0
    # sigma: the residual rows' standard deviation, sqrt(SSR / (m - p)).
    assert e.sigma_m == pytest.approx(
        np.sqrt(np.sum(e.residual_norms**2) / (3 * len(m) - k)), rel=1e-9)
    # save() re-read gives the same numbers.
    path = tmp_path / "calibrated.yaml"
    e.save(str(path))
    again = activecal.load_robot(str(path))
    np.testing.assert_array_equal(again.nominal, e.parameters)
    assert again.free_parameter_names == e.parameter_names
    assert "RMS" in e.report()


def test_identify_bad_input(puma, puma_data):
    m, _ = puma_data
    with pytest.raises(ValueError, match="identify: unknown option 'robust'"):
        activecal.identify(puma, m, robust="huber")
    with pytest.raises(ValueError, match="robust_loss must be none, huber or cauchy, got 'l1'"):
        activecal.identify(puma, m, robust_loss="l1")
    with pytest.raises(ValueError, match="model_selection must be auto, none, validation or cv"):
        activecal.identify(puma, m, model_selection="aic")
    with pytest.raises(ValueError, match="selection_rule must be 1se_most, min, 1se or ftest, got 'aic'"):
        activecal.identify(puma, m, model_selection="cv", selection_rule="aic")
    with pytest.raises(ValueError, match="option folds: expected an integer"):
        activecal.identify(puma, m, folds="five")
    with pytest.raises(ValueError, match="choose one"):
        activecal.identify(puma, m, model_selection="cv", prior_std_m=1e-3)
    with pytest.raises(ValueError, match="the 3 measurements: .*auto_fix=True|the 3 measurements"):
        activecal.identify(puma, m[:3], model_selection="none")
    with pytest.raises(ValueError, match="no measurements"):
        activecal.identify(puma, m[:0])
    wrong = activecal.Measurements("position", np.zeros((3, 5)),
                                   positions=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="expected 6 joint values, got 5"):
        activecal.identify(puma, wrong)
    with pytest.raises(TypeError):
        activecal.identify(puma, "measurements.csv")


def test_identify_does_not_depend_on_threads(puma, puma_data):
    m, _ = puma_data
    one = activecal.identify(puma, m, num_threads=1, seed=2,
                             model_selection="cv")
    two = activecal.identify(puma, m, num_threads=2, seed=2,
                             model_selection="cv")
    assert one.parameter_names == two.parameter_names
    np.testing.assert_array_equal(one.estimates, two.estimates)
    np.testing.assert_array_equal(one.covariance, two.covariance)
    assert one.model_selection_curve == two.model_selection_curve
    assert len(one.model_selection_curve) > 1  # cv ran


def test_the_files_free_set_is_identified_by_default(puma, puma_data):
    # Issue #26 item 4: the robot file names the paper's 27 parameters; the
    # default (model_selection='auto') identifies them all, as
    # activecal_identify does; asked for, cv still selects.
    m, _ = puma_data
    e = activecal.identify(puma, m)
    assert e.model_selection_curve == []  # no selection ran
    assert len(e.parameter_names) == 27 and e.held_fixed == []
    cv = activecal.identify(puma, m, model_selection="cv")
    assert len(cv.model_selection_curve) > 1


def test_learned_residual_as_the_program(puma, puma_data, tmp_path):
    """learned_residual= gives the program's --learned_residual: the same
    decision and numbers, the summary as a dict, and save() writes the
    correction as --model_out does."""
    m, path = puma_data
    e = activecal.identify(puma, m, learned_residual="on",
                           learned_features=40, validation_fraction=0.2)
    lr = e.learned_residual
    assert lr["mode"] == "on" and lr["kept"] and lr["num_features"] == 40
    assert lr["validation_count"] > 0
    assert lr["validation_rms_parametric_m"] > 0
    assert lr["report"].startswith("learned residual (on): 40 random Fourier")
    out = tmp_path / "out.txt"
    model_out = tmp_path / "program.yaml"
    text = subprocess_output([program("activecal_identify"), f"--robot={PUMA}",
                              f"--measurements={path}", "--learned_residual=on",
                              "--learned_features=40",
                              "--validation_fraction=0.2",
                              f"--model_out={model_out}"])
    # The program prints the same report (its fit time aside).
    strip = lambda t: [l for l in t.splitlines() if "fit " not in l]
    assert "\n".join(strip(lr["report"])) in "\n".join(strip(text))
    saved = tmp_path / "python.yaml"
    e.save(str(saved))
    assert "learned_residual:" in saved.read_text()
    assert activecal.identify(puma, m).learned_residual is None
    with pytest.raises(ValueError, match="learned_residual must be off, on or "
                       "auto, got 'maybe'"):
        activecal.identify(puma, m, learned_residual="maybe")
    with pytest.raises(ValueError, match="^learned_residual: num_features"):
        activecal.identify(puma, m, learned_residual="auto",
                           learned_features=0)


def test_rotation_weight_note():
    """Without rotation_weight on 6D data (the README's UR10e): the
    program's note, in notes; given, none."""
    data = SOURCE_DIR / "data"
    ur10e = activecal.load_robot(str(data / "ur10e.urdf"), tip_link="tool0")
    m = activecal.read_measurements(
        ur10e, str(data / "figaroh_ur10e" / "measurements.csv"))
    e = activecal.identify(ur10e, m, parameter_set="full",
                           model_selection="none")
    note = [n for n in e.notes if "rotation_weight" in n]
    assert len(note) == 1 and note[0].startswith(
        "activecal: note: rotation_weight not given: the orientations of the "
        "pose rows were weighted 1 m/rad and 30 parameters kept"), e.notes
    e = activecal.identify(ur10e, m, parameter_set="full",
                           model_selection="none", rotation_weight=0.1)
    assert e.notes == []


def subprocess_output(args):
    import subprocess
    return subprocess.run(args, check=True, capture_output=True,
                          text=True).stdout
