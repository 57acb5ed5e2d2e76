# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""A calibration campaign in the style of a Jupyter notebook (one cell per
"# %%"): plan the poses, simulate the measurements, identify the
parameters, check them on held-out poses, and plot (matplotlib if
installed; skipped otherwise).

    ./run.sh python
    PYTHONPATH=build/python python3 examples/calibrate.py [--levels 4]
    PYTHONPATH=build/python python3 examples/calibrate.py \
        --robot data/ur10.urdf --tip-link tool0

Everything is SI (m, rad). The measurements are simulated from the robot
file's true values; a robot without them (a URDF) is simulated from its
nominal values perturbed (seeded by --seed, Robot.perturbed: the values
activecal_simulate --perturb_m --perturb_rad --seed simulates from):
every parameter of the "full" set in metres by N(0, --perturb-m), in
radians by N(0, --perturb-rad); other parameters stay nominal. With real data,
replace the simulate() cell by
activecal.read_measurements(robot, "measurements.csv").
"""
# %% Setup
import argparse
import os
import pathlib

import numpy as np

import activecal

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--robot", default=str(
    pathlib.Path(__file__).resolve().parents[1] / "data" / "puma560.yaml"))
parser.add_argument("--base-link", default=None,
                    help="URDF: the chain's first link")
parser.add_argument("--tip-link", default=None,
                    help="URDF: the chain's last link (e.g. tool0 for "
                    "data/ur10.urdf)")
parser.add_argument("--perturb-m", type=float, default=1e-3,
                    help="no true values in the robot file: std of the "
                    "perturbation of lengths (m)")
parser.add_argument("--perturb-rad", type=float, default=1e-3,
                    help="no true values in the robot file: std of the "
                    "perturbation of angles (rad)")
parser.add_argument("--levels", type=int, default=4,
                    help="lattice values per joint of the candidate pool")
parser.add_argument("--num-poses", type=int, default=30)
parser.add_argument("--noise-m", type=float, default=1e-4,
                    help="simulated device noise per axis (m)")
parser.add_argument("--seed", type=int, default=1)
parser.add_argument("--out", default="calibrate_out",
                    help="directory of the figures")
args = parser.parse_args()

robot = activecal.load_robot(args.robot, base_link=args.base_link,
                             tip_link=args.tip_link)
print(robot)

# The values the simulated robot has: the file's true values, or (a URDF
# has none) the nominal values perturbed, seeded.
truth = robot.true_parameters
if truth is None:
    # As activecal_simulate --perturb_m --perturb_rad --seed does.
    truth = robot.with_parameter_set("full").perturbed(
        args.perturb_m, args.perturb_rad, seed=args.seed)
    print(f"no true values in {args.robot}: simulating from the nominal "
          f"values perturbed by {args.perturb_m} m / {args.perturb_rad} rad "
          f"(seed {args.seed})")

# %% Plan: a D-optimal design over the joint lattice, with its certificate.
def progress(stage, done, total):
    if done == total:
        print(f"  {stage}: {done}/{total}")


design = activecal.select(robot, algorithm="fedorov", levels=args.levels,
                          num_poses=args.num_poses, seed=args.seed,
                          progress=progress)
print(f"design: {len(design.pose_indices)} poses of {design.pool_size}, "
      f"log10 det {design.log10_det:.4f}, "
      f"D-efficiency >= {design.efficiency_lower_bound:.4f}")
activecal.write_poses(robot, os.devnull, design.joint_angles,
                      design.pose_indices)  # write_poses(robot, "poses.csv", ...)

# A baseline to compare with: as many poses drawn at random in the ranges.
rng = np.random.default_rng(args.seed)
lo, hi = robot.joint_limits.T
random_joints = lo + (hi - lo) * rng.random((args.num_poses, robot.num_joints))

# %% Measure (simulated here: the file's true values plus Gaussian noise).
measured = activecal.simulate(robot, design.joint_angles,
                              noise_m=args.noise_m, seed=args.seed,
                              parameters=truth)
measured_random = activecal.simulate(robot, random_joints,
                                     noise_m=args.noise_m, seed=args.seed,
                                     parameters=truth)

# %% Identify.
estimate = activecal.identify(robot, measured, model_selection="none")
estimate_random = activecal.identify(robot, measured_random,
                                     model_selection="none")
print(estimate.report())
ratio = np.median(estimate_random.std / estimate.std)
print(f"std of the estimates: the random poses' are {ratio:.2f}x the "
      "design's (median over the parameters)")

# %% Check on poses not used in the fit.
check_joints = lo + (hi - lo) * rng.random((200, robot.num_joints))
check = activecal.simulate(robot, check_joints, noise_m=args.noise_m,
                           seed=args.seed + 1, parameters=truth)
before = activecal.evaluate(robot, check)
after = activecal.evaluate(estimate.robot, check)
after_random = activecal.evaluate(estimate_random.robot, check)
print(f"held-out RMS error: nominal {before['position']['rms']:.4g} m, "
      f"calibrated {after['position']['rms']:.4g} m "
      f"(random poses: {after_random['position']['rms']:.4g} m)")

# %% Plot.
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None
    print("matplotlib is not installed: no plots")

if plt is not None:
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    names = estimate.parameter_names
    truth = truth[[robot.parameter_names.index(n) for n in names]]
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    axes[0, 0].plot(design.history, marker=".")
    axes[0, 0].set(title="design: log10 det per step",
                   xlabel="step", ylabel="log10 det")
    x = np.arange(len(names))
    axes[0, 1].errorbar(x, estimate.estimates - truth, yerr=estimate.std,
                        fmt="o", label="D-optimal")
    axes[0, 1].errorbar(x + 0.3, estimate_random.estimates - truth,
                        yerr=estimate_random.std, fmt="s", label="random")
    axes[0, 1].set(title="estimate - truth (+- 1 std)", xticks=x)
    axes[0, 1].set_xticklabels(names, rotation=90, fontsize=6)
    axes[0, 1].legend()
    image = axes[1, 0].imshow(estimate.correlation, vmin=-1, vmax=1,
                              cmap="coolwarm")
    axes[1, 0].set_title("correlation of the estimates")
    fig.colorbar(image, ax=axes[1, 0])
    errors = [np.linalg.norm(e["position_errors_m"], axis=1)
              for e in (before, after_random, after)]
    bins = np.logspace(np.log10(min(e.min() for e in errors)),
                       np.log10(max(e.max() for e in errors)), 40)
    axes[1, 1].hist(errors, bins=bins,
                    label=["nominal", "calibrated (random poses)",
                           "calibrated (D-optimal)"])
    axes[1, 1].set(title="held-out position errors", xlabel="m",
                   xscale="log")
    axes[1, 1].legend()
    fig.tight_layout()
    fig.savefig(out / "calibration.png", dpi=120)
    print(f"wrote {out / 'calibration.png'}")
