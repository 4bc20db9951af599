#!/usr/bin/python3
"""AsynEVO from Python, step by step: read events, run the pipeline, evaluate, plot, stream.

Run from the repository root after building (docs/guide/python.md):

  PYTHONPATH=build/python /usr/bin/python3 examples/python_quickstart.py --out quickstart

Without a dataset argument it first simulates a 3 s sequence with the CLI (build/bin/asynevo simulate);
with one (an ECD-style folder or an event file with its calibration beside it) it uses that. It writes
quickstart/trajectory.png when matplotlib is installed (python3-matplotlib).
"""

# %% Imports and arguments
import argparse
import os
import subprocess
import sys

import numpy as np

import asynevo

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("dataset", nargs="?", help="dataset folder or event file (default: simulate one)")
ap.add_argument("--out", default="quickstart", help="folder for the simulated sequence, run folder and figure")
ap.add_argument("--asynevo", default="build/bin/asynevo", help="the CLI, to simulate a sequence")
args = ap.parse_args()
os.makedirs(args.out, exist_ok=True)

# %% 1. A dataset: given, or simulated (boxes scene, 6-DoF motion, 3 s, exact ground truth)
dataset = args.dataset
if dataset is None:
    dataset = os.path.join(args.out, "sequence")
    subprocess.run([args.asynevo, "simulate", "--scene", "boxes", "--motion", "6dof", "--duration", "3",
                    "--seed", "1", "--out", dataset], check=True, stdout=subprocess.DEVNULL)

# %% 2. Read the events into numpy: t int64 ns, x/y uint16, p int8 (+1 ON, -1 OFF)
events = asynevo.read_events(dataset)
t, x, y, p = events["t"], events["x"], events["y"], events["p"]
span_s = (t[-1] - t[0]) * 1e-9
print(f"read {len(t)} events ({events['format']}, {events['width']}x{events['height']}) over {span_s:.2f} s; "
      f"{np.mean(p > 0) * 100:.0f} % ON")

# %% 3. Run AsynEVO offline (the code 'asynevo run' uses); the run folder goes to OUT/run
result = asynevo.run(dataset, config={"backend": {"knot_dt_ms": 50}}, out=os.path.join(args.out, "run"))
print(result["summary"], end="")
if not result["initialized"]:
    sys.exit(result["message"])
trajectory = result["trajectory"]  # N x 8: t [s], tx ty tz qx qy qz qw (camera-to-world)
print(f"{len(trajectory)} poses, {len(result['landmarks'])} landmarks")

# %% 4. Evaluate against the ground truth (Sim(3) alignment, rpg_trajectory_evaluation's ATE and RTE)
if result["groundtruth"] is None:
    print("no ground truth: nothing to evaluate")
    sys.exit(0)
ev = asynevo.evaluate(result["groundtruth"], trajectory, align="sim3", velocities=result["velocities"])
print(f"ATE {ev['ate_rmse_m']:.4f} m ({ev['ate_perc_of_path']:.2f} % of the {ev['gt_path_length_m']:.2f} m path), "
      f"scale {ev['alignment']['scale']:.3f}")
for rel in ev["relative_error"]["per_length"]:
    if not rel["too_few"]:
        print(f"  RTE over {rel['length_m']:.2f} m: {rel['trans_perc']['mean']:.2f} % translation, "
              f"{rel['rot_deg']['mean']:.2f} deg rotation")

# %% 5. Plot the aligned estimate over the ground truth (top view) into OUT/trajectory.png
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib is not installed (python3-matplotlib): no figure")
else:
    gt, est = ev["gt_positions"], ev["aligned_est_positions"]
    fig, ax = plt.subplots(figsize=(5, 5))
    ax.plot(gt[:, 0], gt[:, 1], "k-", label="ground truth")
    ax.plot(est[:, 0], est[:, 1], "r--", label="AsynEVO (Sim(3)-aligned)")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend()
    ax.set_title(f"ATE {ev['ate_perc_of_path']:.2f} % of the path")
    fig.savefig(os.path.join(args.out, "trajectory.png"), dpi=100, bbox_inches="tight")
    print(f"wrote {os.path.join(args.out, 'trajectory.png')}")

# %% 6. The same events as a live stream: push 10 ms batches, poll the poses that became final
calibration = result["stats"]["input"]["calibration"]  # the file the run used
stream = asynevo.Stream(calibration, config={"backend": {"knot_dt_ms": 50}}, sensor=(events["width"], events["height"]))
edges = np.searchsorted(t, np.arange(t[0], t[-1] + 10_000_000, 10_000_000))
polled = []
for a, b in zip(edges[:-1], edges[1:]):
    stream.push(t[a:b], x[a:b], y[a:b], p[a:b])
    polled.append(stream.poll()["trajectory"])
stream.finish()
polled.append(stream.poll()["trajectory"])
live = np.concatenate(polled)
if not np.array_equal(live, trajectory):  # the streaming API runs the offline pipeline's call sequence
    sys.exit("stream: the poses differ from the offline run's")
print(f"stream: {len(live)} poses from {len(edges) - 1} batches, identical to the offline run")
