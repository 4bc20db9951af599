"""Similarity alignment of trajectories and the drift figures built on it, for the tools under tools/.
Needs numpy (Debian's python3-numpy); the caller imports it first."""

import numpy as np

LOCAL_WINDOW_S = 2.0  # length of the windows of the local figures below
MIN_SPREAD_M = 0.02  # a window whose true positions spread less than this (RMS) has no scale to fit


def umeyama_sim3(model, data):
    """s, R, t minimizing sum |model - (s R data + t)|^2 (Umeyama, IEEE TPAMI 1991); points as rows."""
    mu_m, mu_d = model.mean(0), data.mean(0)
    m0, d0 = model - mu_m, data - mu_d
    C = m0.T @ d0 / len(model)
    U, D, Vt = np.linalg.svd(C)
    S = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt) < 0:
        S[2, 2] = -1
    R = U @ S @ Vt
    s = np.trace(np.diag(D) @ S) / (d0 ** 2).sum(1).mean()
    return s, R, mu_m - s * R @ mu_d


def nearest(t_ref, t):
    """Index into the sorted times t_ref of the entry nearest to each time in t."""
    j = np.clip(np.searchsorted(t_ref, t), 1, max(1, len(t_ref) - 1))
    return np.where(np.abs(t_ref[j - 1] - t) <= np.abs(t_ref[j] - t), j - 1, j) if len(t_ref) > 1 else j * 0


def local_drift(est, gt, segments, window_s=LOCAL_WINDOW_S):
    """How much of a trajectory's error is drift: each segment's estimate cut into consecutive windows
    of window_s, each window aligned to the ground truth by its own Sim(3). Returns (local_rmse_m,
    scale_ratio, windows): the RMSE of the positions after the windows' own alignments, the largest
    ratio between two windows' alignment scales within a segment (1 = no scale drift; windows whose
    true positions spread less than MIN_SPREAD_M are left out of it), and the number of windows.
    est, gt: (N, 8) TUM rows; segments: (start_s, end_s) of each segment. (None, None, 0) without a
    window."""
    if len(est) == 0 or len(gt) == 0:
        return None, None, 0
    matched = gt[nearest(gt[:, 0], est[:, 0])]
    sq, ratio, windows = [], 1.0, 0
    for start, end in segments:
        in_segment = (est[:, 0] >= start - 1e-6) & (est[:, 0] <= end + 1e-6)
        t = est[in_segment, 0]
        if len(t) < 3:
            continue
        scales = []
        for w0 in np.arange(t[0], t[-1], window_s):
            m = in_segment & (est[:, 0] >= w0) & (est[:, 0] < w0 + window_s)
            if m.sum() < 3:
                continue
            P, Q = est[m, 1:4], matched[m, 1:4]
            s, R, tr = umeyama_sim3(Q, P)
            sq.append(((Q - (s * (R @ P.T).T + tr)) ** 2).sum(1))
            windows += 1
            if np.sqrt(((Q - Q.mean(0)) ** 2).sum(1).mean()) >= MIN_SPREAD_M:
                scales.append(s)
        if len(scales) >= 2:
            ratio = max(ratio, max(scales) / min(scales))
    if not sq:
        return None, None, 0
    return float(np.sqrt(np.concatenate(sq).mean())), float(ratio), windows
