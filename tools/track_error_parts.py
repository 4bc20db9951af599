#!/usr/bin/python3
"""What a track's error is made of, from the per-measurement errors that
`bench_replay_tracks RUN SEQ OUT --dump-errors FILE` writes (lines `id t x y x_true y_true`, raw pixels;
the truth is the projection of the scene point on the ray of the track's first measurement).

Prints three readings (docs/results/track_errors.md):
  * slow and fast parts: each track's error smoothed by a centred moving average over --window-ms, and
    what is left (jitter);
  * anchoring later: the error measured against the track's measurement at age K (e(t) - e(t_K)) for
    measurements older than K, against the error from the first one, for K in --anchor-ms;
  * a lag along the motion: per track the error and the direction of the true image motion with their
    track means removed, the least-squares lag b of e = b * direction, and what is left after it;
  * the error by the track's age and by how far its image motion has turned since its first 20 ms;
  * with --corners FILE (lines `t x y score`, `frontend_eval --corners`): each measurement moved by the
    median offset from the track of the corner events within --corner-radius px of it over
    --corner-window-ms (where there are at least --corner-min of them), and the error after.

Needs numpy (Debian's python3-numpy). Run with /usr/bin/python3."""

import argparse
import sys

import numpy as np

MIN_SPEED_PX_S = 5.0  # image motion slower than this has no direction
MIN_MEASUREMENTS = 6  # shorter tracks are left out


def read_dump(path):
    """Rows of (id, t, x, y, x_true, y_true) sorted by track and time; an error names the line."""
    rows = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            if not line.strip() or line.startswith("#"):
                continue
            fields = line.split()
            try:
                values = [float(v) for v in fields]
            except ValueError:
                values = []
            if len(values) != 6 or not np.all(np.isfinite(values)):
                raise ValueError("%s:%d: expected 'id t x y x_true y_true', got %r" % (path, number, line.rstrip()))
            rows.append(values)
    if not rows:
        raise ValueError("%s: no measurement" % path)
    d = np.array(rows)
    return d[np.lexsort((d[:, 1], d[:, 0]))]


def tracks(d):
    """(times, errors, true positions) of each track with at least MIN_MEASUREMENTS measurements."""
    _, starts = np.unique(d[:, 0], return_index=True)
    bounds = list(starts) + [len(d)]
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a >= MIN_MEASUREMENTS:
            yield d[a:b, 1], d[a:b, 2:4] - d[a:b, 4:6], d[a:b, 4:6]


def norms(x):
    return np.linalg.norm(x, axis=1)


def slow_and_fast(d, window_s):
    """Median |error|, |smoothed error| and |error - smoothed| over all measurements."""
    raw, slow, fast = [], [], []
    for t, e, _ in tracks(d):
        s = np.array([e[np.abs(t - ti) <= window_s / 2].mean(0) for ti in t])
        raw.append(e)
        slow.append(s)
        fast.append(e - s)
    return tuple(float(np.median(norms(np.vstack(x)))) for x in (raw, slow, fast))


def anchored_later(d, age_s):
    """Over measurements older than age_s: median |e(t)| and median |e(t) - e(t_K)|, t_K the first
    measurement at age >= age_s; and their count."""
    first, later = [], []
    for t, e, _ in tracks(d):
        age = t - t[0]
        k = int(np.searchsorted(age, age_s - 1e-12))
        if k >= len(t) - 1:
            continue
        first.append(norms(e[k + 1:]))
        later.append(norms(e[k + 1:] - e[k]))
    if not first:
        return float("nan"), float("nan"), 0
    first, later = np.concatenate(first), np.concatenate(later)
    return float(np.median(first)), float(np.median(later)), len(first)


def motion_lag(d):
    """Least-squares lag b (px) of e = c_track + b * direction, and the median |e - c_track| before and
    after removing b * direction (direction: unit true image motion, 0 where slower than MIN_SPEED)."""
    errors, directions = [], []
    for t, e, truth in tracks(d):
        v = np.gradient(truth, t, axis=0)
        speed = norms(v)
        direction = np.where((speed > MIN_SPEED_PX_S)[:, None], v / np.maximum(speed, 1e-12)[:, None], 0.0)
        errors.append(e - e.mean(0))
        directions.append(direction - direction.mean(0))
    e, u = np.vstack(errors), np.vstack(directions)
    b = float((e * u).sum() / max((u * u).sum(), 1e-12))
    return b, float(np.median(norms(e))), float(np.median(norms(e - b * u)))


AGE_EDGES_S = (0.0, 0.05, 0.2, 0.5, float("inf"))
TURN_EDGES_DEG = (0.0, 15.0, 45.0, 90.0, 180.01)


def error_by_turn_and_age(d):
    """Median |error| (and count) per bin of turn (the angle between the true image motion at the
    measurement and its mean over the track's first 20 ms) and age; {(turn bin, age bin): (median, n)}.
    Measurements whose image moves slower than MIN_SPEED, and tracks that start slower, are left out."""
    turns, ages, errors = [], [], []
    for t, e, truth in tracks(d):
        v = np.gradient(truth, t, axis=0)
        speed = norms(v)
        v0 = v[(t - t[0]) <= 0.02].mean(0)
        if np.linalg.norm(v0) < MIN_SPEED_PX_S:
            continue
        moving = speed > MIN_SPEED_PX_S
        cosine = (v[moving] @ v0) / (speed[moving] * np.linalg.norm(v0))
        turns.append(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))
        ages.append((t - t[0])[moving])
        errors.append(norms(e)[moving])
    table = {}
    if not errors:
        return table
    turn, age, error = np.concatenate(turns), np.concatenate(ages), np.concatenate(errors)
    for i in range(len(TURN_EDGES_DEG) - 1):
        for j in range(len(AGE_EDGES_S) - 1):
            s = (turn >= TURN_EDGES_DEG[i]) & (turn < TURN_EDGES_DEG[i + 1]) & (age >= AGE_EDGES_S[j]) & (
                age < AGE_EDGES_S[j + 1])
            if s.any():
                table[(i, j)] = (float(np.median(error[s])), int(s.sum()))
    return table


def snapped_to_corners(d, corners, radius, window_s, min_corners):
    """Median |error| with each track's mean removed, before and after moving each measurement by the
    median offset of the nearby corner events; and how many measurements moved, of how many."""
    ct, cp = corners[:, 0], corners[:, 1:3]
    before, after, moved, total = [], [], 0, 0
    for t, e, truth in tracks(d):
        m = truth + e
        i0, i1 = np.searchsorted(ct, [t[0] - window_s, t[-1] + window_s])
        tc = ct[i0:i1]
        offset = cp[i0:i1] - np.stack([np.interp(tc, t, m[:, 0]), np.interp(tc, t, m[:, 1])], 1)
        near = norms(offset) <= radius if len(tc) else np.zeros(0, bool)
        tc, offset = tc[near], offset[near]
        snapped = m.copy()
        for i in range(len(t)):
            within = np.abs(tc - t[i]) <= window_s / 2
            total += 1
            if within.sum() >= min_corners:
                snapped[i] = m[i] + np.median(offset[within], 0)
                moved += 1
        es = snapped - truth
        before.append(e - e.mean(0))
        after.append(es - es.mean(0))
    return float(np.median(norms(np.vstack(before)))), float(np.median(norms(np.vstack(after)))), moved, total


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dump", help="a --dump-errors file of bench_replay_tracks")
    parser.add_argument("--window-ms", type=float, default=50.0, help="moving-average window (default 50)")
    parser.add_argument("--anchor-ms", type=float, nargs="+", default=[10, 20, 50, 100])
    parser.add_argument("--corners", help="corner events (frontend_eval --corners)")
    parser.add_argument("--corner-radius", type=float, default=1.5, help="px (default 1.5)")
    parser.add_argument("--corner-window-ms", type=float, default=20.0, help="default 20")
    parser.add_argument("--corner-min", type=int, default=3, help="default 3")
    args = parser.parse_args(argv)
    if not args.window_ms > 0 or any(not k >= 0 for k in args.anchor_ms):
        parser.error("--window-ms must be > 0 and --anchor-ms >= 0")
    try:
        d = read_dump(args.dump)
        corners = None
        if args.corners:
            corners = np.loadtxt(args.corners, ndmin=2)
            if corners.shape[1] < 3 or not np.all(np.isfinite(corners)):
                raise ValueError("%s: expected lines 't x y score'" % args.corners)
            corners = corners[np.argsort(corners[:, 0], kind="stable")]
    except (OSError, ValueError) as e:
        print("track_error_parts: %s" % e, file=sys.stderr)
        return 1
    raw, slow, fast = slow_and_fast(d, args.window_ms * 1e-3)
    print("measurements %d of %d tracks" % (len(d), len(np.unique(d[:, 0]))))
    print("median |error| %.3f px; smoothed over %g ms %.3f px; what is left (jitter) %.3f px"
          % (raw, args.window_ms, slow, fast))
    for k in args.anchor_ms:
        first, later, n = anchored_later(d, k * 1e-3)
        print("older than %g ms (%d): from the first measurement %.3f px, from the one at %g ms %.3f px"
              % (k, n, first, k, later))
    b, before, after = motion_lag(d)
    print("lag along the true image motion %.3f px; error less its track mean %.3f px, less the lag too %.3f px"
          % (b, before, after))
    table = error_by_turn_and_age(d)
    print("median |error| px (measurements) by the turn of the image motion since the track's first 20 ms"
          " and the age")
    print("turn \\ age       " + "".join("%-16s" % ("%g-%g s" % (AGE_EDGES_S[j], AGE_EDGES_S[j + 1]))
                                       for j in range(len(AGE_EDGES_S) - 1)))
    for i in range(len(TURN_EDGES_DEG) - 1):
        cells = ["%.3f (%d)" % table[(i, j)] if (i, j) in table else "-" for j in range(len(AGE_EDGES_S) - 1)]
        print("%-17s" % ("%g-%g deg" % (TURN_EDGES_DEG[i], min(TURN_EDGES_DEG[i + 1], 180)))
              + "".join("%-16s" % c for c in cells))
    if corners is not None:
        before, after, moved, total = snapped_to_corners(d, corners, args.corner_radius,
                                                         args.corner_window_ms * 1e-3, args.corner_min)
        print("moved to the corners within %g px over %g ms (at least %d): %d of %d measurements; error less its"
              " track mean %.3f -> %.3f px" % (args.corner_radius, args.corner_window_ms, args.corner_min, moved,
                                               total, before, after))
    return 0


if __name__ == "__main__":
    sys.exit(main())
