#!/usr/bin/python3
"""Figures for an AsynEVO run folder (DESIGN.md section 1), written as PNG files into DIR/plots/.

  trajectory.png      estimate vs ground truth, top (x-y) and side (x-z) views, after alignment
  position.png        x, y, z over time, estimate (aligned) vs ground truth
  velocity.png        linear velocity (world frame, aligned) and angular velocity (body frame)
  relative_error.png  relative translation / rotation error box plots per sub-trajectory length
  runtime.png         backend time per update over event time, and a box plot per stage
  tracks.png          feature trajectories in (x, y, t)

Each figure is drawn only when its input files exist; the others are listed as skipped. The
alignment (s, R, t) and the relative errors come from eval.json ('asynevo eval' / 'asynevo plot'
write it); without eval.json the trajectories are aligned here with Umeyama Sim(3).

Needs Debian's python3-matplotlib and python3-numpy; run it with /usr/bin/python3.
Usage: plot_run.py --run DIR [--out DIR/plots] [--max-tracks 400]
"""

import argparse
import json
import os
import sys

try:
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import alignment
except ImportError as e:  # pragma: no cover - depends on the machine
    sys.exit(
        "plot_run.py: %s. Install Debian's python3-matplotlib and python3-numpy "
        "(scripts/setup.sh) and run with /usr/bin/python3." % e
    )

MAX_TIME_DIFF_S = 0.02


# ----------------------------------------------------------------------------- files


def load_table(path, min_cols):
    """Numeric whitespace-separated table, '#' comments skipped; None if missing or empty."""
    if not os.path.isfile(path):
        return None
    rows = []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            fields = s.replace(",", " ").split()
            try:
                rows.append([float(v) for v in fields])
            except ValueError:
                continue  # a header line
    rows = [r for r in rows if len(r) >= min_cols]
    if not rows:
        return None
    n = min(len(r) for r in rows)
    return np.array([r[:n] for r in rows], dtype=float)


def load_csv_with_header(path):
    """(header list, data array) of a CSV with a header row; None if missing or empty."""
    if not os.path.isfile(path):
        return None
    header, rows = None, []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            fields = [v.strip() for v in s.split(",")]
            if header is None:
                header = fields
                continue
            try:
                rows.append([float(v) for v in fields])
            except ValueError:
                continue
    if header is None or not rows:
        return None
    return header, np.array(rows, dtype=float)


# ----------------------------------------------------------------------------- geometry


def quat_to_rot(q):
    """Rotation matrices (n,3,3) from quaternions (n,4) in x y z w order."""
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    x, y, z, w = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    R = np.empty((len(q), 3, 3))
    R[:, 0, 0] = 1 - 2 * (y * y + z * z)
    R[:, 0, 1] = 2 * (x * y - z * w)
    R[:, 0, 2] = 2 * (x * z + y * w)
    R[:, 1, 0] = 2 * (x * y + z * w)
    R[:, 1, 1] = 1 - 2 * (x * x + z * z)
    R[:, 1, 2] = 2 * (y * z - x * w)
    R[:, 2, 0] = 2 * (x * z - y * w)
    R[:, 2, 1] = 2 * (y * z + x * w)
    R[:, 2, 2] = 1 - 2 * (x * x + y * y)
    return R


def rot_log(R):
    """Rotation vectors (n,3) of rotation matrices (n,3,3)."""
    cos = np.clip((np.trace(R, axis1=1, axis2=2) - 1) / 2, -1, 1)
    theta = np.arccos(cos)
    v = np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]], axis=1)
    s = np.sin(theta)
    factor = np.where(s > 1e-9, theta / (2 * np.maximum(s, 1e-12)), 0.5)
    return v * factor[:, None]


def nearest_matches(t_est, t_gt, max_diff=MAX_TIME_DIFF_S):
    """Index pairs (est, gt) of nearest times within max_diff (for plotting only)."""
    j = np.clip(np.searchsorted(t_gt, t_est), 1, len(t_gt) - 1)
    left_closer = np.abs(t_est - t_gt[j - 1]) <= np.abs(t_gt[j] - t_est)
    j = np.where(left_closer, j - 1, j)
    ok = np.abs(t_gt[j] - t_est) < max_diff
    return np.nonzero(ok)[0], j[ok]


def finite_difference(t, p, window_s=0.05):
    """Central differences over about +-window_s/2 (mocap noise is large at the ms scale)."""
    if len(t) < 3:
        return t[:0], p[:0]
    dt = np.median(np.diff(t))
    k = max(1, int(round(window_s / 2 / dt))) if dt > 0 else 1
    if len(t) <= 2 * k:
        k = 1
    return t[k:-k], (p[2 * k :] - p[: -2 * k]) / (t[2 * k :] - t[: -2 * k])[:, None]


def body_rates(t, R, window_s=0.05):
    """Body-frame angular velocity from orientations by central differences."""
    if len(t) < 3:
        return t[:0], np.zeros((0, 3))
    dt = np.median(np.diff(t))
    k = max(1, int(round(window_s / 2 / dt))) if dt > 0 else 1
    if len(t) <= 2 * k:
        k = 1
    rel = np.einsum("nji,njk->nik", R[: -2 * k], R[2 * k :])  # R_a^T R_b
    return t[k:-k], rot_log(rel) / (t[2 * k :] - t[: -2 * k])[:, None]


# ----------------------------------------------------------------------------- figures


class Run:
    def __init__(self, run_dir):
        self.dir = run_dir
        self.est = load_table(os.path.join(run_dir, "stamped_traj_estimate.txt"), 8)
        self.gt = load_table(os.path.join(run_dir, "stamped_groundtruth.txt"), 8)
        self.vel = load_table(os.path.join(run_dir, "velocities.txt"), 7)
        self.timing = load_csv_with_header(os.path.join(run_dir, "timing.csv"))
        self.tracks = load_table(os.path.join(run_dir, "tracks.txt"), 4)
        self.eval = None
        eval_path = os.path.join(run_dir, "eval.json")
        if os.path.isfile(eval_path):
            with open(eval_path) as f:
                self.eval = json.load(f)
        self.align = None  # (s, R, t, label)
        if self.est is not None and self.gt is not None:
            if self.eval and "alignment" in self.eval:
                a = self.eval["alignment"]
                self.align = (a["scale"], np.array(a["rotation"]), np.array(a["translation"]),
                              "aligned: %s (eval.json), scale %.4g" % (a["type"], a["scale"]))
            else:
                ie, ig = nearest_matches(self.est[:, 0], self.gt[:, 0])
                if len(ie) >= 3:
                    s, R, t = alignment.umeyama_sim3(self.gt[ig, 1:4], self.est[ie, 1:4])
                    self.align = (s, R, t, "aligned: sim3 (no eval.json), scale %.4g" % s)
        if self.est is not None:
            self.t0 = self.est[0, 0] if self.gt is None else min(self.est[0, 0], self.gt[0, 0])
        elif self.gt is not None:
            self.t0 = self.gt[0, 0]
        else:
            self.t0 = 0.0

    def est_aligned(self):
        """Estimate positions (n,3) and rotations (n,3,3) after the alignment (or as is)."""
        p, R = self.est[:, 1:4], quat_to_rot(self.est[:, 4:8])
        if self.align is None:
            return p, R
        s, Ra, t, _ = self.align
        return s * p @ Ra.T + t, np.einsum("ij,njk->nik", Ra, R)

    def align_label(self):
        return self.align[3] if self.align else "not aligned"


def save(fig, out_dir, name, dpi=110):
    path = os.path.join(out_dir, name)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


def plot_trajectory(run, out_dir):
    if run.est is None or run.gt is None:
        return None, "needs stamped_traj_estimate.txt and stamped_groundtruth.txt"
    p_est, _ = run.est_aligned()
    p_gt = run.gt[:, 1:4]
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5))
    for ax, (i, j, name) in zip(axes, [(0, 1, "top view (x-y)"), (0, 2, "side view (x-z)")]):
        ax.plot(p_gt[:, i], p_gt[:, j], "k-", lw=1.0, label="ground truth")
        ax.plot(p_est[:, i], p_est[:, j], "r-", lw=1.0, label="estimate")
        ax.plot(p_gt[0, i], p_gt[0, j], "ko", ms=4)
        ax.plot(p_est[0, i], p_est[0, j], "ro", ms=4)
        ax.set_xlabel("xyz"[i] + " [m]")
        ax.set_ylabel("xyz"[j] + " [m]")
        ax.set_title(name)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
    axes[0].legend()
    fig.suptitle("trajectory (%s)" % run.align_label())
    fig.tight_layout()
    return save(fig, out_dir, "trajectory.png"), None


def plot_position(run, out_dir):
    if run.est is None:
        return None, "needs stamped_traj_estimate.txt"
    p_est, _ = run.est_aligned()
    fig, axes = plt.subplots(3, 1, figsize=(10, 7.5), sharex=True)
    for k, ax in enumerate(axes):
        if run.gt is not None:
            ax.plot(run.gt[:, 0] - run.t0, run.gt[:, 1 + k], "k-", lw=1.0, label="ground truth")
        ax.plot(run.est[:, 0] - run.t0, p_est[:, k], "r-", lw=1.0, label="estimate")
        ax.set_ylabel("xyz"[k] + " [m]")
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="upper right")
    axes[-1].set_xlabel("time [s]")
    fig.suptitle("position (%s)" % run.align_label())
    fig.tight_layout()
    return save(fig, out_dir, "position.png"), None


def plot_velocity(run, out_dir):
    if run.est is None and run.gt is None:
        return None, "needs a trajectory"
    fig, axes = plt.subplots(3, 2, figsize=(12, 7.5), sharex=True)
    note = []
    if run.gt is not None:
        t, v = finite_difference(run.gt[:, 0], run.gt[:, 1:4])
        tw, w = body_rates(run.gt[:, 0], quat_to_rot(run.gt[:, 4:8]))
        for k in range(3):
            axes[k, 0].plot(t - run.t0, v[:, k], "k-", lw=0.8, label="ground truth (finite diff.)")
            axes[k, 1].plot(tw - run.t0, w[:, k], "k-", lw=0.8, label="ground truth (finite diff.)")
    if run.est is not None:
        p_est, R_est = run.est_aligned()
        if run.vel is not None:
            # Body-frame twist per knot -> world frame with the estimate's orientation at that time.
            idx = np.clip(np.searchsorted(run.est[:, 0], run.vel[:, 0]), 0, len(run.est) - 1)
            scale = run.align[0] if run.align else 1.0
            v = scale * np.einsum("nij,nj->ni", R_est[idx], run.vel[:, 1:4])
            t, tw, w = run.vel[:, 0], run.vel[:, 0], run.vel[:, 4:7]
            label = "estimate (velocities.txt)"
        else:
            t, v = finite_difference(run.est[:, 0], p_est)
            tw, w = body_rates(run.est[:, 0], quat_to_rot(run.est[:, 4:8]))
            label = "estimate (finite diff.)"
            note.append("no velocities.txt: estimate differentiated")
        for k in range(3):
            axes[k, 0].plot(t - run.t0, v[:, k], "r-", lw=0.8, label=label)
            axes[k, 1].plot(tw - run.t0, w[:, k], "r-", lw=0.8, label=label)
    for k in range(3):
        axes[k, 0].set_ylabel("v_" + "xyz"[k] + " [m/s]")
        axes[k, 1].set_ylabel("w_" + "xyz"[k] + " [rad/s]")
        for ax in axes[k]:
            ax.grid(True, alpha=0.3)
    axes[0, 0].set_title("linear velocity, world frame")
    axes[0, 1].set_title("angular velocity, body (camera) frame")
    axes[0, 0].legend(loc="upper right", fontsize=8)
    axes[2, 0].set_xlabel("time [s]")
    axes[2, 1].set_xlabel("time [s]")
    fig.suptitle("velocity (%s)%s" % (run.align_label(), ("; " + "; ".join(note)) if note else ""))
    fig.tight_layout()
    return save(fig, out_dir, "velocity.png"), None


def plot_relative_error(run, out_dir):
    if not run.eval or "relative_error" not in run.eval:
        return None, "needs eval.json"
    per_length = [e for e in run.eval["relative_error"]["per_length"] if e["samples"]["trans_m"]]
    if not per_length:
        return None, "eval.json has no relative-error samples (trajectory too short?)"
    labels = ["%.2f" % e["length_m"] for e in per_length]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for ax, key, ylabel in [(axes[0], "trans_m", "translation error [m]"),
                            (axes[1], "rot_deg", "rotation error [deg]")]:
        ax.boxplot([e["samples"][key] for e in per_length], labels=labels, showfliers=False)
        ax.set_xlabel("sub-trajectory length [m]")
        ax.set_ylabel(ylabel)
        ax.grid(True, axis="y", alpha=0.3)
    align = run.eval.get("alignment", {}).get("type", "?")
    fig.suptitle("relative error (rpg_trajectory_evaluation definition, %s scale)" % align)
    fig.tight_layout()
    return save(fig, out_dir, "relative_error.png"), None


def plot_runtime(run, out_dir):
    if run.timing is None:
        return None, "needs timing.csv"
    header, data = run.timing
    stage_cols = [k for k, h in enumerate(header) if h.endswith("_ms") and k > 0]
    if not stage_cols:
        return None, "timing.csv has no *_ms columns"
    total = header.index("total_ms") if "total_ms" in header else None
    t = data[:, 0] - run.t0 if run.est is not None else data[:, 0] - data[0, 0]
    y = data[:, total] if total is not None else data[:, stage_cols].sum(1)
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), gridspec_kw={"width_ratios": [2, 1]})
    axes[0].plot(t, y, "b.", ms=2)
    axes[0].set_xlabel("event time [s]")
    axes[0].set_ylabel("backend time per update [ms]")
    axes[0].set_title("%s per update (%d updates)" % ("total" if total is not None else "sum of stages", len(y)))
    axes[0].grid(True, alpha=0.3)
    axes[1].boxplot([data[:, k] for k in stage_cols], labels=[header[k][:-3] for k in stage_cols],
                    showfliers=False)
    axes[1].set_ylabel("ms")
    axes[1].set_title("per stage")
    plt.setp(axes[1].get_xticklabels(), rotation=30, ha="right")
    axes[1].grid(True, axis="y", alpha=0.3)
    span = data[-1, 0] - data[0, 0]
    if total is not None and span > 0:
        fig.suptitle("backend runtime (real-time factor %.3f)" % (data[:, total].sum() / 1000.0 / span))
    fig.tight_layout()
    return save(fig, out_dir, "runtime.png"), None


def plot_tracks(run, out_dir, max_tracks):
    if run.tracks is None:
        return None, "needs tracks.txt"
    ids = run.tracks[:, 0].astype(np.int64)
    order = np.argsort(ids, kind="stable")
    tr = run.tracks[order]
    ids = ids[order]
    starts = np.concatenate(([0], np.nonzero(np.diff(ids))[0] + 1, [len(ids)]))
    segments = [tr[a:b] for a, b in zip(starts[:-1], starts[1:])]
    if len(segments) > max_tracks:  # keep the longest ones
        segments = sorted(segments, key=len, reverse=True)[:max_tracks]
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the 3d projection)

    fig = plt.figure(figsize=(9, 7))
    ax = fig.add_subplot(111, projection="3d")
    cmap = plt.get_cmap("tab20")
    t0 = tr[:, 1].min()
    for k, seg in enumerate(segments):
        ax.plot(seg[:, 2], seg[:, 1] - t0, seg[:, 3], "-", lw=0.8, color=cmap(k % 20))
    ax.set_xlabel("x [px]")
    ax.set_ylabel("t [s]")
    ax.set_zlabel("y [px]")
    ax.invert_zaxis()  # image y points down
    ax.set_title("feature tracks (%d of %d shown)" % (len(segments), len(starts) - 1))
    fig.tight_layout()
    return save(fig, out_dir, "tracks.png"), None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--run", required=True, help="run folder")
    parser.add_argument("--out", help="folder for the PNG files (default: RUN/plots)")
    parser.add_argument("--max-tracks", type=int, default=400, help="longest feature tracks drawn")
    args = parser.parse_args()
    if not os.path.isdir(args.run):
        sys.exit("plot_run.py: %s: not a folder" % args.run)
    out_dir = args.out or os.path.join(args.run, "plots")
    os.makedirs(out_dir, exist_ok=True)
    run = Run(args.run)
    figures = [("trajectory", lambda: plot_trajectory(run, out_dir)),
               ("position", lambda: plot_position(run, out_dir)),
               ("velocity", lambda: plot_velocity(run, out_dir)),
               ("relative error", lambda: plot_relative_error(run, out_dir)),
               ("runtime", lambda: plot_runtime(run, out_dir)),
               ("feature tracks", lambda: plot_tracks(run, out_dir, args.max_tracks))]
    written = 0
    for name, draw in figures:
        path, why = draw()
        if path:
            print("wrote %s" % path)
            written += 1
        else:
            print("skipped %s: %s" % (name, why))
    if written == 0:
        print("no figure drawn: %s holds none of the inputs" % args.run)


if __name__ == "__main__":
    main()
