#!/usr/bin/python3
"""A setting's evaluation-matrix result over start offsets (docs/evaluation_matrix.md, "Start offsets").

A single run's ATE depends on when its start happens: 50 ms later can move it by several points. A
setting replayed at a few offsets (workflow key replay_skip_ms, one run folder per offset) is scored per
sequence by the median over its offsets, and per half by the median of those; the spread of the
half's median over the offsets shows how far one draw can be from it.

  matrix_offsets.py NAME=RUNS_DIR[,RUNS_DIR...] [NAME=...] [--metric ate_pct] [--sequences]

Each RUNS_DIR holds SEQ/score.json (matrix-out/runs/SETTING). The first NAME is the reference; the
others are compared with it sequence by sequence. A failed or missing run counts as infinitely bad,
as in the matrix report. Lower is better, except for the metrics in HIGHER_IS_BETTER (coverage), where
a failed run counts as minus infinity. Standard library only.
"""

import argparse
import json
import math
import os
import statistics
import sys

HALVES = (("tune", "tuning"), ("val", "validation"))
HIGHER_IS_BETTER = {"coverage", "coverage_after_onset"}


def read_score(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def metric_of(score, metric):
    """The metric of one run; the worst value (inf, or -inf where higher is better) for a failed, missing
    or unscored run."""
    worst = -math.inf if metric in HIGHER_IS_BETTER else math.inf
    if not score or score.get("status") != "ok":
        return worst
    v = score.get(metric)
    return worst if v is None else float(v)


def load_setting(run_dirs, metric):
    """{sequence: [value per offset]} over the sequences every run folder of the setting has."""
    per_dir = []
    for d in run_dirs:
        seqs = {s for s in os.listdir(d) if os.path.isfile(os.path.join(d, s, "score.json"))} if os.path.isdir(d) else set()
        per_dir.append((d, seqs))
    common = set.intersection(*(s for _, s in per_dir)) if per_dir else set()
    return {s: [metric_of(read_score(os.path.join(d, s, "score.json")), metric) for d, _ in per_dir] for s in common}


def half_of(sequence):
    for suffix, name in HALVES:
        if sequence.endswith("-" + suffix):
            return name
    return "other"


def summarize(values_by_seq):
    """Per half: (runs, median over sequences of the per-sequence median, the half's median at each
    offset)."""
    out = {}
    for half in sorted({half_of(s) for s in values_by_seq}):
        seqs = sorted(s for s in values_by_seq if half_of(s) == half)
        offsets = len(values_by_seq[seqs[0]])
        out[half] = (len(seqs), statistics.median(statistics.median(values_by_seq[s]) for s in seqs),
                     [statistics.median(values_by_seq[s][i] for s in seqs) for i in range(offsets)])
    return out


def fmt(x):
    return "failed" if math.isinf(x) else "%.2f" % x


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("settings", nargs="+", help="NAME=RUNS_DIR[,RUNS_DIR...], one folder per offset")
    p.add_argument("--metric", default="ate_pct", help="score.json key (default ate_pct)")
    p.add_argument("--sequences", action="store_true", help="also print every sequence")
    args = p.parse_args(argv)
    settings = []
    for spec in args.settings:
        name, sep, dirs = spec.partition("=")
        if not sep or not dirs:
            p.error("%s: expected NAME=RUNS_DIR[,RUNS_DIR...]" % spec)
        data = load_setting(dirs.split(","), args.metric)
        if not data:
            p.error("%s: no sequence has a score.json in every folder" % name)
        settings.append((name, data))
    ref_name, ref = settings[0]
    for name, data in settings:
        for half, (runs, med, per_offset) in summarize(data).items():
            print("%-24s %-10s %2d sequences, %d offsets: median %s (per offset %s)"
                  % (name, half, runs, len(per_offset), fmt(med), " ".join(fmt(v) for v in per_offset)))
        if name != ref_name:
            common = sorted(set(data) & set(ref))
            for half in sorted({half_of(s) for s in common}):
                seqs = [s for s in common if half_of(s) == half]
                sign = -1 if args.metric in HIGHER_IS_BETTER else 1
                better = sum(sign * statistics.median(data[s]) < sign * statistics.median(ref[s]) for s in seqs)
                worse = sum(sign * statistics.median(data[s]) > sign * statistics.median(ref[s]) for s in seqs)
                print("%-24s %-10s against %s: %d sequences better, %d worse (per-sequence medians)"
                      % (name, half, ref_name, better, worse))
        if args.sequences:
            for s in sorted(data):
                print("  %-28s %s  median %s" % (s, " ".join(fmt(v) for v in data[s]), fmt(statistics.median(data[s]))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
