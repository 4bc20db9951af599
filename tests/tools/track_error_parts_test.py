#!/usr/bin/python3
"""tools/track_error_parts.py on synthetic error dumps: a lag along a turning motion, a slow error with
jitter on top, an offset that appears after the first measurement, a malformed line named."""

import contextlib
import io
import math
import os
import sys
import tempfile

import numpy as np

from tool_checks import check, exit_code

import track_error_parts as tep  # noqa: E402  (tools/, put on the path by tool_checks)


def write(path, rows):
    with open(path, "w") as f:
        f.write("# id t x y x_true y_true\n")
        for r in rows:
            f.write(" ".join("%.9f" % v for v in r) + "\n")


with tempfile.TemporaryDirectory() as root:
    # 1. Tracks moving on circles (100 px/s), each measured 0.3 px behind its motion: a lag of -0.3 px
    #    that turns with the motion; nothing else.
    rows = []
    for track in range(5):
        for k in range(200):
            t = 0.005 * k
            a = 2 * math.pi * t + track
            x, y = 100 + 16 * math.cos(a), 90 + 16 * math.sin(a)
            dx, dy = -math.sin(a), math.cos(a)  # direction of the motion
            rows.append((track, t, x - 0.3 * dx, y - 0.3 * dy, x, y))
    write(os.path.join(root, "lag.txt"), rows)
    d = tep.read_dump(os.path.join(root, "lag.txt"))
    b, before, after = tep.motion_lag(d)
    check(abs(b + 0.3) < 0.01, "a lag of 0.3 px behind the motion is found (b = %.4f)" % b)
    check(before > 0.25 and after < 0.01, "removing it leaves nothing (%.3f -> %.4f px)" % (before, after))

    # 2. A slow error (1 px sine, period 1 s) with an alternating +-0.1 px jitter on top.
    rows = []
    for k in range(400):
        t = 0.005 * k
        slow = math.sin(2 * math.pi * t)
        rows.append((1, t, 50 + slow + (0.1 if k % 2 else -0.1), 50, 50, 50))
    write(os.path.join(root, "slow.txt"), rows)
    raw, slow, fast = tep.slow_and_fast(tep.read_dump(os.path.join(root, "slow.txt")), 0.06)
    check(abs(fast - 0.1) < 0.02, "the jitter is the part the moving average leaves (%.3f px)" % fast)
    check(abs(slow - math.sqrt(0.5)) < 0.05, "the slow part is the sine (median |sin| %.3f px)" % slow)

    # 3. An offset of 0.5 px from the second measurement on: from the first measurement every later error
    #    is 0.5 px, from the one at 20 ms none is.
    rows = [(2, 0.005 * k, 10 + (0.5 if k > 0 else 0.0), 10, 10, 10) for k in range(50)]
    write(os.path.join(root, "offset.txt"), rows)
    first, later, n = tep.anchored_later(tep.read_dump(os.path.join(root, "offset.txt")), 0.02)
    check(abs(first - 0.5) < 1e-9 and later < 1e-9, "anchoring later removes a settled offset (%.3f, %.3f)"
          % (first, later))
    check(n == 45, "measurements older than 20 ms counted (%d)" % n)

    # 4. Corners exactly at the true point every 2 ms: a track that wanders by a 0.5 px sine is pulled
    #    back onto it; corners 5 px away are not used.
    corner_rows = []
    for k in range(200):
        t = 0.002 * k
        corner_rows.append((t, 30.0, 40.0, 10.0))
        corner_rows.append((t, 35.0, 40.0, 10.0))
    np.savetxt(os.path.join(root, "corners.txt"), np.array(corner_rows), header="t x y score")
    rows = [(3, 0.005 * k, 30 + 0.5 * math.sin(2 * math.pi * 0.005 * k), 40, 30, 40) for k in range(80)]
    write(os.path.join(root, "wander.txt"), rows)
    corners = np.loadtxt(os.path.join(root, "corners.txt"), ndmin=2)
    before, after, moved, total = tep.snapped_to_corners(tep.read_dump(os.path.join(root, "wander.txt")),
                                                         corners, 1.5, 0.02, 3)
    check(moved == total == 80, "every measurement has corners near it (%d of %d)" % (moved, total))
    check(before > 0.05 and after < 0.01, "the corners pull the wander back (%.3f -> %.3g px)" % (before, after))

    # 5. The lag tracks of case 1 (turning at 2 pi rad/s, a constant 0.3 px): the same error in every cell;
    #    a straight track whose error grows with its age: larger in the older cells only.
    table = tep.error_by_turn_and_age(tep.read_dump(os.path.join(root, "lag.txt")))
    check(all(abs(m - 0.3) < 1e-3 for m, _ in table.values()) and len(table) >= 8,
          "a constant error is the same at every turn and age (%d cells)" % len(table))
    rows = [(4, 0.005 * k, 20 + 100 * 0.005 * k, 60 + 0.5 * 0.005 * k, 20 + 100 * 0.005 * k, 60)
            for k in range(200)]
    write(os.path.join(root, "growing.txt"), rows)
    table = tep.error_by_turn_and_age(tep.read_dump(os.path.join(root, "growing.txt")))
    check(set(i for i, _ in table) == {0}, "a straight track stays in the first turn bin")
    check(table[(0, 3)][0] > table[(0, 1)][0] > table[(0, 0)][0], "its error grows with the age bins")

    # 6. A malformed line is named with its file and line; the command exits non-zero.
    bad = os.path.join(root, "bad.txt")
    with open(bad, "w") as f:
        f.write("# id t x y x_true y_true\n1 0.0 1 2 3 4\n1 0.1 1 nan 3 4\n")
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = tep.main([bad])
    check(code == 1 and "bad.txt:3" in err.getvalue(), "a bad line is named: %r" % err.getvalue().strip())
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = tep.main([os.path.join(root, "lag.txt")])
    check(code == 0 and "lag along the true image motion -0.300 px" in out.getvalue(),
          "the command prints the lag:\n" + out.getvalue())

sys.exit(exit_code())
