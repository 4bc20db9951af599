#!/usr/bin/python3
"""Evaluation and figure of the repeated-texture experiment (docs/results/repeated_texture.md): speed over
time of the ground truth, AsynEVO (events) and the 30 Hz frame-based KLT baseline (its knot velocities and
the speed from differencing its neighbouring poses), and a table of velocity errors per phase of the
speed-ramp preset (sim/speed_ramp.hpp).

  repeated_texture.py --gt SEQ/groundtruth.txt --run NAME=RUN_DIR [--run NAME=RUN_DIR ...]
                      [--differenced NAME ...] --out-figure PNG --out-json FILE
                      [--phases 2.0 3.5 | --single-phase NAME] [--title TEXT]

NAME is `asynevo` (events) or a frame-baseline label (klt30, klt30_l1, klt30_predict); --differenced
adds, for the named runs, the speed from differencing neighbouring estimated poses (as the paper does for
DSO). --single-phase evaluates the whole sequence as one phase of that name.
Each run folder holds velocities.txt, stamped_traj_estimate.txt and two evaluations by `asynevo eval`:
eval_all/eval.json (Sim(3) fitted on the whole trajectory) and eval_slow/eval.json (Sim(3) fitted on the
first 30 knots, inside the walking phase of the speed-ramp preset). The estimate's linear velocities are multiplied by the scale of
each alignment in turn. Errors per phase, for every method:
  velocity RMSE  sqrt(mean ‖s·v_e − v_g‖²)   [m/s]  (body frame; for pose differencing the aligned
                                                     world-frame velocity against the ground truth's)
  speed error    sqrt(mean (s·‖v_e‖ − ‖v_g‖)²) / mean ‖v_g‖ · 100   [%]
The ground-truth velocity is the central difference of the 1 kHz ground-truth positions over ±5 ms (the
camera does not rotate in this preset, so body and world frames coincide up to the start pose).
Needs Debian's python3-numpy and python3-matplotlib; run with /usr/bin/python3.
"""

import argparse
import json
import os

import numpy as np


def load(path, cols):
    rows = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    a = np.array([[float(x) for x in r[:cols]] for r in rows])
    return a.reshape(-1, cols)


def quat_to_rot(q):  # x y z w
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


class GroundTruth:
    def __init__(self, path):
        g = load(path, 8)
        self.t, self.p = g[:, 0], g[:, 1:4]
        self.R = [quat_to_rot(q) for q in g[:, 4:8]]

    def position(self, t):
        return np.stack([np.interp(t, self.t, self.p[:, i]) for i in range(3)], axis=-1)

    def velocity_world(self, t, h=0.005):
        t = np.clip(t, self.t[0] + h, self.t[-1] - h)
        return (self.position(t + h) - self.position(t - h)) / (2 * h)

    def velocity_body(self, t):
        vw = self.velocity_world(t)
        idx = np.clip(np.searchsorted(self.t, t), 0, len(self.t) - 1)
        return np.stack([self.R[i].T @ v for i, v in zip(idx, vw)])


class Run:
    def __init__(self, run_dir):
        self.vel = load(os.path.join(run_dir, "velocities.txt"), 7)
        self.traj = load(os.path.join(run_dir, "stamped_traj_estimate.txt"), 8)
        self.align = {}
        for name in ("all", "slow"):
            a = json.load(open(os.path.join(run_dir, "eval_" + name, "eval.json")))["alignment"]
            self.align[name] = (a["scale"], np.array(a["rotation"]), np.array(a["translation"]))

    def twist_speed(self, align):
        s = self.align[align][0]
        return self.vel[:, 0], s * self.vel[:, 1:4]

    def differenced(self, align):
        """World-frame velocity from neighbouring aligned poses, at the midpoints."""
        s, R, t = self.align[align]
        p = (s * (R @ self.traj[:, 1:4].T)).T + t
        dt = np.diff(self.traj[:, 0])
        return 0.5 * (self.traj[1:, 0] + self.traj[:-1, 0]), np.diff(p, axis=0) / dt[:, None]


def phase_errors(t, v_est, v_gt, phases):
    out = {}
    for name, (lo, hi) in phases.items():
        m = (t >= lo) & (t < hi)
        if not np.any(m):
            out[name] = None
            continue
        err = np.linalg.norm(v_est[m] - v_gt[m], axis=1)
        speed_est, speed_gt = np.linalg.norm(v_est[m], axis=1), np.linalg.norm(v_gt[m], axis=1)
        out[name] = {
            "samples": int(m.sum()),
            "velocity_rmse_mps": float(np.sqrt(np.mean(err ** 2))),
            "speed_rmse_perc": float(np.sqrt(np.mean((speed_est - speed_gt) ** 2)) / np.mean(speed_gt) * 100),
            "mean_speed_est_mps": float(np.mean(speed_est)),
            "mean_speed_gt_mps": float(np.mean(speed_gt)),
        }
    return out


STYLE = {"asynevo": ("tab:red", "AsynEVO (events)"),
         "klt30": ("tab:blue", "30 Hz KLT baseline, 3 pyramid levels"),
         "klt30_l1": ("tab:green", "30 Hz KLT baseline, 1 pyramid level"),
         "klt30_predict": ("tab:purple", "30 Hz KLT baseline, 1 level, constant-velocity start")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gt", required=True)
    ap.add_argument("--run", action="append", required=True, help="NAME=RUN_DIR")
    ap.add_argument("--differenced", nargs="*", default=[], help="runs also shown by pose differencing")
    ap.add_argument("--out-figure", required=True)
    ap.add_argument("--out-json", required=True)
    ap.add_argument("--phases", nargs=2, type=float, default=[2.0, 3.5], help="ramp start and end (s)")
    ap.add_argument("--single-phase", default="", help="one phase of this name over the whole sequence")
    ap.add_argument("--title", default="")
    args = ap.parse_args()

    gt = GroundTruth(args.gt)
    runs = {}
    for spec in args.run:
        name, _, path = spec.partition("=")
        runs[name] = Run(path)
    t_end = gt.t[-1] + 1e-9
    phases = {"slow": (0.0, args.phases[0]), "accelerating": (args.phases[0], args.phases[1]),
              "fast": (args.phases[1], t_end)}
    if args.single_phase:
        phases = {args.single_phase: (gt.t[0], t_end)}
    result = {"phases_s": phases, "alignments": {}, "errors": {}}
    curves = {}
    for align in ("slow", "all"):
        result["alignments"][align] = {k: r.align[align][0] for k, r in runs.items()}
        errs = {}
        for key, run in runs.items():
            t, v = run.twist_speed(align)
            errs[key] = phase_errors(t, v, gt.velocity_body(t), phases)
            curves[(key, align)] = (t, np.linalg.norm(v, axis=1))
            if key in args.differenced:
                t, v = run.differenced(align)
                errs[key + "_differenced"] = phase_errors(t, v, gt.velocity_world(t), phases)
                curves[(key + "_differenced", align)] = (t, np.linalg.norm(v, axis=1))
        result["errors"][align] = errs
    with open(args.out_json, "w") as f:
        json.dump(result, f, indent=1)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.4))
    tg = np.arange(gt.t[0], gt.t[-1], 0.005)
    for ax, align, label in zip(axes, ("slow", "all"),
                                ("Sim(3) scale from the first 30 knots (1.5 s)",
                                 "Sim(3) scale from the whole trajectory")):
        if not args.single_phase:
            ax.axvspan(args.phases[0], min(args.phases[1], gt.t[-1]), color="0.92")
        ax.plot(tg, np.linalg.norm(gt.velocity_world(tg), axis=1), "k-", lw=2, label="ground truth")
        for key in runs:
            colour, text = STYLE.get(key, ("tab:gray", key))
            ax.plot(*curves[(key, align)], "-", color=colour, lw=1.4, label=text + (" (knot velocity)" if key in args.differenced else ""))
            if key in args.differenced:
                ax.plot(*curves[(key + "_differenced", align)], ":", color=colour, lw=1.4,
                        label=text + " (differenced poses)")
        ax.set_xlabel("time [s]")
        ax.set_title(label, fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("speed [m/s]")
    axes[0].legend(loc="upper left", fontsize=7.5)
    if args.title:
        fig.suptitle(args.title, fontsize=11)
    fig.tight_layout()
    fig.savefig(args.out_figure, dpi=100)

    for align in ("slow", "all"):
        print("\nSim(3) scale from %s (scales: %s)\n" % (
            "the first 30 knots" if align == "slow" else "the whole trajectory",
            ", ".join("%s %.3f" % kv for kv in result["alignments"][align].items())))
        print("| method | " + " | ".join("%s: velocity RMSE [m/s], speed error [%%]" % p for p in phases) + " |")
        print("|---" * (len(phases) + 1) + "|")
        for key, per in result["errors"][align].items():
            cells = ["%.3f, %.1f" % (e["velocity_rmse_mps"], e["speed_rmse_perc"]) if e else "-" for e in per.values()]
            print("| %s | %s |" % (key, " | ".join(cells)))


if __name__ == "__main__":
    main()
