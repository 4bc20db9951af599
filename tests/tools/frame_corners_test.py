#!/usr/bin/python3
"""tools/frame_corners.py on synthetic frames: four squares have 16 corners at a small spacing and one
per square when the spacing exceeds a square's diagonal; the border and a blank frame count none; a
folder without images.txt is an error naming the file."""

import os
import sys
import tempfile

import numpy as np
from skimage.io import imsave

from tool_checks import check, exit_code

import frame_corners  # noqa: E402  (tools/, put on the path by tool_checks)


def squares(positions, size=20, shape=(180, 240)):
    image = np.full(shape, 0.9)
    for y, x in positions:
        image[y : y + size, x : x + size] = 0.1
    return image


four = squares([(40, 40), (40, 160), (120, 40), (120, 160)])
check(frame_corners.count_corners(four, 5, 16, 0.01) == 16, "four squares: 16 corners 5 px apart or more")
check(frame_corners.count_corners(four, 30, 16, 0.01) == 4, "four squares: one corner each at a 30 px spacing")
near_edge = squares([(2, 2)])
check(frame_corners.count_corners(near_edge, 5, 16, 0.01) == 1, "a square at the corner: only its inner corner is inside the border")
check(frame_corners.count_corners(np.full((180, 240), 0.5), 5, 16, 0.01) == 0, "a blank frame: no corner")

with tempfile.TemporaryDirectory() as folder:
    os.makedirs(os.path.join(folder, "images"))
    with open(os.path.join(folder, "images.txt"), "w") as f:
        for i, image in enumerate([four, squares([(40, 40)])]):
            name = f"images/frame_{i}.png"
            imsave(os.path.join(folder, name), (image * 255).astype(np.uint8), check_contrast=False)
            f.write(f"{i * 0.5:.3f} {name}\n")
    check(frame_corners.frame_paths(folder)[1].endswith("frame_1.png"), "images.txt: frames in time order")
    check(frame_corners.main([folder, "--min-distance", "5"]) == 0, "a folder of two frames is counted")
    os.remove(os.path.join(folder, "images.txt"))
    try:
        frame_corners.frame_paths(folder)
        check(False, "a folder without images.txt is an error")
    except SystemExit as e:
        check("images.txt: no such file" in str(e), "a folder without images.txt: the error names the file")

sys.exit(exit_code())
