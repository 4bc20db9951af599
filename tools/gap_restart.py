#!/usr/bin/python3
"""How soon the estimator starts again after a gap in the events, on the evaluation matrix's sequences.

For each sequence folder, the events of [t_gap, t_gap + gap) are removed (t_gap: the middle of the
ground truth's time span unless --at says otherwise), `asynevo run` runs on the rest with the given
configuration, and stats.json's segments say when the estimator was initialized again: the restart
delay is that time minus the end of the gap. The initialization issue's target is 0.5 s
(docs/method/tracking_loss.md).

  gap_restart.py --asynevo BIN --config config/sim.yaml --out DIR SEQ_DIR [SEQ_DIR ...]
      [--gap-ms 400] [--at S] [--jobs 2] [--keep-events]

Writes DIR/NAME/ (the gapped sequence without its events unless --keep-events, and its run folder) and
DIR/gap_restart.json; prints a table.
The sequences must hold events.aevt (the matrix's simulated sequences do; format:
docs/reference/formats.md#aevt-version-1).
"""

import argparse
import concurrent.futures
import json
import os
import shutil
import statistics
import subprocess
import sys

import numpy as np

import matrix_run  # the sensor-sized configuration, as the matrix's runs use it

AEVT_HEADER = 64
AEVT_RECORD = np.dtype([("t", "<i8"), ("x", "<u2"), ("y", "<u2"), ("p", "i1"), ("pad", "V3")])
TARGET_S = 0.5


def cut_aevt(src, dst, t0_ns, t1_ns):
    """Copies the .aevt file `src` to `dst` without the events of [t0_ns, t1_ns); returns how many were
    removed. The header's count and time span are rewritten; the records stay byte for byte."""
    with open(src, "rb") as f:
        header = bytearray(f.read(AEVT_HEADER))
    if header[:8] != b"ASYNEVOE" or int.from_bytes(header[20:24], "little") != AEVT_RECORD.itemsize:
        raise ValueError(f"{src}: not a version 1 .aevt file with 16-byte records")
    events = np.memmap(src, dtype=AEVT_RECORD, mode="r", offset=AEVT_HEADER)
    keep = (events["t"] < t0_ns) | (events["t"] >= t1_ns)
    kept = events[keep]
    if len(kept) == 0:
        raise ValueError(f"{src}: no event outside [{t0_ns}, {t1_ns}) ns")
    header[24:32] = int(len(kept)).to_bytes(8, "little")
    header[32:40] = int(kept["t"][0]).to_bytes(8, "little", signed=True)
    header[40:48] = int(kept["t"][-1]).to_bytes(8, "little", signed=True)
    with open(dst, "wb") as f:
        f.write(bytes(header))
        kept.tofile(f)
    return int(len(events) - len(kept))


def ground_truth_span(seq_dir):
    t = np.loadtxt(os.path.join(seq_dir, "groundtruth.txt"), usecols=0, comments="#", ndmin=1)
    return float(t[0]), float(t[-1])


def restart_after(stats, gap_start_s, gap_end_s):
    """(delay s or None, how the segment before the gap ended) from stats.json: the first segment
    initialized after the gap (its first knots may lie inside the gap: a start fits knots over the span
    of tracks it used), and the last one initialized before it."""
    segments = stats.get("estimator", {}).get("segments", [])
    before = [s for s in segments if s["initialized_at_s"] < gap_start_s]
    after = [s for s in segments if s["initialized_at_s"] >= gap_end_s]
    ended_by = before[-1]["ended_by"] if before else None
    if not after:
        return None, ended_by
    return after[0]["initialized_at_s"] - gap_end_s, ended_by


def run_one(args, seq_dir):
    name = os.path.basename(os.path.normpath(seq_dir))
    work = os.path.join(args.out, name)
    data = os.path.join(work, "sequence")
    run_dir = os.path.join(work, "run")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(data)
    for f in os.listdir(seq_dir):
        if f != "events.aevt" and not f.startswith(".") and os.path.isfile(os.path.join(seq_dir, f)):
            shutil.copy(os.path.join(seq_dir, f), data)
    t_begin, t_end = ground_truth_span(seq_dir)
    gap_start = args.at if args.at is not None else 0.5 * (t_begin + t_end)
    gap_end = gap_start + args.gap_ms * 1e-3
    removed = cut_aevt(os.path.join(seq_dir, "events.aevt"), os.path.join(data, "events.aevt"),
                       round(gap_start * 1e9), round(gap_end * 1e9))
    config = matrix_run.config_for(args.config, seq_dir, work)
    cmd = [args.asynevo, "run", "--dataset", data, "--config", config, "--out", run_dir]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if not args.keep_events:  # a gapped copy of a large sensor's events takes gigabytes
        os.remove(os.path.join(data, "events.aevt"))
    record = {"sequence": name, "gap_start_s": gap_start, "gap_end_s": gap_end, "events_removed": removed,
              "exit_code": proc.returncode}
    if proc.returncode != 0:
        record["message"] = (proc.stderr or proc.stdout).strip().splitlines()[-1:]
        return record
    with open(os.path.join(run_dir, "stats.json")) as f:
        stats = json.load(f)
    delay, ended_by = restart_after(stats, gap_start, gap_end)
    record.update({"restart_s": delay, "ended_by": ended_by,
                   "segments": len(stats.get("estimator", {}).get("segments", []))})
    return record


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--asynevo", required=True)
    p.add_argument("--config", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--gap-ms", type=float, default=400.0)
    p.add_argument("--at", type=float, default=None, help="gap start in seconds (default: mid ground truth)")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--keep-events", action="store_true", help="keep each gapped events.aevt after its run")
    p.add_argument("sequences", nargs="+")
    args = p.parse_args(argv)
    for path in [args.asynevo, args.config] + args.sequences:
        if not os.path.exists(path):
            p.error(f"{path}: no such file or folder")
    os.makedirs(args.out, exist_ok=True)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(args.jobs, 1)) as pool:
        records = list(pool.map(lambda s: run_one(args, s), args.sequences))
    delays = [r["restart_s"] for r in records if r.get("restart_s") is not None]
    missing = [r["sequence"] for r in records if r.get("restart_s") is None]
    print(f"{'sequence':32s} {'gap s':>12s} {'ended by':>14s} {'restart s':>10s}")
    for r in records:
        gap = f"{r['gap_start_s']:.2f}-{r['gap_end_s']:.2f}"
        restart = "never" if r.get("restart_s") is None else f"{r['restart_s']:.3f}"
        if r["exit_code"] != 0:
            restart = f"exit {r['exit_code']}"
        print(f"{r['sequence']:32s} {gap:>12s} {str(r.get('ended_by')):>14s} {restart:>10s}")
    summary = {"gap_ms": args.gap_ms, "sequences": len(records), "restarted": len(delays),
               "within_target": sum(d <= TARGET_S for d in delays), "target_s": TARGET_S,
               "median_s": statistics.median(delays) if delays else None,
               "worst_s": max(delays) if delays else None, "never_restarted": missing}
    print(f"restarted {summary['restarted']} of {len(records)}; within {TARGET_S} s: {summary['within_target']}; "
          f"median {summary['median_s']}, worst {summary['worst_s']}")
    with open(os.path.join(args.out, "gap_restart.json"), "w") as f:
        json.dump({"summary": summary, "runs": records}, f, indent=1)
    return 0 if all(r["exit_code"] == 0 for r in records) else 1


if __name__ == "__main__":
    sys.exit(main())
