#!/usr/bin/python3
"""How well the chirality cost tells a start's motion from its depth-reversed alternative, against the
ground truth (docs/method/depth_reversal.md, "How far the cost can be trusted").

  reversal_truth.py --sequences matrix-out/sequences RUNS_DIR [RUNS_DIR ...]

Each RUNS_DIR holds SEQ/run/ with the comparisons a run or a replay logged (init_reversals.txt of
'asynevo run', stamped_traj_estimate.txt.init_reversals.txt of a replay; backend.init_depth_reversal
not off), and SEQ names a sequence folder with groundtruth.txt (TUM: t px py pz qx qy qz qw, the
camera's pose T_w_c). For every comparison that found an alternative, the true translation direction
over its two times, x_b = R_b_a x_a + t_b_a with T_b_a = T_w_b^-1 T_w_a (nearest ground-truth pose),
decides which of the two directions is nearer the truth. Printed per half (tuning: SEQ ends in -tune,
validation: -val) and per factor by which the alternative is cheaper (below 1: dearer): how often the
cheaper one is the nearer one. Standard library only.
"""

import argparse
import bisect
import math
import os
import sys

HALVES = (("tune", "tuning"), ("val", "validation"))
# Bins of cost / reversed_cost: above 1 the alternative is cheaper.
BINS = ((0.0, 0.8), (0.8, 1.0), (1.0, 1.25), (1.25, 1.5), (1.5, 2.0), (2.0, math.inf))


def rotation(qx, qy, qz, qw):
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    x, y, z, w = qx / n, qy / n, qz / n, qw / n
    return ((1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
            (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
            (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)))


def data_lines(path, fields):
    """(line number, numbers) of each data line of a text file with `fields` fields per line; the last
    text fields (after the numbers) are kept as strings. Exits naming the file and line on a bad one."""
    with open(path) as f:
        for number, line in enumerate(f, 1):
            if not line.strip() or line.startswith("#"):
                continue
            v = line.split()
            try:
                if len(v) != len(fields):
                    raise ValueError("%d fields, need %d" % (len(v), len(fields)))
                values = [float(x) if kind == "number" else x for x, kind in zip(v, fields)]
            except ValueError as e:
                raise SystemExit("reversal_truth: %s line %d: %s" % (path, number, e))
            if not all(math.isfinite(x) for x in values if isinstance(x, float)):
                raise SystemExit("reversal_truth: %s line %d: a value is not finite" % (path, number))
            yield values


def read_groundtruth(path):
    times, poses = [], []
    for t, px, py, pz, qx, qy, qz, qw in data_lines(path, ["number"] * 8):
        times.append(t)
        poses.append((rotation(qx, qy, qz, qw), (px, py, pz)))
    if not times:
        raise SystemExit("reversal_truth: %s: no poses" % path)
    return times, poses


def nearest(times, poses, t):
    i = bisect.bisect_left(times, t)
    if i > 0 and (i == len(times) or t - times[i - 1] <= times[i] - t):
        i -= 1
    return poses[i]


def true_translation(gt, t_a, t_b):
    """t_b_a of x_b = R_b_a x_a + t_b_a: R_b^T (p_a - p_b)."""
    (R_a, p_a), (R_b, p_b) = nearest(*gt, t_a), nearest(*gt, t_b)
    d = [p_a[k] - p_b[k] for k in range(3)]
    return [sum(R_b[k][i] * d[k] for k in range(3)) for i in range(3)]


def angle_deg(u, v):
    nu, nv = math.sqrt(sum(x * x for x in u)), math.sqrt(sum(x * x for x in v))
    if nu == 0 or nv == 0:
        return math.nan
    c = max(-1.0, min(1.0, sum(a * b for a, b in zip(u, v)) / (nu * nv)))
    return math.degrees(math.acos(c))


# init_reversals.txt: t_a_s t_b_s method features parallax_px cost reversed_cost tx ty tz rx ry rz decision
CHECK_FIELDS = ["number", "number", "text"] + ["number"] * 10 + ["text"]


def read_checks(path):
    """The comparisons of one init_reversals file: (t_a, t_b, method, cost, reversed_cost, t, reversed_t)."""
    return [(v[0], v[1], v[2], v[5], v[6], v[7:10], v[10:13]) for v in data_lines(path, CHECK_FIELDS)]


def log_of(run_dir):
    for name in ("init_reversals.txt", "stamped_traj_estimate.txt.init_reversals.txt"):
        path = os.path.join(run_dir, name)
        if os.path.exists(path):
            return path
    return None


def collect(runs_dirs, sequences):
    """Per comparison with an alternative: (half, method, cost / reversed_cost, cheaper_is_nearer)."""
    samples = []
    for runs in runs_dirs:
        if not os.path.isdir(runs):
            raise SystemExit("reversal_truth: %s is not a folder" % runs)
        for seq in sorted(os.listdir(runs)):
            path = log_of(os.path.join(runs, seq, "run"))
            if path is None:
                continue
            half = next((h for suffix, h in HALVES if seq.endswith("-" + suffix)), None)
            gt_path = os.path.join(sequences, seq, "groundtruth.txt")
            if not os.path.exists(gt_path):
                raise SystemExit("reversal_truth: %s has no ground truth (%s)" % (seq, gt_path))
            gt = read_groundtruth(gt_path)
            for t_a, t_b, method, cost, reversed_cost, t, reversed_t in read_checks(path):
                if reversed_cost <= 0:
                    continue  # no alternative found
                truth = true_translation(gt, t_a, t_b)
                given_off, reversed_off = angle_deg(t, truth), angle_deg(reversed_t, truth)
                if math.isnan(given_off) or math.isnan(reversed_off):
                    continue  # the camera did not move between the two times
                cheaper_is_nearer = (reversed_cost < cost) == (reversed_off < given_off)
                samples.append((half, method, cost / reversed_cost, cheaper_is_nearer, reversed_off < given_off))
    return samples


def table(samples):
    lines = []
    for _, half in HALVES + (("", None),):
        for method in ("two-view", "multi-view", "audit"):
            rows = [s for s in samples if s[0] == half and s[1] == method]
            if not rows:
                continue
            lines.append("%s, %s: %d comparisons with an alternative" % (half or "other", method, len(rows)))
            for lo, hi in BINS:
                sel = [s for s in rows if lo <= s[2] < hi]
                right = sum(1 for s in sel if s[3])
                reversed_nearer = sum(1 for s in sel if s[4])
                lines.append("  cost / alternative's cost %.2f-%s: %4d; the cheaper nearer the truth %4d (%s); the "
                             "alternative nearer %4d" % (lo, "inf" if hi == math.inf else "%.2f" % hi, len(sel), right,
                                                         "%.0f %%" % (100.0 * right / len(sel)) if sel else "-",
                                                         reversed_nearer))
    return lines


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="RUNS_DIR with SEQ/run/")
    parser.add_argument("--sequences", required=True, help="folder of the sequences (SEQ/groundtruth.txt)")
    args = parser.parse_args(argv)
    samples = collect(args.runs, args.sequences)
    if not samples:
        raise SystemExit("reversal_truth: no comparison with an alternative in %s" % ", ".join(args.runs))
    print("\n".join(table(samples)))


if __name__ == "__main__":
    main(sys.argv[1:])
