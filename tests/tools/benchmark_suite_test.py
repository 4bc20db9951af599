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

REPO_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO_DIR, "tools"))

import numpy as np  # noqa: E402

import benchmark_suite as bs  # noqa: E402

FAILURES = []


def check(cond, what):
    print(("ok      " if cond else "FAILED  ") + what, flush=True)
    if not cond:
        FAILURES.append(what)


# ----------------------------------------------------------------------------- units


def rot_to_quat(R):
    """x y z w quaternions of rotation matrices (n,3,3) (for trace > -1, enough here)."""
    w = np.sqrt(np.maximum(1 + np.trace(R, axis1=1, axis2=2), 1e-12)) / 2
    x = (R[:, 2, 1] - R[:, 1, 2]) / (4 * w)
    y = (R[:, 0, 2] - R[:, 2, 0]) / (4 * w)
    z = (R[:, 1, 0] - R[:, 0, 1]) / (4 * w)
    return np.stack([x, y, z, w], axis=1)


def exp_so3(phi):
    th = np.linalg.norm(phi, axis=1)
    K = np.zeros((len(phi), 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -phi[:, 2], phi[:, 1], -phi[:, 0]
    K[:, 1, 0], K[:, 2, 0], K[:, 2, 1] = phi[:, 2], -phi[:, 1], phi[:, 0]
    a = np.where(th > 1e-9, np.sin(th) / np.maximum(th, 1e-12), 1.0)[:, None, None]
    b = np.where(th > 1e-9, (1 - np.cos(th)) / np.maximum(th, 1e-12) ** 2, 0.5)[:, None, None]
    return np.eye(3)[None] + a * K + b * K @ K


def synthetic_run(folder, scale, v_gain=1.0, w_bias=0.0):
    """A 1 kHz ground truth (constant body rate, smooth translation) and knot velocities at 50 ms,
    the linear part divided by `scale` (a map in other units) and multiplied by v_gain."""
    omega = np.array([0.2, -0.3, 0.5])
    t = np.arange(0, 4.0005, 0.001)
    p = np.stack([np.sin(t), 0.5 * np.cos(2 * t), 0.1 * t], axis=1)
    R = exp_so3(t[:, None] * omega[None])
    with open(os.path.join(folder, "stamped_groundtruth.txt"), "w") as f:
        for ti, pi, qi in zip(t, p, rot_to_quat(R)):
            f.write("%.9f %s %s\n" % (ti, " ".join("%.12g" % v for v in pi), " ".join("%.12g" % v for v in qi)))
    tk = np.arange(0.1, 3.9, 0.05)
    dp = np.stack([np.cos(tk), -np.sin(2 * tk), 0.1 * np.ones_like(tk)], axis=1)
    Rk = exp_so3(tk[:, None] * omega[None])
    v_b = np.einsum("nji,nj->ni", Rk, dp)
    with open(os.path.join(folder, "velocities.txt"), "w") as f:
        for ti, vi in zip(tk, v_b):
            vals = list(vi * v_gain / scale) + list(omega + w_bias)
            f.write("%.9f %s\n" % (ti, " ".join("%.12g" % v for v in vals)))
    return np.linalg.norm(v_b, axis=1)


def units():
    with tempfile.TemporaryDirectory(prefix="benchmark_suite_test_") as d:
        speeds = synthetic_run(d, scale=2.5)
        v = bs.velocity_errors(d, 2.5)
        check(v["vel_rmse_mps"] < 1e-4, "exact velocities (map scale 1/2.5) give ~0 RMSE: %.2e m/s" % v["vel_rmse_mps"])
        check(v["omega_rmse_dps"] < 1e-3, "exact angular velocity gives ~0 RMSE: %.2e deg/s" % v["omega_rmse_dps"])
        check(abs(v["mean_speed_mps"] - speeds.mean()) < 1e-4, "mean speed is the ground truth's")
        check(v["velocity_samples"] == len(speeds), "every knot inside the ground-truth span is used")

        synthetic_run(d, scale=2.5, v_gain=1.1, w_bias=0.01)
        v = bs.velocity_errors(d, 2.5)
        expect = 100 * 0.1 * np.sqrt(np.mean(speeds**2)) / speeds.mean()
        check(abs(v["vel_rmse_perc"] - expect) < 1e-3, "10 %% too fast: %.4f %% vs %.4f %%" % (v["vel_rmse_perc"], expect))
        check(abs(v["omega_rmse_dps"] - np.degrees(0.01 * np.sqrt(3))) < 1e-3, "angular bias shows in the ω RMSE")

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
    if FAILURES:
        print("%d check(s) failed" % len(FAILURES))
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
