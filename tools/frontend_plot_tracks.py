#!/usr/bin/python3
"""Figures of frontend feature tracks (asynevo track output, 'id t x y' per line).

  <prefix>_xyt.png      feature trajectories in (x, y, t), one colour per feature
  <prefix>_overlay.png  the tracks drawn over an image of event counts (when --events is given)

Needs Debian's python3-matplotlib and python3-numpy; run with /usr/bin/python3.
Usage: frontend_plot_tracks.py --tracks tracks.txt [--events events.txt] --prefix docs/images/frontend_x
       [--width 240 --height 180] [--title TEXT]
"""

import argparse
import sys

try:
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:  # pragma: no cover
    sys.exit("frontend_plot_tracks.py: %s (install python3-matplotlib, run /usr/bin/python3)" % e)


def read_tracks(path):
    data = np.loadtxt(path, ndmin=2)
    tracks = {}
    for fid, t, x, y in data:
        tracks.setdefault(int(fid), []).append((t, x, y))
    return {k: np.array(sorted(v)) for k, v in tracks.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tracks", required=True)
    ap.add_argument("--events")
    ap.add_argument("--prefix", required=True)
    ap.add_argument("--width", type=int, default=240)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--title", default="")
    a = ap.parse_args()

    tracks = read_tracks(a.tracks)
    if not tracks:
        sys.exit("no tracks in %s" % a.tracks)
    t0 = min(v[0, 0] for v in tracks.values())
    cmap = plt.get_cmap("tab20")

    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    for i, (fid, v) in enumerate(sorted(tracks.items())):
        ax.plot(v[:, 1], (v[:, 0] - t0) * 1e3, v[:, 2], "-o", ms=2, lw=1.2, color=cmap(i % 20))
    ax.set_xlabel("x [px]")
    ax.set_ylabel("t [ms]")
    ax.set_zlabel("y [px]")
    ax.set_xlim(0, a.width)
    ax.set_zlim(a.height, 0)
    ax.set_title(a.title or "feature trajectories (%d features)" % len(tracks))
    fig.tight_layout()
    fig.savefig(a.prefix + "_xyt.png", dpi=110)
    print("wrote", a.prefix + "_xyt.png")

    if a.events:
        ev = np.loadtxt(a.events, usecols=(1, 2), dtype=int)
        img = np.zeros((a.height, a.width))
        np.add.at(img, (ev[:, 1], ev[:, 0]), 1)
        fig, ax = plt.subplots(figsize=(7, 5.5))
        ax.imshow(np.minimum(img, np.percentile(img[img > 0], 95)), cmap="gray_r")
        for i, (fid, v) in enumerate(sorted(tracks.items())):
            ax.plot(v[:, 1], v[:, 2], "-", lw=1.8, color=cmap(i % 20))
            ax.plot(v[-1, 1], v[-1, 2], "o", ms=4, color=cmap(i % 20))
        ax.set_xlim(-0.5, a.width - 0.5)
        ax.set_ylim(a.height - 0.5, -0.5)
        ax.set_title(a.title or "tracks over event counts")
        fig.tight_layout()
        fig.savefig(a.prefix + "_overlay.png", dpi=110)
        print("wrote", a.prefix + "_overlay.png")


if __name__ == "__main__":
    main()
