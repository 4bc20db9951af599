#!/usr/bin/python3
"""How many features a scene offers at the frontend's spacing: corners in rendered frames.

The frontend keeps at most `max_features` and seeds none within `min_distance_px` of another or within
`border_margin_px` of the image border (docs/method/frontend.md). A scene with fewer corners than that
cannot fill the budget, whatever the detector. This tool counts, in each frame a simulation rendered
(`asynevo simulate ... --frame-rate HZ` writes images/ and images.txt), the corners a greedy detector
keeps at that spacing: local maxima of the Shi-Tomasi response (the smaller eigenvalue of the
structure tensor; Shi and Tomasi, "Good features to track", CVPR 1994) above `--rel` times the
frame's largest, taken strongest first, no two closer than the spacing (Euclidean), none within the
border. The counts are an upper bound on what a corner tracker can hold there; events add no corners
a frame does not show.

  frame_corners.py SIM_FOLDER [SIM_FOLDER ...] [--min-distance 15] [--border 16] [--rel 0.01]

Prints, per folder, the median, minimum and maximum count over its frames. Needs Debian's
python3-skimage (scripts/debian-packages.txt).
"""

import argparse
import os
import statistics
import sys

import numpy as np
from skimage.feature import corner_peaks, corner_shi_tomasi
from skimage.io import imread


def count_corners(image, min_distance, border, rel):
    """Corners of one grey image (2-D array, any scale) at the given spacing and border."""
    response = corner_shi_tomasi(np.asarray(image, dtype=float), sigma=1.5)
    if not response.max() > 0:
        return 0
    # Candidates: local maxima over a 5x5 neighbourhood. The spacing is enforced greedily below, by
    # Euclidean distance as the frontend's patch search does: corner_peaks' own min_distance first
    # suppresses every weaker peak in a square around a stronger one.
    peaks = corner_peaks(response, min_distance=2, threshold_rel=rel, exclude_border=border)
    strengths = response[peaks[:, 0], peaks[:, 1]]
    kept = []
    for i in np.argsort(-strengths, kind="stable"):
        y, x = peaks[i]
        if all((x - kx) ** 2 + (y - ky) ** 2 > min_distance**2 for ky, kx in kept):
            kept.append((y, x))
    return len(kept)


def frame_paths(folder):
    """The frames of a simulation folder, in time order (images.txt: 't path' lines)."""
    listing = os.path.join(folder, "images.txt")
    if not os.path.isfile(listing):
        raise SystemExit(f"frame_corners: {listing}: no such file (simulate with --frame-rate HZ)")
    paths = []
    with open(listing) as f:
        for number, line in enumerate(f, 1):
            parts = line.split()
            if not parts or parts[0].startswith("#"):
                continue
            if len(parts) != 2:
                raise SystemExit(f"frame_corners: {listing}:{number}: expected 't path', got {line.strip()!r}")
            paths.append(os.path.join(folder, parts[1]))
    if not paths:
        raise SystemExit(f"frame_corners: {listing}: no frames")
    return paths


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folders", nargs="+", help="simulation folders with images.txt")
    parser.add_argument("--min-distance", type=float, default=15.0, help="px between two corners (min_distance_px)")
    parser.add_argument("--border", type=int, default=16, help="px kept free at the border (border_margin_px)")
    parser.add_argument("--rel", type=float, default=0.01, help="response threshold, share of the frame's largest")
    args = parser.parse_args(argv)
    for folder in args.folders:
        counts = []
        for path in frame_paths(folder):
            try:
                image = imread(path, as_gray=True)
            except (OSError, ValueError) as e:
                raise SystemExit(f"frame_corners: {path}: cannot read the image ({e})")
            counts.append(count_corners(image, args.min_distance, args.border, args.rel))
        print(f"{os.path.basename(os.path.normpath(folder))}: corners at {args.min_distance:g} px spacing, "
              f"border {args.border} px: median {statistics.median(counts):g}, min {min(counts)}, "
              f"max {max(counts)} over {len(counts)} frames")
    return 0


if __name__ == "__main__":
    sys.exit(main())
