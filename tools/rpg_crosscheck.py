#!/usr/bin/python3
"""Independent re-computation of an evaluation with rpg_trajectory_evaluation's definitions, written
as a straight transcription of the toolbox's *procedure* (not its code) in numpy: all-pairs
timestamp association in float seconds, Umeyama through numpy's SVD, 4x4 homogeneous matrices
inverted with numpy.linalg.inv, the O(n^2) forward scan for sub-trajectory ends. It shares nothing
with the C++ implementation, so agreement checks the C++ fast paths (sliding-window association,
binary-searched end indices, closed-form inverses).

Usage: rpg_crosscheck.py --gt GT --est EST --eval EVAL_JSON [--tol 1e-6] [--abs-tol 1e-5]
Prints every statistic that differs by more than --tol relative and --abs-tol absolute (the
arccos in the rotation angle leaves ~1e-6 deg of rounding noise near 0 in any implementation) and
exits 1 if there is one.
Supports align types sim3/se3/posyaw/none with all frames (what the C++ tests exercise).
"""

import argparse
import json
import sys

import numpy as np


def load(path):
    rows = []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if s and not s.startswith("#"):
                rows.append([float(v) for v in s.split()])
    return np.array(rows)


def associate(t_es, t_gt, max_diff=0.02):
    cand = []
    for a, ta in enumerate(t_es):
        lo = np.searchsorted(t_gt, ta - max_diff - 1e-3)
        hi = np.searchsorted(t_gt, ta + max_diff + 1e-3)
        for b in range(lo, hi):
            d = abs(ta - t_gt[b])
            if d < max_diff:
                cand.append((d, a, b))
    cand.sort()
    used_a, used_b, matches = set(), set(), []
    for d, a, b in cand:
        if a not in used_a and b not in used_b:
            used_a.add(a)
            used_b.add(b)
            matches.append((a, b))
    matches.sort()
    return matches


def quat_matrix(q):  # x y z w -> 4x4
    q = np.array(q, dtype=float)
    n = np.dot(q, q)
    q *= np.sqrt(2.0 / n)
    x, y, z, w = q
    return np.array([[1 - y * y - z * z, x * y - z * w, x * z + y * w, 0],
                     [x * y + z * w, 1 - x * x - z * z, y * z - x * w, 0],
                     [x * z - y * w, y * z + x * w, 1 - x * x - y * y, 0],
                     [0, 0, 0, 1.0]])


def umeyama(model, data, with_scale, yaw_only=False):
    mu_m, mu_d = model.mean(0), data.mean(0)
    m0, d0 = model - mu_m, data - mu_d
    n = len(model)
    C = m0.T @ d0 / n
    sigma2 = (d0 * d0).sum() / n
    U, D, Vt = np.linalg.svd(C)
    S = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt.T) < 0:
        S[2, 2] = -1
    R = U @ S @ Vt
    if yaw_only:
        M = d0.T @ m0
        th = np.pi / 2 - np.arctan2(M[0, 0] + M[1, 1], M[0, 1] - M[1, 0])
        R = np.array([[np.cos(th), -np.sin(th), 0], [np.sin(th), np.cos(th), 0], [0, 0, 1.0]])
    s = np.trace(np.diag(D) @ S) / sigma2 if with_scale else 1.0
    return s, R, mu_m - s * R @ mu_d


def rot_angle_log(R):
    tr = np.trace(R)
    if abs(tr + 1) < 1e-10:
        return np.pi
    tr3 = tr - 3
    if tr3 < -1e-7:
        th = np.arccos((tr - 1) / 2)
        mag = th / (2 * np.sin(th))
    else:
        mag = 0.5 - tr3 * tr3 / 12
    return np.linalg.norm(mag * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]))


def stats(v):
    v = np.asarray(v)
    if len(v) == 0:
        return None
    return dict(rmse=float(np.sqrt(np.dot(v, v) / len(v))), mean=float(np.mean(v)), median=float(np.median(v)),
                std=float(np.std(v)), min=float(np.min(v)), max=float(np.max(v)), num_samples=len(v))


def distances(p):
    d = np.sqrt(np.sum(np.diff(p, axis=0) ** 2, 1))
    return np.concatenate(([0], np.cumsum(d)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gt", required=True)
    ap.add_argument("--est", required=True)
    ap.add_argument("--eval", required=True)
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--abs-tol", type=float, default=1e-5)
    a = ap.parse_args()
    gt, es = load(a.gt), load(a.est)
    ev = json.load(open(a.eval))
    align = ev["alignment"]["type"]
    m = associate(es[:, 0], gt[:, 0])
    ie = [x for x, _ in m]
    ig = [y for _, y in m]
    p_es, q_es, p_gt, q_gt = es[ie, 1:4], es[ie, 4:8], gt[ig, 1:4], gt[ig, 4:8]
    if align == "sim3":
        s, R, t = umeyama(p_gt, p_es, True)
    elif align == "se3":
        s, R, t = umeyama(p_gt, p_es, False)
    elif align == "posyaw":
        s, R, t = umeyama(p_gt, p_es, False, yaw_only=True)
    else:
        s, R, t = 1.0, np.eye(3), np.zeros(3)
    p_al = s * p_es @ R.T + t
    e_trans = np.sqrt(np.sum((p_gt - p_al) ** 2, 1))
    e_rot = []
    for i in range(len(p_al)):
        R_we = R @ quat_matrix(q_es[i])[:3, :3]
        R_wg = quat_matrix(q_gt[i])[:3, :3]
        e_rot.append(np.rad2deg(rot_angle_log(R_we @ np.linalg.inv(R_wg))))
    mine = {"matched": len(m), "scale": s, "ate.trans_m": stats(e_trans), "ate.rot_deg": stats(e_rot)}
    traj_len = distances(gt[:, 1:4])[-1]
    acc = distances(p_gt)
    lengths = [e["length_m"] for e in ev["relative_error"]["per_length"]]
    pct_lengths = [np.trunc(pct * traj_len * 100.0) / 100.0 for pct in [0.1, 0.2, 0.3, 0.4, 0.5]]
    for k, L in enumerate(lengths):
        tol = 0.2 * L
        comps = []
        for idx in range(len(acc)):
            err = np.abs(acc[idx:] - (acc[idx] + L))
            j = int(np.argmin(err))
            if err[j] < tol:
                comps.append(idx + j)
        tr, rot = [], []
        if len(comps) >= 2:
            for idx, c in enumerate(comps):
                T_c1 = quat_matrix(q_es[idx]); T_c1[:3, 3] = p_es[idx]
                T_c2 = quat_matrix(q_es[c]); T_c2[:3, 3] = p_es[c]
                T_c12 = np.linalg.inv(T_c1) @ T_c2
                T_c12[:3, 3] *= s
                T_m1 = quat_matrix(q_gt[idx]); T_m1[:3, 3] = p_gt[idx]
                T_m2 = quat_matrix(q_gt[c]); T_m2[:3, 3] = p_gt[c]
                T_m12 = np.linalg.inv(T_m1) @ T_m2
                E = np.linalg.inv(T_m12) @ T_c12
                Rot = np.eye(4); Rot[:3, :3] = T_c2[:3, :3]
                E = Rot @ E @ np.linalg.inv(Rot)
                tr.append(np.linalg.norm(E[:3, 3]))
                rot.append(np.arccos(min(1, max(-1, (np.trace(E[:3, :3]) - 1) / 2))) * 180 / np.pi)
        mine["rel[%d].trans_m" % k] = stats(tr)
        mine["rel[%d].trans_perc" % k] = stats(np.array(tr) / L * 100)
        mine["rel[%d].rot_deg" % k] = stats(rot)
    theirs = {"matched": ev["association"]["matched"], "scale": ev["alignment"]["scale"],
              "ate.trans_m": ev["ate"]["trans_m"], "ate.rot_deg": ev["ate"]["rot_deg"]}
    for k, e in enumerate(ev["relative_error"]["per_length"]):
        theirs["rel[%d].trans_m" % k] = e["trans_m"]
        theirs["rel[%d].trans_perc" % k] = e["trans_perc"]
        theirs["rel[%d].rot_deg" % k] = e["rot_deg"]
    worst = 0.0
    ok = True
    if not ev["relative_error"]["per_length"]:
        print("no relative errors in %s" % a.eval)
    if len(lengths) == 5 and any(abs(x - y) > 0 for x, y in zip(lengths, pct_lengths)):
        print("lengths differ: python %s, C++ %s" % (pct_lengths, lengths))
        ok = False
    for key in mine:
        a_, b_ = mine[key], theirs[key]
        if isinstance(a_, dict) or isinstance(b_, dict):
            if a_ is None and b_.get("num_samples", 0) == 0:
                continue
            if a_ is None or b_.get("num_samples", 0) != a_["num_samples"]:
                print("%-22s sample counts differ: %s vs %s" % (key, a_ and a_["num_samples"], b_.get("num_samples")))
                ok = False
                continue
            for f in ["rmse", "mean", "median", "std", "min", "max"]:
                d = abs(a_[f] - b_[f]) / max(abs(a_[f]), 1e-9)
                if abs(a_[f] - b_[f]) <= a.abs_tol:
                    d = min(d, a.tol)
                worst = max(worst, d)
                if d > a.tol:
                    print("%-22s %-6s python %.12g  C++ %.12g  rel diff %.2g" % (key, f, a_[f], b_[f], d))
                    ok = False
        else:
            d = abs(a_ - b_) / max(abs(a_), 1e-9)
            worst = max(worst, d)
            if d > a.tol:
                print("%-22s python %.12g  C++ %.12g" % (key, a_, b_))
                ok = False
    print("compared %d statistics groups, largest relative difference (beyond the absolute floor) %.3g: %s"
          % (len(mine), worst, "AGREE" if ok else "DIFFER"))
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
