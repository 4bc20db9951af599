#!/usr/bin/python3
"""Writes config/sensors/NAME.yaml for each simulated sensor preset (davis240c, davis346, dvxplorer,
gen4): config/sim.yaml, the defaults the evaluation matrix measures, with that sensor's size. The
matrix runs config/sim.yaml sized to each sequence's sensor in the same way (tools/matrix_run.py,
config_for), so each file holds the settings measured on that sensor's rows of the matrix.

  sensor_configs.py [--check]

--check writes nothing and exits 1, naming the file, when a committed file differs from what this
script would write (run it again after a change of config/sim.yaml). Standard library only.
"""

import argparse
import os
import re
import sys

import config_text

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The presets of `asynevo simulate --sensor` (src/sim/sensor.cpp): name, size, what it stands for.
# The matrix's sequences of each sensor are named PREFIX-SCENE-MOTION-HALF (workflow/matrix.yaml).
SENSORS = [
    ("davis240c", 240, 180, "a DAVIS240C", "d240"),
    ("davis346", 346, 260, "a DAVIS346", "d346"),
    ("dvxplorer", 640, 480, "a DVXplorer", "dvx"),
    ("gen4", 1280, 720, "a Prophesee Gen4", "gen4"),
]


def sensor_config(sim_text, name, width, height, what, prefix):
    """config/sim.yaml's text for one sensor: its own header, the sensor block set to its size."""
    body = sim_text[re.search(r"^sensor:", sim_text, re.MULTILINE).start():]
    body = config_text.override_yaml(body, ["sensor.width=%d" % width, "sensor.height=%d" % height], "config/sim.yaml")
    header = (
        "# AsynEVO configuration for %s (%dx%d): the defaults of config/sim.yaml with this sensor\n"
        "# size, as the evaluation matrix measures them on its %s-* sequences (docs/evaluation_matrix.md).\n"
        "# Written by tools/sensor_configs.py from config/sim.yaml: edit that file, then run the script.\n"
        "#   asynevo run --dataset SEQ --config config/sensors/%s.yaml --out RUN\n"
        "# Every parameter is listed with its meaning; a value left out keeps its default in code.\n\n"
        % (what, width, height, prefix, name))
    return header + body


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--check", action="store_true", help="compare with the committed files, write nothing")
    args = p.parse_args()
    with open(os.path.join(ROOT, "config", "sim.yaml")) as f:
        sim_text = f.read()
    out_dir = os.path.join(ROOT, "config", "sensors")
    stale = []
    for name, width, height, what, prefix in SENSORS:
        path = os.path.join(out_dir, name + ".yaml")
        text = sensor_config(sim_text, name, width, height, what, prefix)
        if args.check:
            try:
                with open(path) as f:
                    if f.read() == text:
                        continue
            except OSError:
                pass
            stale.append(path)
            continue
        os.makedirs(out_dir, exist_ok=True)
        with open(path, "w") as f:
            f.write(text)
        print("wrote %s" % os.path.relpath(path, ROOT))
    for path in stale:
        print("error: %s differs from config/sim.yaml sized for its sensor; run tools/sensor_configs.py"
              % os.path.relpath(path, ROOT), file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
