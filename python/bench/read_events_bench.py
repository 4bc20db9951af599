#!/usr/bin/python3
"""Cost of moving events between the C++ readers and numpy (asynevo.read_events, asynevo.check_events).

Prints, for one event file (any supported format):
  read_events   wall time, the reader's own time (parse_s) and the time spent copying its packets into
                the numpy arrays (convert_s: the conversion cost, file parsing excluded)
  check_events  numpy arrays -> C++ events with every check run() and Stream.push() make
A benchmark, not a test: it prints figures and fails only when something does not work.

Without --events it makes a file of about 10 M events: the CLI simulates the boxes scene with the 6dof
motion (--duration, default 12 s) and converts it to .aevt, the fastest format to parse, into --work.

Usage: PYTHONPATH=build/python /usr/bin/python3 python/bench/read_events_bench.py [--events FILE]
         [--asynevo build/bin/asynevo] [--work /tmp/asynevo-read-bench] [--repeat 3]
"""

import argparse
import os
import subprocess
import sys
import time

import numpy as np

import asynevo


def make_events(asynevo_bin, work, duration):
    path = os.path.join(work, "events.aevt")
    if os.path.exists(path):
        return path
    seq = os.path.join(work, "sequence")
    subprocess.run([asynevo_bin, "simulate", "--scene", "boxes", "--motion", "6dof", "--duration", str(duration),
                    "--seed", "1", "--out", seq], check=True, stdout=subprocess.DEVNULL)
    subprocess.run([asynevo_bin, "convert", "--dataset", seq, "--out", path], check=True, stdout=subprocess.DEVNULL)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--events", help="event file or dataset folder (default: simulate one)")
    ap.add_argument("--asynevo", default="build/bin/asynevo", help="the CLI, to simulate and convert")
    ap.add_argument("--work", default="/tmp/asynevo-read-bench", help="where the simulated file goes")
    ap.add_argument("--duration", type=float, default=12.0, help="simulated seconds (12 s: ~10 M events)")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each measurement (the best is kept)")
    args = ap.parse_args()

    if args.events:
        path = args.events
    else:
        os.makedirs(args.work, exist_ok=True)
        path = make_events(args.asynevo, args.work, args.duration)

    best = None
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        ev = asynevo.read_events(path)
        wall = time.perf_counter() - t0
        if best is None or wall < best[0]:
            best = (wall, ev["stats"]["parse_s"], ev["stats"]["convert_s"])
        n = len(ev["t"])
        del ev
    wall, parse_s, convert_s = best
    ev = asynevo.read_events(path)
    n = len(ev["t"])
    print(f"file          {path} ({ev['format']}, {ev['width']}x{ev['height']}), {n} events, "
          f"{os.path.getsize(path) / 1e6:.0f} MB")
    print(f"read_events   {wall:.3f} s wall ({n / wall / 1e6:.1f} M events/s): reader {parse_s:.3f} s, "
          f"copy into numpy {convert_s:.3f} s ({convert_s / n * 1e9:.2f} ns/event, "
          f"{convert_s * 1e7 / n:.3f} s per 10 M events)")

    checks = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        asynevo.check_events(ev["t"], ev["x"], ev["y"], ev["p"], ev["width"], ev["height"])
        checks.append(time.perf_counter() - t0)
    check = min(checks)
    print(f"check_events  {check:.3f} s ({check / n * 1e9:.2f} ns/event, {check * 1e7 / n:.3f} s per 10 M events): "
          "numpy -> C++ events with all checks")
    t = ev["t"].astype(np.int64)
    x, y, p = ev["x"].astype(np.int32), ev["y"].astype(np.int32), ev["p"] > 0
    t0 = time.perf_counter()
    asynevo.check_events(t, x, y, p, ev["width"], ev["height"])
    other = time.perf_counter() - t0
    print(f"check_events  {other:.3f} s with int32 pixels and bool polarities (other dtypes, no conversion copy)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
