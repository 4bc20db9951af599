#!/usr/bin/python3
"""Tests of workflow/baselines.smk, tools/baseline_run.py and tools/benchmark_suite.py (registered
with ctest in tests/tools/CMakeLists.txt).

  benchmark_suite_test.py units                          sequence table, run status, metric and report
                                                         helpers, on synthetic data and a stand-in binary
  benchmark_suite_test.py smoke --asynevo BIN --work DIR  a 3 s end-to-end run of the workflow
"""

import argparse
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

import baseline_run  # noqa: E402
import benchmark_suite as bs  # noqa: E402


# ----------------------------------------------------------------------------- units


def raises(fn, *args):
    """The message of the BaselineError fn(*args) raises, or None."""
    try:
        fn(*args)
    except baseline_run.BaselineError as e:
        return str(e)
    return None


def units_sequence_table():
    table = baseline_run.load_sequences()
    check(baseline_run.select_sequences(table) == ["room_poster", "boxes_6dof", "shapes_translation"],
          "the default set of workflow/baselines.yaml is the issue-7 set")  # fmt: skip
    check(len(table) == 6 and all(s["duration"] == 20.0 for s in table.values()), "six 20 s sequences in the table")
    check(baseline_run.select_sequences(table, "boxes_6dof, poster_6dof,boxes_6dof") == ["boxes_6dof", "poster_6dof"],
          "a comma list selects those sequences, in its order, once each")  # fmt: skip
    msg = raises(baseline_run.select_sequences, table, "boxes_6dof,castle")
    check(msg is not None and "castle" in msg and "boxes_6dof" in msg, "an unknown sequence is named: %s" % msg)
    check(baseline_run.select_backends(None) == baseline_run.BACKENDS, "all three backends by default")
    msg = raises(baseline_run.select_backends, "window,isam2")
    check(msg is not None and "unknown backend(s) isam2" in msg, "an unknown backend is named: %s" % msg)
    args = baseline_run.simulate_args(table["room_poster"], 3)
    check(args == ["--scene", "room", "--motion", os.path.join(REPO_DIR, "tests/data/ecd/poster_6dof_gt/groundtruth.txt"),
                   "--duration", "3", "--seed", "11"], "simulate arguments with a duration override: %s" % args)  # fmt: skip
    check(baseline_run.simulate_args(table["boxes_6dof"])[3:6] == ["6dof", "--duration", "20"],
          "a preset motion and the sequence's own duration")  # fmt: skip

    with tempfile.TemporaryDirectory(prefix="benchmark_suite_test_") as d:
        path = os.path.join(d, "t.yaml")
        for text, expect in (
            ("sequences:\n  a: {scene: boxes, motion: 6dof, seed: 1, duration: 3, default: true, speed: 2}\n",
             "sequence a: unknown key(s) speed"),
            ("sequences:\n  a: {scene: boxes, motion: nowhere/gt.txt, seed: 1, duration: 3, default: true}\n",
             "sequence a: motion file nowhere/gt.txt does not exist"),
            ("sequences:\n  a: {scene: boxes, motion: 6dof, seed: 1, duration: 3}\n", "no sequence is marked"),
            ("sequences:\n  a: {scene: boxes, motion: 6dof, seed: -1, duration: 3, default: true}\n",
             "sequence a: 'seed' must be an integer"),
            ("sequences:\n  a: {scene: boxes, motion: 6dof, duration: 3, default: true}\n",
             "sequence a: missing key(s) seed"),
        ):  # fmt: skip
            with open(path, "w") as f:
                f.write(text)
            msg = raises(baseline_run.load_sequences, path)
            check(msg is not None and path in msg and expect in msg, "bad table entry rejected: %s" % msg)


FAKE_ASYNEVO = """#!/bin/sh
# stand-in for asynevo: the run's behaviour follows the dataset folder's name, eval fails for 'badeval'
cmd=$1; shift
ds=; out=
while [ $# -gt 0 ]; do case "$1" in --dataset) ds=$2; shift;; --out) out=$2; shift;; esac; shift; done
if [ "$cmd" = run ]; then
  case "$ds" in
    *fail*) echo "reading events"; echo "error: initialization never succeeded after 3 attempt(s)"; exit 1;;
    *slow*) printf 't_s,window_knots,total_ms\n0.5,10,50\n1.0,20,70\n1.5,30,90\n' > "$out/timing.csv"; exec sleep 30;;
  esac
  exit 0
fi
case "$out" in *badeval*) echo "error: no estimate poses"; exit 1;; esac
echo '{}' > "$out/eval.json"
"""


def units_run_status():
    """tools/baseline_run.py's status files (with a stand-in binary), and how the report reads them."""
    with tempfile.TemporaryDirectory(prefix="benchmark_suite_test_") as d:
        fake = os.path.join(d, "asynevo")
        with open(fake, "w") as f:
            f.write(FAKE_ASYNEVO)
        os.chmod(fake, 0o755)
        out = os.path.join(d, "out")

        def run(seq, backend, timeout=0):
            seq_dir = os.path.join(out, "sequences", seq)
            os.makedirs(seq_dir, exist_ok=True)
            status = os.path.join(out, "runs", seq, backend + ".json")
            os.makedirs(os.path.dirname(status), exist_ok=True)
            code = baseline_run.main(["--asynevo", fake, "--dataset", seq_dir, "--backend", backend, "--run-dir",
                                      os.path.join(out, "runs", seq, backend), "--status", status,
                                      "--timeout", str(timeout)])  # fmt: skip
            check(code == 0, "baseline_run.py exits 0 for %s/%s" % (seq, backend))
            return bs.read_json(status) or {}

        ok = run("fine", "window")
        check(ok.get("status") == "ok" and ok.get("message") == "" and "--backend window" in " ".join(ok.get("command", [])),
              "a finished run is ok, run with --backend: %s" % ok.get("command"))  # fmt: skip
        check(os.path.isfile(os.path.join(out, "runs", "fine", "window", "eval.json")), "the run was evaluated")
        failed = run("fail", "incremental")
        check(failed.get("status") == "failed" and failed.get("message") == "error: initialization never succeeded "
              "after 3 attempt(s)", "a failed run keeps the line that says why: %s" % failed.get("message"))  # fmt: skip
        check(os.path.isfile(os.path.join(out, "runs", "fail", "incremental", "run.log")), "the run's output is in run.log")
        badeval = run("badeval", "window")
        check(badeval.get("status") == "failed" and badeval.get("message") == "evaluation failed: error: no estimate poses",
              "a failed evaluation fails the run: %s" % badeval.get("message"))  # fmt: skip
        t0 = time.monotonic()
        stopped = run("slow", "incremental", timeout=1)
        check(stopped.get("status") == "timeout" and stopped.get("run_timeout_s") == 1 and time.monotonic() - t0 < 15,
              "a run past its time limit is stopped and marked timeout: %s" % stopped.get("message"))  # fmt: skip

        # the report's view of the same folders
        seq_dir = os.path.join(out, "sequences", "slow")
        with open(os.path.join(seq_dir, "sim.yaml"), "w") as f:
            f.write("scene: \"boxes\"\nbegin_s: 0.000000000\nend_s: 3.000000000\nstats:\n  events: 2331804\n")
        with open(os.path.join(seq_dir, "groundtruth.txt"), "w") as f:
            f.write("# t x y z qx qy qz qw\n0 0 0 0 0 0 0 1\n1 3 4 0 0 0 0 1\n2 3 4 1 0 0 0 1\n")
        os.makedirs(os.path.join(out, "logs", "simulate"))
        with open(os.path.join(out, "logs", "simulate", "slow.benchmark.tsv"), "w") as f:
            f.write("s\th:m:s\tmax_rss\n9.8765\t0:00:09\t100\n")
        spec = dict(scene="boxes", motion="6dof", seed=12, duration=20.0, about="boxes scene, 6dof preset")
        seq = bs.sequence_info(out, "slow", spec)
        check(seq["duration_s"] == 3.0 and seq["events"] == 2331804 and seq["gt_path_length_m"] == 6.0
              and seq["simulate_wall_s"] == 9.9, "sequence read from its folder: %s" % seq)  # fmt: skip
        rec = bs.load_run(out, seq, "incremental")
        check(rec["message"] == "stopped after the time limit of 1 s (run_timeout_s) at event time 1.5 s of the 3 s "
              "sequence (runtime figures cover its 3 updates up to there)", "report's timeout message: %s" % rec["message"])  # fmt: skip
        check(bs.load_run(out, seq, "window") is None, "a run without a status file is None")
        check(bs.runs_made([rec, dict(started="2026-01-01 10:00")]) == "2026-01-01 10:00 – " + rec["started"],
              "the runs' dates span %s" % bs.runs_made([rec, dict(started="2026-01-01 10:00")]))  # fmt: skip


def units():
    units_sequence_table()
    units_run_status()

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

    # a run stopped by the workflow's run_timeout_s: its runtime up to where it stopped, and where that was
    tm = dict(t_s=np.array([0.5, 1.0, 1.5]), total_ms=np.array([50.0, 70.0, 90.0]), window_knots=np.array([10, 20, 30.0]))
    stopped = dict(sequence="s", backend="incremental", status="timeout", timing=tm, stats=None, eval=None,
                   run_dir="/nonexistent", message="stopped after the time limit of 450 s (run_timeout_s)")  # fmt: skip
    stopped["summary"] = bs.summarize_run(stopped, seqs[0])
    stopped["message"] = bs.timeout_message(stopped, seqs[0])
    check(stopped["message"] == "stopped after the time limit of 450 s (run_timeout_s) at event time 1.5 s of the 3 s sequence "
          "(runtime figures cover its 3 updates up to there)", "timeout message: %s" % stopped["message"])  # fmt: skip
    rt = bs.runtime_table(seqs, [ok, stopped])
    check("| s | incremental | timeout at event time 1.5 s | 3 | 70.0 | 88.0 | 90.0 | 0.2 |" in rt,
          "the runtime table has the stopped run's partial runtime")  # fmt: skip
    acc = bs.accuracy_table(seqs, [ok, stopped])
    check("| s | incremental | **timeout**: stopped after the time limit of 450 s (run_timeout_s) at event time 1.5 s" in acc,
          "the accuracy table says where the run was stopped")  # fmt: skip
    early = dict(stopped, timing=None, message="stopped after the time limit of 5 s (run_timeout_s)")
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
    snakemake = shutil.which("snakemake")
    check(snakemake is not None, "snakemake is installed (Debian package snakemake)")
    if snakemake is None:
        return
    docs = os.path.join(work, "docs", "results.md")
    os.makedirs(os.path.dirname(docs))
    with open(docs, "w") as f:
        f.write("# results\n\n%s\nnothing yet\n%s\n\nhand-written text stays\n" % (bs.BEGIN_MARKER, bs.END_MARKER))
    out = os.path.join(work, "out")
    base = [snakemake, "-s", os.path.join(REPO_DIR, "workflow", "baselines.smk"), "--cores", "2", "--quiet", "--nolock"]
    config = ["asynevo=" + asynevo, "out=" + out, "sequences=boxes_6dof", "backends=window,incremental-frozen",
              "duration=3", "docs=" + docs]  # fmt: skip

    # unknown names stop the workflow before anything runs, named
    bad = subprocess.run(base + ["--config"] + [c for c in config if not c.startswith(("sequences=", "backends="))]
                         + ["sequences=boxes_6dof,castle", "backends=window,isam2"], capture_output=True, text=True)  # fmt: skip
    said = bad.stdout + bad.stderr
    named = bad.returncode != 0 and "unknown sequence(s) castle" in said and "unknown backend(s) isam2" in said
    check(named, "unknown sequence and backend names stop the workflow, named" + ("" if named else " (%s)" % said.strip()[-300:]))
    check(not os.path.exists(out), "nothing ran for the bad names")

    t0 = time.monotonic()
    r = subprocess.run(base + ["--config"] + config, cwd=REPO_DIR, capture_output=True, text=True)
    print("workflow: exit %d in %.1f s" % (r.returncode, time.monotonic() - t0), flush=True)
    check(r.returncode == 0, "snakemake -s workflow/baselines.smk exits 0" + ("" if r.returncode == 0 else " (%s)" % (r.stdout + r.stderr).strip()[-600:]))

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
    check("| boxes_6dof | boxes | 6dof | 3 | 12 |" in report, "the sequence table has the 3 s simulation")
    check("snakemake -s workflow/baselines.smk --cores 2 --config" in report and "sequences=boxes_6dof" in report,
          "the report names the workflow command")  # fmt: skip

    results = bs.read_json(os.path.join(out, "results.json")) or {"runs": []}
    status = {r["backend"]: r["status"] for r in results["runs"]}
    check(status == {"window": "ok", "incremental-frozen": "ok"}, "both runs ok: %s" % status)
    for r in results["runs"]:
        check(isinstance(r["summary"].get("vel_rmse_perc"), float), "%s has a velocity error" % r["backend"])
        cmd = r.get("command", [])
        check("--backend" in cmd and cmd[cmd.index("--backend") + 1] == r["backend"], "%s was run with --backend %s" % (r["backend"], r["backend"]))
    for backend in ("window", "incremental-frozen"):
        run_dir = os.path.join(out, "runs", "boxes_6dof", backend)
        check(all(os.path.isfile(os.path.join(run_dir, f)) for f in ("eval.json", "timing.csv", "run.log")),
              "%s is a run folder with eval.json, timing.csv and run.log" % run_dir)  # fmt: skip

    for name in ("runtime_over_time.png", "runtime_boxplots.png", "window_size.png", "trajectories.png"):
        for folder in (os.path.join(out, "figures"), os.path.join(work, "docs", "images", "results")):
            path = os.path.join(folder, name)
            ok = os.path.isfile(path) and open(path, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
            check(ok and os.path.getsize(path) > 2000, "%s is a PNG" % path)

    text = open(docs).read()
    check("nothing yet" not in text and "hand-written text stays" in text, "docs section replaced, rest kept")
    check("](images/results/runtime_over_time.png)" in text, "docs link the copied figures")

    # a second invocation has nothing to do (file-based rules)
    again = subprocess.run(base + ["-n", "--config"] + config, capture_output=True, text=True)
    check(again.returncode == 0 and "Nothing to be done" in (again.stdout + again.stderr), "a finished workflow is not rerun")
    # the report step alone redraws from the run folders
    t0 = time.monotonic()
    code = subprocess.call([sys.executable, os.path.join(REPO_DIR, "tools", "benchmark_suite.py"), "--out", out,
                            "--sequences", "boxes_6dof", "--backends", "window,incremental-frozen"])  # fmt: skip
    check(code == 0 and time.monotonic() - t0 < 60, "benchmark_suite.py alone redraws the report (%.1f s)" % (time.monotonic() - t0))


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
