#!/usr/bin/python3
"""Tests of the evaluation matrix's tools (tools/matrix.py, matrix_run.py, matrix_report.py) and of the
Snakemake workflow (workflow/Snakefile).

  matrix_test.py units                                  checks on synthetic data (~2 s, no binary)
  matrix_test.py smoke --asynevo BIN --work DIR         dry run of the whole matrix, then one 2 s
                                                        sequence through simulate -> run -> report
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tool_checks import REPO_DIR, check, exit_code  # noqa: E402

import numpy as np  # noqa: E402

import matrix as matrix_lib  # noqa: E402
import matrix_report  # noqa: E402
import matrix_run  # noqa: E402

GOOD_CELL = "{name: c1, sensor: davis240c, noise: low, scene: boxes, motion: m6, variants: [{seed: 1}, {seed: 2, start: 3}]}"
HEADER = """duration_s: 10
sensors: [davis240c, davis346]
noise_levels: [low, high]
scenes: {boxes: boxes, shapes: planar}
motions:
  m6: {preset: 6dof, kind: preset}
  mocap: {file: tests/data/ecd/poster_6dof_gt/groundtruth.txt, kind: mocap}
cells:
"""


def write_matrix(folder, cells, header=HEADER):
    path = os.path.join(folder, "m.yaml")
    with open(path, "w") as f:
        f.write(header + "".join("  - %s\n" % c for c in cells))
    return path


def load_error(folder, cells, header=HEADER):
    try:
        matrix_lib.load(write_matrix(folder, cells, header))
    except matrix_lib.MatrixError as e:
        return str(e)
    return None


def units():
    tmp = tempfile.mkdtemp(prefix="matrix_units_")
    # the repository's matrix: at least 36 sequences, both halves the same cells
    m = matrix_lib.load()
    tune, val = matrix_lib.select(m, "tuning"), matrix_lib.select(m, "validation")
    check(len(m["sequences"]) >= 36, "workflow/matrix.yaml has >= 36 sequences (%d)" % len(m["sequences"]))
    check([s["cell"] for s in tune] == [s["cell"] for s in val], "tuning and validation halves hold the same cells")
    check(all(s["name"].endswith("-tune") for s in tune) and all(s["name"].endswith("-val") for s in val),
          "sequence names say their half")  # fmt: skip
    for key, want in (("sensor", 4), ("noise", 3), ("scene_kind", 5)):
        check(len({s[key] for s in val}) >= want, "validation half covers %d %s values" % (want, key))
    check({"mocap", "fast", "slow-start", "preset"} <= {s["motion_kind"] for s in val},
          "validation half covers mocap, fast, slow-start and preset motions")  # fmt: skip

    # expansion and simulate arguments
    good_dir = os.path.join(tmp, "good")
    os.makedirs(good_dir)
    ok = matrix_lib.load(write_matrix(good_dir, [GOOD_CELL]))
    s = ok["sequences"]
    check([x["name"] for x in s] == ["c1-tune", "c1-val"] and [x["half"] for x in s] == ["tuning", "validation"],
          "a cell expands to CELL-tune and CELL-val")  # fmt: skip
    args = matrix_lib.simulate_args(s[1])
    check(args[args.index("--seed") + 1] == "2" and args[args.index("--start") + 1] == "3",
          "the validation variant's seed and start reach simulate")  # fmt: skip
    check("--binary" in args and "--sensor" in args and "--noise-level" in args, "simulate gets sensor, noise, binary")

    # bad input names the cell and what is wrong, before anything runs
    bad = [
        (GOOD_CELL.replace("boxes", "castle", 1), "cell c1", "unknown scene 'castle'"),
        (GOOD_CELL.replace("davis240c", "kinect"), "cell c1", "unknown sensor 'kinect'"),
        (GOOD_CELL.replace("noise: low", "noise: loud"), "cell c1", "unknown noise level 'loud'"),
        (GOOD_CELL.replace("motion: m6", "motion: m7"), "cell c1", "unknown motion 'm7'"),
        (GOOD_CELL.replace("[{seed: 1}, ", "["), "cell c1", "exactly two"),
        (GOOD_CELL.replace("{seed: 1}", "{seed: -1}"), "tuning variant", "'seed'"),
        (GOOD_CELL.replace("start: 3", "start: -3"), "validation variant", "'start' must be >= 0"),
        (GOOD_CELL.replace("variants", "variant"), "cell c1", "unknown key(s) variant"),
    ]
    for cell_text, where, what in bad:
        err = load_error(tmp, [cell_text])
        check(err is not None and where in err and what in err, "bad cell rejected: %s (%s)" % (what, err))
    err = load_error(tmp, [GOOD_CELL, GOOD_CELL])
    check(err is not None and "used twice" in err, "a repeated cell name is rejected")
    err = load_error(tmp, [GOOD_CELL], HEADER.replace("tests/data/ecd/poster_6dof_gt", "tests/data/nowhere"))
    check(err is not None and "motion mocap" in err and "no such file" in err, "a missing motion file is rejected")
    err = load_error(tmp, [GOOD_CELL], HEADER.replace("boxes: boxes", "boxes: cubist"))
    check(err is not None and "scene boxes" in err, "an unknown scene kind is rejected")

    # coverage and motion onset
    t = np.arange(1.0, 10.0001, 0.05)
    check(abs(matrix_run.coverage(t, 0.0, 10.0) - 0.9) < 1e-9, "coverage of an estimate from 1 s to 10 s is 90 %")
    t_gap = np.concatenate([np.arange(0.0, 4.0001, 0.05), np.arange(6.0, 10.0001, 0.05)])
    check(abs(matrix_run.coverage(t_gap, 0.0, 10.0) - 0.8) < 1e-9, "a 2 s hole is not covered")
    check(matrix_run.coverage([5.0], 0.0, 10.0) == 0.0, "a lone pose covers nothing")
    stats = dict(estimator=dict(initialized=True, initialized_at_s=0.5, segments=[
        dict(ended_by="event_gap"), dict(ended_by="residual"), dict(ended_by="end_of_stream")]))  # fmt: skip
    stats["frontend"] = dict(mean_active_features=41.6, median_active_features=48)
    scored = matrix_run.score(None, stats, np.zeros((0, 8)), np.zeros((0, 8)))
    evaluated = matrix_run.score(
        dict(matched_gt_path_length_m=4.0, alignment=dict(scale=0.5),
             ate=dict(trans_m=dict(rmse=0.1), rot_deg=dict(rmse=178.5)),
             velocity=dict(linear_rmse_perc_of_mean_speed=170.0, direction_deg=dict(median=139.7),
                           reversed_fraction=0.902)), stats, np.zeros((0, 8)), np.zeros((0, 8)))  # fmt: skip
    check(abs(evaluated["ate_pct"] - 2.5) < 1e-9 and evaluated["direction_deg"] == 139.7
          and abs(evaluated["reversed_pct"] - 90.2) < 1e-9 and evaluated["ate_rot_deg"] == 178.5,
          "the score takes the direction of travel, its reversed share and the rotation error from eval.json")  # fmt: skip
    check(scored["mean_active_features"] == 41.6 and scored["median_active_features"] == 48,
          "the score keeps the frontend's mean and median active features")  # fmt: skip
    check(scored["segments"] == 3 and scored["segment_ends"] == ["event_gap", "residual"],
          "the score counts the segments and says why each but the last ended")  # fmt: skip
    gt_t = np.arange(0.0, 3.0, 0.001)
    gt = np.zeros((len(gt_t), 8))
    gt[:, 0] = gt_t
    gt[:, 7] = 1.0
    gt[:, 1] = np.where(gt_t > 1.5, (gt_t - 1.5) * 0.1, 0.0)  # still, then 0.1 m/s from 1.5 s
    onset = matrix_run.motion_onset(gt)
    check(onset is not None and abs(onset - 1.601) < 0.002, "motion onset is when the camera is 1 cm away (%s)" % onset)
    check(matrix_run.motion_onset(gt[:1000]) is None, "a still camera has no onset")
    est_t = np.arange(1.7, 2.97, 0.05)  # an estimate from 1.7 s, 0.1 s after the onset, to 2.95 s
    est = np.zeros((len(est_t), 8))
    est[:, 0] = est_t
    scored = matrix_run.score(None, dict(estimator=dict(initialized=True, initialized_at_s=1.9)), gt, est)
    check(abs(scored["coverage"] - 1.25 / 2.999) < 1e-6, "coverage counts the still start (%s)" % scored["coverage"])
    check(abs(scored["coverage_after_onset"] - 1.25 / (2.999 - onset)) < 1e-6,
          "coverage after the onset counts from the onset (%s)" % scored["coverage_after_onset"])  # fmt: skip
    check(matrix_run.score(None, {}, gt[:1000], est)["coverage_after_onset"] is None,
          "a still camera has no coverage after onset")  # fmt: skip
    check(abs(scored["init_after_data_s"] - scored["init_after_onset_s"]) < 1e-12,
          "without an offset the start delay counts from the onset")  # fmt: skip
    late = matrix_run.score(None, dict(estimator=dict(initialized=True, initialized_at_s=1.9)), gt, est, 1.75)
    check(abs(late["init_after_data_s"] - 0.15) < 1e-9 and abs(late["init_after_onset_s"] - (1.9 - onset)) < 1e-9,
          "a run given data from 1.75 s, after the onset, counts its start delay from there (%s)"
          % late["init_after_data_s"])  # fmt: skip
    early = matrix_run.score(None, dict(estimator=dict(initialized=True, initialized_at_s=1.9)), gt, est, 0.5)
    check(abs(early["init_after_data_s"] - early["init_after_onset_s"]) < 1e-12,
          "an offset before the onset does not change the start delay")  # fmt: skip
    check(matrix_run.skip_of(["asynevo", "run", "--skip-ms", "150"]) == 0.15 and matrix_run.skip_of(None) == 0.0,
          "the skip of a recorded command")  # fmt: skip
    replay_dir = os.path.join(tmp, "replay_run")
    os.makedirs(replay_dir)
    with open(os.path.join(replay_dir, "tracks.txt"), "w") as f:
        f.write("# id t x y\n0 0.020169452 169 66\n1 0.0213 137 136\n")
    replay = dict(replay_of="elsewhere", command=["bench_replay_tracks", "a", "b", "c", "--skip-ms", "100"])
    given = dict(input=dict(first_event_s=0.051))  # the recorded run was given events from 51 ms on
    check(abs(matrix_run.data_start(replay, given, replay_dir, 0.001) - (0.1 + 0.020169452 - 0.001)) < 1e-12,
          "a replay's offset counts from its tracks' first measurement")  # fmt: skip
    late_events = dict(input=dict(first_event_s=0.301))
    check(abs(matrix_run.data_start(replay, late_events, replay_dir, 0.001) - 0.3) < 1e-12,
          "a replay's data start is never before the recorded run's first event")  # fmt: skip
    full = dict(command=["asynevo", "run", "--skip-ms", "50"])
    check(abs(matrix_run.data_start(full, given, replay_dir, 0.001) - 0.05) < 1e-12,
          "a full run's data start is its first event, after its --skip-ms")  # fmt: skip
    check(matrix_run.data_start(dict(replay_of="elsewhere", command=["bench_replay_tracks"]), {}, replay_dir, 0.0) == 0.0,
          "nothing said, no data start")  # fmt: skip
    # a replay's figures come from its log, also when it is scored again
    with open(os.path.join(replay_dir, "segments.txt"), "w") as f:
        f.write("# segment t_begin t_end knots ended_by\n0 0.3 5.0 94 event_gap\n1 5.4 9.9 90 end_of_stream\n")
    out = "bench: fed 10 measurements (0 skipped), 184 knots, initialized true at 0.312 s after 7 attempt(s)\n"
    st = matrix_run.replay_stats(replay_dir, replay_dir, out, 1.5)
    check(st["estimator"]["initialized"] and st["estimator"]["initialized_at_s"] == 0.312
          and st["estimator"]["init_attempts"] == 7 and [g["ended_by"] for g in st["estimator"]["segments"]]
          == ["event_gap", "end_of_stream"], "a replay's start, attempts and segments from its log")  # fmt: skip

    # drift: each 2 s window of a segment aligned by its own Sim(3)
    import alignment
    t = np.arange(0.0, 8.0, 0.05)
    truth = np.zeros((len(t), 8))
    truth[:, 0] = t
    truth[:, 7] = 1.0
    truth[:, 1] = np.cos(t)  # a loop of radius 1 m in x-y
    truth[:, 2] = np.sin(t)
    local, ratio, windows = alignment.local_drift(truth, truth, [(0.0, 7.95)])
    check(windows == 4 and local < 1e-9 and abs(ratio - 1.0) < 1e-9, "an exact estimate has no drift")  # fmt: skip
    drifting = truth.copy()
    grow = np.where(t < 4.0, 1.0, 1.5)  # the map's scale jumps by half at 4 s, each half rigid
    drifting[:, 1:4] = truth[:, 1:4] * grow[:, None] + np.array([0.3, -0.2, 0.1])
    local, ratio, _ = alignment.local_drift(drifting, truth, [(0.0, 7.95)])
    check(local < 1e-9 and abs(ratio - 1.5) < 1e-9,
          "a scale that jumps between windows: no local error, scale ratio 1.5 (%s, %s)" % (local, ratio))  # fmt: skip
    _, ratio, _ = alignment.local_drift(drifting, truth, [(0.0, 3.95), (4.0, 7.95)])
    check(abs(ratio - 1.0) < 1e-9, "each segment has its own scale: no drift within either")  # fmt: skip
    still = truth.copy()
    still[t >= 4.0, 1:4] = truth[t >= 4.0][0, 1:4]  # the camera stands still from 4 s
    _, ratio, _ = alignment.local_drift(still, still, [(0.0, 7.95)])
    check(abs(ratio - 1.0) < 1e-9, "windows without motion fit no scale")
    scored = matrix_run.score(dict(matched_gt_path_length_m=8.0, ate=dict(trans_m=dict(rmse=0.1))), {}, truth, drifting,
                              segment_bounds=[(0.0, 7.95)])  # fmt: skip
    check(abs(scored["scale_drift_pct"] - 50.0) < 1e-6 and scored["ate_local_pct"] < 1e-6,
          "the score holds the drift figures (%s)" % scored["scale_drift_pct"])  # fmt: skip
    seg_dir = os.path.join(tmp, "segments_run")
    os.makedirs(seg_dir)
    with open(os.path.join(seg_dir, "segments.txt"), "w") as f:
        f.write("# index start_s end_s knots ended_by\n0 0.05 4.0 80 event_gap\n1 4.4 9.9 110 end_of_stream\n")
    check(matrix_run.read_segments(seg_dir) == [(0.05, 4.0), (4.4, 9.9)] and matrix_run.read_segments(tmp) == [],
          "segment bounds from segments.txt")  # fmt: skip

    # a configuration's sensor section follows the sequence's sensor
    seq_dir = os.path.join(tmp, "seq346")
    os.makedirs(seq_dir)
    with open(os.path.join(seq_dir, "camchain.yaml"), "w") as f:
        f.write("cam0:\n  camera_model: pinhole\n  resolution: [346, 260]\n")
    cfg = os.path.join(tmp, "cfg.yaml")
    with open(cfg, "w") as f:
        f.write("# c\nsensor:\n  # w\n  width: 240\n  height: 180\nbackend:\n  knot_dt_ms: 50\n")
    used = matrix_run.config_for(cfg, seq_dir, tmp)
    text = open(used).read()
    check(used != cfg and "  width: 346\n  height: 260\n" in text and "# w" in text and "knot_dt_ms: 50" in text,
          "a 240x180 sensor section becomes the sequence's 346x260, the rest unchanged")  # fmt: skip
    check(matrix_run.config_for(cfg, tmp, tmp) == cfg, "a sequence without camchain.yaml keeps the configuration")

    # the report: failures are the worst value and stay in the tables
    runs = os.path.join(tmp, "runs")
    for name, score in (
        ("c1-tune", dict(status="ok", ate_pct=1.0, rte10_pct=5.0, vel_pct=20.0, init_s=0.5, coverage=0.9, init_attempts=3,
                         segments=2, segment_ends=["event_gap"], mean_active_features=41.6,
                         median_active_features=48, direction_deg=140.0, reversed_pct=90.0)),
        ("c1-val", dict(status="failed", message="initialization never succeeded after 40 attempt(s)", coverage=0.0,
                        init_attempts=40)),
    ):  # fmt: skip
        os.makedirs(os.path.join(runs, name))
        with open(os.path.join(runs, name, "score.json"), "w") as f:
            json.dump(score, f)
    rows = matrix_report.rows_of(ok, "all", runs)
    summary = matrix_report.summarize(rows)
    check(summary["failed"] == 1 and summary["ate_pct"]["worst"] == float("inf"), "a failed run is the worst ATE")
    check(summary["coverage_pct"]["worst"] == 0.0, "a failed run's coverage is 0")
    check(summary["above2"] == 1, "a failed run counts among the runs above 2 %")
    check(summary["misdirected"] == 2, "a run travelling backwards and a failed run are both misdirected")
    md = os.path.join(tmp, "report", "report.md")
    docs = os.path.join(tmp, "results.md")
    with open(docs, "w") as f:
        f.write("before\n%s\nold\n%s\nafter\n" % (matrix_report.BEGIN_MARKER, matrix_report.END_MARKER))
    code = subprocess.run([sys.executable, os.path.join(REPO_DIR, "tools", "matrix_report.py"), "--matrix",
                           ok["path"], "--runs", runs, "--name", "t", "--out", md, "--docs", docs, "--docs-images",
                           os.path.join(tmp, "img")]).returncode  # fmt: skip
    text = open(md).read() if os.path.exists(md) else ""
    check(code == 0 and "initialization never succeeded" in text and "| c1-val |" in text,
          "the report lists the failed run with its message")  # fmt: skip
    check("| 2 (event_gap) |" in text, "the report lists a run's segments and why each ended")
    check("| 42 / 48 |" in text, "the report gives the active features' mean and median")
    check("| 140.0 (90) |" in text, "the report gives a run's direction of travel and its reversed share")
    check(os.path.exists(os.path.join(tmp, "report", "distributions.png")), "the report draws the distributions")
    doc = open(docs).read()
    check("old" not in doc and "before" in doc and "after" in doc and "| c1-tune |" in doc,
          "--docs replaces only the matrix section")  # fmt: skip
    shutil.rmtree(tmp)


SMOKE_MATRIX = """duration_s: 2
sensors: [davis240c]
noise_levels: [low]
scenes: {boxes: boxes}
motions:
  m6: {preset: 6dof, kind: preset}
cells:
  - {name: smoke, sensor: davis240c, noise: low, scene: boxes, motion: m6, variants: [{seed: 1}, {seed: 2}]}
"""


def smoke(asynevo, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    snakemake = shutil.which("snakemake")
    check(snakemake is not None, "snakemake is installed (Debian package snakemake)")
    if snakemake is None:
        return
    base = [snakemake, "-s", os.path.join(REPO_DIR, "workflow", "Snakefile"), "--cores", "2", "--quiet", "--nolock"]
    # dry run of the repository's matrix: every job planned, names checked against the binary
    dry = subprocess.run(base + ["-n", "--config", "asynevo=" + asynevo, "out=" + os.path.join(work, "dry")],
                         capture_output=True, text=True)  # fmt: skip
    n = len(matrix_lib.load()["sequences"])
    check(dry.returncode == 0, "dry run of workflow/matrix.yaml succeeds" + ("" if dry.returncode == 0 else " (%s)" % dry.stderr.strip()[-500:]))
    check("simulate" in dry.stdout and "run" in dry.stdout and "report" in dry.stdout,
          "the dry run plans simulate, run and report jobs")  # fmt: skip
    check(str(n) in dry.stdout, "the dry run plans %d runs" % n)
    # a matrix naming an unknown scene fails before anything runs, naming the cell
    bad = os.path.join(work, "bad.yaml")
    with open(bad, "w") as f:
        f.write(SMOKE_MATRIX.replace("boxes", "castle"))
    r = subprocess.run(base + ["-n", "--config", "asynevo=" + asynevo, "matrix=" + bad, "out=" + os.path.join(work, "bad")],
                       capture_output=True, text=True)  # fmt: skip
    check(r.returncode != 0 and "castle" in (r.stdout + r.stderr), "an unknown scene stops the workflow, named")
    check(not os.path.exists(os.path.join(work, "bad", "sequences")), "nothing ran for the bad matrix")
    r = subprocess.run(base + ["-n", "--config", "asynevo=" + asynevo, "halff=validation"], capture_output=True, text=True)
    check(r.returncode != 0 and "halff" in (r.stdout + r.stderr), "an unknown configuration key stops the workflow, named")
    r = subprocess.run(base + ["-n", "--config", "asynevo=" + asynevo, "replay_skip_ms=50"], capture_output=True, text=True)
    check(r.returncode != 0 and "replay_skip_ms needs replay_of" in (r.stdout + r.stderr),
          "replay_skip_ms without replay_of stops the workflow")
    r = subprocess.run(base + ["-n", "--config", "asynevo=" + asynevo, "skip_ms=50", "replay_of=other"],
                       capture_output=True, text=True)  # fmt: skip
    check(r.returncode != 0 and "skip_ms is for full runs" in (r.stdout + r.stderr),
          "skip_ms with replay_of stops the workflow (a replay takes replay_skip_ms)")
    r = subprocess.run(base + ["-n", "--config", "asynevo=" + asynevo, "skip_ms=-5"], capture_output=True, text=True)
    check(r.returncode != 0 and "skip_ms -5" in (r.stdout + r.stderr), "a negative skip_ms stops the workflow")
    # one 2 s sequence (the validation half of the smoke matrix) through the whole workflow
    path = os.path.join(work, "smoke.yaml")
    with open(path, "w") as f:
        f.write(SMOKE_MATRIX)
    out = os.path.join(work, "out")
    r = subprocess.run(base + ["--config", "asynevo=" + asynevo, "matrix=" + path, "out=" + out, "half=validation"],
                       capture_output=True, text=True)  # fmt: skip
    check(r.returncode == 0, "the smoke workflow runs" + ("" if r.returncode == 0 else " (%s)" % r.stderr.strip()[-500:]))
    score = matrix_report.read_json(os.path.join(out, "runs", "baseline", "smoke-val", "score.json"))
    check(score is not None and score.get("status") in ("ok", "failed"), "the run left its score (%s)" % (score or {}).get("status"))
    if score and score.get("status") == "ok":
        check(score.get("ate_pct") is not None and score["ate_pct"] < 20, "the 2 s run has an ATE (%s %%)" % score.get("ate_pct"))
    report = os.path.join(out, "report", "baseline", "report.md")
    check(os.path.exists(report) and "| smoke-val |" in open(report).read(), "the report lists the sequence")
    check(not os.path.exists(os.path.join(out, "sequences", "smoke-tune")), "half=validation simulates only that half")
    # the same sequence started 300 ms into its events (skip_ms): asynevo run is given --skip-ms
    r = subprocess.run(base + ["--config", "asynevo=" + asynevo, "matrix=" + path, "out=" + out, "half=validation",
                               "name=skip300", "skip_ms=300"], capture_output=True, text=True)  # fmt: skip
    check(r.returncode == 0, "the smoke workflow runs with skip_ms" + ("" if r.returncode == 0 else " (%s)" % r.stderr.strip()[-500:]))
    skip_score = matrix_report.read_json(os.path.join(out, "runs", "skip300", "smoke-val", "score.json")) or {}
    check("--skip-ms" in skip_score.get("command", []) and "300" in skip_score.get("command", []),
          "the run's command has --skip-ms 300 (%s)" % skip_score.get("command"))
    skip_stats = matrix_report.read_json(os.path.join(out, "runs", "skip300", "smoke-val", "run", "stats.json")) or {}
    check(skip_stats.get("input", {}).get("events_skipped_at_start", 0) > 0, "the run left out the first 300 ms of events")
    # a second invocation has nothing to do (file-based rules)
    again = subprocess.run(base + ["-n", "--config", "asynevo=" + asynevo, "matrix=" + path, "out=" + out,
                                   "half=validation"], capture_output=True, text=True)  # fmt: skip
    check(again.returncode == 0 and "Nothing to be done" in (again.stdout + again.stderr), "a finished workflow is not rerun")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("mode", choices=["units", "smoke"])
    p.add_argument("--asynevo")
    p.add_argument("--work")
    args = p.parse_args()
    if args.mode == "units":
        units()
    else:
        smoke(os.path.abspath(args.asynevo), os.path.abspath(args.work))
    return exit_code()


if __name__ == "__main__":
    sys.exit(main())
