#!/usr/bin/python3
"""Tests of tools/benchmark_suite.py (registered with ctest in tests/tools/CMakeLists.txt).

  benchmark_suite_test.py units                          metric and report helpers, synthetic data
  benchmark_suite_test.py smoke --asynevo BIN --work DIR  a 3 s end-to-end run of the suite
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tool_checks import REPO_DIR, check, exit_code  # noqa: E402

import numpy as np  # noqa: E402

import benchmark_suite as bs  # noqa: E402


# ----------------------------------------------------------------------------- units


def units():
    # the velocity error is asynevo eval's (tests/eval/velocity_errors_test.cpp); the suite reads it
    ev = dict(velocity=dict(samples=70, linear_mps=dict(rmse=0.05, mean=0.04, num_samples=70),
                            angular_dps=dict(rmse=2.0, num_samples=70), mean_gt_speed_mps=0.5,
                            mean_gt_rate_dps=40.0, linear_rmse_perc_of_mean_speed=10.0,
                            angular_rmse_perc_of_mean_rate=5.0))  # fmt: skip
    v = bs.velocity_summary(ev)
    check(v == dict(velocity_samples=70, vel_rmse_mps=0.05, mean_speed_mps=0.5, vel_rmse_perc=10.0,
                    omega_rmse_dps=2.0, omega_rmse_perc=5.0), "velocity read from eval.json: %s" % v)  # fmt: skip
    check("velocity_error" in bs.velocity_summary({}) and "vel_rmse_perc" not in bs.velocity_summary({}),
          "an eval.json without velocity says so")  # fmt: skip
    ev["velocity"]["samples"] = 0
    check(bs.velocity_summary(ev).get("velocity_samples") == 0 and "vel_rmse_perc" not in bs.velocity_summary(ev),
          "no velocity sample gives no error figure")  # fmt: skip

    with tempfile.TemporaryDirectory(prefix="benchmark_suite_test_") as d:
        path = os.path.join(d, "timing.csv")
        with open(path, "w") as f:
            f.write("t_s,window_knots,total_ms\n0.05,3,10.5\n0.10,4,12.5\n0.15,4")  # killed mid-line
        tm = bs.load_timing(path)
        check(tm is not None and list(tm["total_ms"]) == [10.5, 12.5], "a truncated last timing row is skipped")

    q = bs.quarter_medians(np.arange(8.0), np.array([1, 1, 2, 2, 3, 3, 4, 4.0]))
    check(q == [1.0, 2.0, 3.0, 4.0], "quarter medians %s" % q)

    seqs = [dict(name="s", scene="boxes", motion="6dof", duration_s=3, seed=1)]
    ok = dict(sequence="s", backend="window", status="ok", message="",
              timing=dict(t_s=np.arange(4.0), total_ms=np.array([10, 20, 30, 40.0]), window_knots=np.ones(4)),
              summary=dict(updates=4, update_median_ms=25.0, quarter_median_ms=[10.0, 20.0, 30.0, 40.0],
                           backend_total_s=0.1, ate_perc=0.5, rte10_perc=3.0, vel_rmse_perc=5.0,
                           real_time_factor=1.5, rte=[dict(trans_perc_mean=3.0)]))  # fmt: skip
    bad = dict(sequence="s", backend="incremental", status="failed", timing=None, summary={},
               message="initialization never succeeded after 3 attempt(s): too few features")  # fmt: skip
    acc = bs.accuracy_table(seqs, [ok, bad])
    check("| s | incremental | **failed**: initialization never succeeded" in acc, "a failed run stays in the table")
    tgt = bs.targets_table(seqs, [ok, bad])
    check("met (0.50)" in tgt and "**missed** (3.0)" in tgt and "**missed** (1.50)" in tgt, "targets met/missed")
    ratios, _ = bs.ratio_table(seqs, [ok, bad])
    check("no timing" in ratios, "a baseline without timing is named in the ratio table")

    # a run stopped by --run-timeout: its runtime up to where it stopped, and where that was
    tm = dict(t_s=np.array([0.5, 1.0, 1.5]), total_ms=np.array([50.0, 70.0, 90.0]), window_knots=np.array([10, 20, 30.0]))
    stopped = dict(sequence="s", backend="incremental", status="timeout", timing=tm, stats=None, eval=None,
                   run_dir="/nonexistent", message="stopped after the --run-timeout of 450 s")  # fmt: skip
    stopped["summary"] = bs.summarize_run(stopped, seqs[0])
    stopped["message"] = bs.timeout_message(stopped, seqs[0])
    check(stopped["message"] == "stopped after the --run-timeout of 450 s at event time 1.5 s of the 3 s sequence "
          "(runtime figures cover its 3 updates up to there)", "timeout message: %s" % stopped["message"])  # fmt: skip
    rt = bs.runtime_table(seqs, [ok, stopped])
    check("| s | incremental | timeout at event time 1.5 s | 3 | 70.0 | 88.0 | 90.0 | 0.2 |" in rt,
          "the runtime table has the stopped run's partial runtime")  # fmt: skip
    acc = bs.accuracy_table(seqs, [ok, stopped])
    check("| s | incremental | **timeout**: stopped after the --run-timeout of 450 s at event time 1.5 s" in acc,
          "the accuracy table says where the run was stopped")  # fmt: skip
    early = dict(stopped, timing=None, message="stopped after the --run-timeout of 5 s")
    early["summary"] = bs.summarize_run(early, seqs[0])
    check(bs.timeout_message(early, seqs[0]).endswith("before its first backend update (no timing rows)"),
          "a run stopped before any update says so")  # fmt: skip

    with tempfile.TemporaryDirectory(prefix="benchmark_suite_test_") as d:
        doc = os.path.join(d, "r.md")
        with open(doc, "w") as f:
            f.write("head\n%s\nold\n%s\ntail\n" % (bs.BEGIN_MARKER, bs.END_MARKER))
        bs.update_docs(doc, "new\n")
        with open(doc) as f:
            text = f.read()
        check(text == "head\n%s\nnew\n%s\ntail\n" % (bs.BEGIN_MARKER, bs.END_MARKER), "only the marked section changes")


# ----------------------------------------------------------------------------- smoke


NUMBER_ROW = re.compile(r"^\| boxes_6dof \| (window|incremental-frozen) \| ok \|(.*)$", re.MULTILINE)


def smoke(asynevo, work):
    if os.path.isdir(work):
        shutil.rmtree(work)
    os.makedirs(work)
    docs = os.path.join(work, "docs", "results.md")
    os.makedirs(os.path.dirname(docs))
    with open(docs, "w") as f:
        f.write("# results\n\n%s\nnothing yet\n%s\n\nhand-written text stays\n" % (bs.BEGIN_MARKER, bs.END_MARKER))
    out = os.path.join(work, "out")
    cmd = [sys.executable, os.path.join(REPO_DIR, "tools", "benchmark_suite.py"), "--asynevo", asynevo,
           "--out", out, "--duration", "3", "--sequences", "boxes_6dof",
           "--backends", "window,incremental-frozen", "--docs", docs]  # fmt: skip
    t0 = time.monotonic()
    code = subprocess.call(cmd, cwd=REPO_DIR)
    print("suite: exit %d in %.1f s" % (code, time.monotonic() - t0), flush=True)
    check(code == 0, "benchmark_suite.py exits 0")

    report_path = os.path.join(out, "results.md")
    check(os.path.isfile(report_path), "results.md written")
    report = open(report_path).read() if os.path.isfile(report_path) else ""
    rows = NUMBER_ROW.findall(report)
    # each backend: one accuracy row and one runtime row, both with numbers in every leading cell
    for backend in ("window", "incremental-frozen"):
        mine = [cells for b, cells in rows if b == backend]
        check(len(mine) >= 2, "%s has accuracy and runtime rows (found %d)" % (backend, len(mine)))
        for cells in mine:
            first = [c.strip() for c in cells.split("|")[:4]]
            check(all(re.fullmatch(r"-?[0-9]+(\.[0-9]+)?", c) for c in first), "%s row starts with numbers: %s" % (backend, first))
    check(re.search(r"^\| boxes_6dof \| incremental-frozen \| [0-9.]+ \|", report, re.MULTILINE) is not None,
          "ratio table has a number for the frozen baseline")  # fmt: skip
    check("met (" in report or "missed** (" in report, "targets are marked met/missed")

    results = json.load(open(os.path.join(out, "results.json")))
    status = {r["backend"]: r["status"] for r in results["runs"]}
    check(status == {"window": "ok", "incremental-frozen": "ok"}, "both runs ok: %s" % status)
    for r in results["runs"]:
        check(isinstance(r["summary"].get("vel_rmse_perc"), float), "%s has a velocity error" % r["backend"])

    for name in ("runtime_over_time.png", "runtime_boxplots.png", "window_size.png", "trajectories.png"):
        for folder in (os.path.join(out, "figures"), os.path.join(work, "docs", "images", "results")):
            path = os.path.join(folder, name)
            ok = os.path.isfile(path) and open(path, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
            check(ok and os.path.getsize(path) > 2000, "%s is a PNG" % path)

    text = open(docs).read()
    check("nothing yet" not in text and "hand-written text stays" in text, "docs section replaced, rest kept")
    check("](images/results/runtime_over_time.png)" in text, "docs link the copied figures")

    # a second call reuses the sequence and the runs
    t0 = time.monotonic()
    code = subprocess.call(cmd + ["--skip-existing"], cwd=REPO_DIR)
    check(code == 0 and time.monotonic() - t0 < 30, "--skip-existing reuses everything (%.1f s)" % (time.monotonic() - t0))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("what", choices=["units", "smoke"])
    p.add_argument("--asynevo")
    p.add_argument("--work")
    a = p.parse_args()
    if a.what == "units":
        units()
    else:
        smoke(os.path.abspath(a.asynevo), os.path.abspath(a.work))
    return exit_code()


if __name__ == "__main__":
    sys.exit(main())
