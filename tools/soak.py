#!/usr/bin/env python3
"""Soak benchmark (docs/reliability.md, "Soak"): a long stream through `asynevo run`, made by playing a
short sequence back to back (`--repeat`), with the process's resident memory sampled once a second and
the per-update time read from timing.csv. Memory and update time must stay flat: the tool reports the
slope of each over time and the ratio of the last tenth's median to the second tenth's (the first
tenth is start-up and is left out of both); for the update time also issue 23's figure, the 95th
percentile of the last tenth over that of the first.

  /usr/bin/python3 tools/soak.py --dataset SEQ --repeat 180 --out soak-out     # 30 min of event time

This is a benchmark, not a test: it prints figures and writes OUT/soak.json and OUT/soak.png; it exits
non-zero only when the run itself fails.
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import time

import numpy as np


def rss_mib(pid):
    """Resident set size of a live process in MiB (from /proc), None once it is gone."""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def trend(t, y):
    """(slope per unit of t, last-tenth median / second-tenth median) of a series after its first tenth
    (start-up: loading, the first map); None when too short."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    k = len(y) // 10
    if k < 2 or t[-1] <= t[k]:
        return None, None
    slope = float(np.polyfit(t[k:], y[k:], 1)[0])
    first, last = float(np.median(y[k:2 * k])), float(np.median(y[-k:]))
    return slope, (last / first if first > 0 else None)


def p95_ratio(y):
    """Issue 23's figure: the 95th percentile of the last tenth over that of the first tenth (start-up
    included); None when too short."""
    y = np.asarray(y, dtype=float)
    k = len(y) // 10
    if k < 2:
        return None
    first = float(np.percentile(y[:k], 95))
    return float(np.percentile(y[-k:], 95)) / first if first > 0 else None


def read_timing(path):
    """Event time (s) and total update time (ms) of every row of a run's timing.csv."""
    t, total = [], []
    with open(path) as f:
        for row in csv.DictReader(f):
            t.append(float(row["t_s"]))
            total.append(float(row["total_ms"]))
    return np.array(t), np.array(total)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--asynevo", default="build/bin/asynevo")
    p.add_argument("--dataset", required=True, help="a sequence folder (e.g. from asynevo simulate)")
    p.add_argument("--repeat", type=int, default=180, help="passes of the sequence (180 x 10 s = 30 min)")
    p.add_argument("--config", default="", help="configuration YAML for the run")
    p.add_argument("--out", required=True, help="folder for the run folder, soak.json and soak.png")
    p.add_argument("--sample-s", type=float, default=1.0, help="memory sampling period (s of wall time)")
    args = p.parse_args()

    os.makedirs(args.out, exist_ok=True)
    run_dir = os.path.join(args.out, "run")
    cmd = [args.asynevo, "run", "--dataset", args.dataset, "--repeat", str(args.repeat), "--out", run_dir]
    if args.config:
        cmd += ["--config", args.config]
    log_path = os.path.join(args.out, "run.log")
    wall, rss = [], []
    t0 = time.monotonic()
    with open(log_path, "w") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
        while proc.poll() is None:
            m = rss_mib(proc.pid)
            if m is not None:
                wall.append(time.monotonic() - t0)
                rss.append(m)
            time.sleep(args.sample_s)
    if proc.returncode != 0:
        print("soak: the run failed (exit %d); see %s" % (proc.returncode, log_path), file=sys.stderr)
        return 1
    t_ev, total_ms = read_timing(os.path.join(run_dir, "timing.csv"))
    with open(os.path.join(run_dir, "stats.json")) as f:
        stats = json.load(f)
    rss_slope, rss_ratio = trend(wall, rss)
    upd_slope, upd_ratio = trend(t_ev, total_ms)
    result = dict(
        command=cmd, wall_s=round(time.monotonic() - t0, 1), event_time_s=stats.get("event_time_span_s"),
        events=stats.get("events"), updates=len(total_ms), segments=stats.get("segments"),
        rss_mib=dict(first=rss[0] if rss else None, last=rss[-1] if rss else None, max=max(rss) if rss else None,
                     slope_per_min=rss_slope * 60 if rss_slope is not None else None, last_first_ratio=rss_ratio),
        update_ms=dict(median=float(np.median(total_ms)) if len(total_ms) else None,
                       p95=float(np.percentile(total_ms, 95)) if len(total_ms) else None,
                       slope_per_min_of_event_time=upd_slope * 60 if upd_slope is not None else None,
                       last_first_ratio=upd_ratio, p95_last_over_first_tenth=p95_ratio(total_ms)),
    )  # fmt: skip
    with open(os.path.join(args.out, "soak.json"), "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, (a, b) = plt.subplots(2, 1, figsize=(8, 6))
        a.plot(np.array(wall) / 60, rss)
        a.set_xlabel("wall time (min)")
        a.set_ylabel("resident memory (MiB)")
        b.plot(t_ev / 60, total_ms, ",", alpha=0.5)
        b.set_xlabel("event time (min)")
        b.set_ylabel("update time (ms)")
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "soak.png"), dpi=100)
    except ImportError:
        pass
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
