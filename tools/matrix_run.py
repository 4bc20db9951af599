#!/usr/bin/python3
"""One cell of the evaluation matrix: `asynevo run` on a simulated sequence, `asynevo eval` of the
estimate, and the sequence's score (docs/evaluation_matrix.md, "What is measured").

  matrix_run.py --asynevo BIN --dataset SEQ_DIR --config FILE --run-dir DIR --score FILE
                [--sequence NAME] [--timeout S] [--skip-ms MS] [--replay-of RECORDED_RUN_DIR
                --replay-bin BIN [--replay-skip-ms MS]]

--skip-ms leaves out the events of the sequence's first MS milliseconds (`asynevo run --skip-ms`): the
start then comes from later in the stream (start offsets). The score still counts time, coverage and
the motion onset from the sequence's ground truth, as for a replay with --replay-skip-ms.

With --replay-of, the frontend does not run: the backend replays the tracks that run folder recorded
(bench_replay_tracks, exact: the same tracks and order as in the run), with the backend section of
--config. A backend setting is judged that way in seconds per sequence. --replay-skip-ms drops the first
MS milliseconds of the recorded tracks (the start then comes from later windows).

Writes FILE (JSON) in every case: status "ok", or "failed" / "timeout" with the message that says
why. A failed run is a result, not an error of this script, which exits 0 unless it could not write
its score. Needs Debian's python3-numpy.
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import alignment  # noqa: E402
import config_text  # noqa: E402

COVERAGE_MAX_GAP_S = 0.25  # estimate poses further apart than this do not cover the time between them
ONSET_TRANSLATION_M = 0.01  # motion onset: the camera is this far from its first pose ...
ONSET_ROTATION_DEG = 1.0  # ... or turned this much


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def load_poses(path):
    """(N, 8) array of a TUM file (t tx ty tz qx qy qz qw), empty when missing or empty."""
    if not os.path.isfile(path):
        return np.zeros((0, 8))
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                rows.append([float(v) for v in line.split()[:8]])
    return np.array(rows).reshape(-1, 8)


def coverage(est_t, begin_s, end_s, max_gap_s=COVERAGE_MAX_GAP_S):
    """Share of [begin_s, end_s] covered by the estimate: the union of the intervals between
    consecutive estimate times closer than max_gap_s (a lone pose covers nothing)."""
    span = end_s - begin_s
    if span <= 0 or len(est_t) < 2:
        return 0.0
    t = np.clip(np.sort(np.asarray(est_t, dtype=float)), begin_s, end_s)
    gaps = np.diff(t)
    return float(np.sum(gaps[gaps <= max_gap_s]) / span)


def motion_onset(gt):
    """Time of the first ground-truth pose ONSET_TRANSLATION_M or ONSET_ROTATION_DEG away from the
    first pose (the start of camera motion); None when the camera never moves that much."""
    if len(gt) == 0:
        return None
    d = np.linalg.norm(gt[:, 1:4] - gt[0, 1:4], axis=1)
    q0 = gt[0, 4:8] / np.linalg.norm(gt[0, 4:8])
    q = gt[:, 4:8] / np.linalg.norm(gt[:, 4:8], axis=1, keepdims=True)
    angle_deg = np.degrees(2.0 * np.arccos(np.clip(np.abs(q @ q0), 0.0, 1.0)))
    moved = np.nonzero((d > ONSET_TRANSLATION_M) | (angle_deg > ONSET_ROTATION_DEG))[0]
    return float(gt[moved[0], 0]) if len(moved) else None


def last_message(text, limit=300):
    """The line of a failed command's output that says why (an error line, else the last line)."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    for ln in reversed(lines):
        if re.search(r"error|never succeeded|failed|terminate|what\(\)", ln, re.IGNORECASE):
            return ln[:limit]
    return lines[-1][:limit] if lines else "(no output)"


def run_logged(cmd, log_path, timeout_s=None):
    """(exit code or None on timeout, wall seconds, output) of cmd, its output also in log_path."""
    t0 = time.monotonic()
    with open(log_path, "w") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        try:
            proc = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT)
        except OSError as e:
            f.write("error: cannot start %s: %s\n" % (cmd[0], e.strerror))
            return 127, time.monotonic() - t0, "error: cannot start %s: %s" % (cmd[0], e.strerror)
        try:
            code = proc.wait(timeout=timeout_s if timeout_s else None)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
            code = None
    with open(log_path, errors="replace") as f:
        return code, time.monotonic() - t0, f.read()


def skip_of(command):
    """The --skip-ms of a recorded command line, in seconds (0 without one)."""
    command = command or []
    for flag, value in zip(command, command[1:]):
        if flag == "--skip-ms":
            return float(value) / 1000.0
    return 0.0


def first_track_time(tracks_path):
    """Event time of the first measurement in a run's tracks.txt, or None without one."""
    try:
        with open(tracks_path) as f:
            for line in f:
                fields = line.split()
                if fields and not fields[0].startswith("#"):
                    return float(fields[1])
    except (OSError, IndexError, ValueError):
        return None
    return None


def data_start(rec, stats, run_dir, begin):
    """Time after `begin` from which the run was given data: its first event (a full run's --skip-ms
    cuts the events from the stream's first on; a replay has the recorded run's input), or, for a
    replay with --skip-ms, its tracks' first measurement plus the skip (as bench_replay_tracks counts
    it), whichever is later. 0 when nothing says."""
    first_event = ((stats or {}).get("input") or {}).get("first_event_s")
    start = first_event - begin if first_event is not None and begin is not None else 0.0
    skip = skip_of(rec.get("command")) if rec.get("replay_of") else 0.0
    first = first_track_time(os.path.join(run_dir, "tracks.txt")) if skip else None
    if first is not None and begin is not None:
        start = max(start, first - begin + skip)
    return start


def read_segments(run_dir):
    """(start_s, end_s) of each segment in a run folder's segments.txt; [] without one."""
    segments = []
    try:
        with open(os.path.join(run_dir, "segments.txt")) as f:
            for line in f:
                fields = line.split()
                if len(fields) >= 3 and not fields[0].startswith("#"):
                    segments.append((float(fields[1]), float(fields[2])))
    except (OSError, ValueError):
        return []
    return segments


def score(eval_json, stats, gt, est, data_start_s=0.0, segment_bounds=()):
    """The figures of one finished run (None where a figure does not exist). data_start_s: from when
    after the ground truth's first pose the run was given data (a start offset; see data_start);
    segment_bounds: (start_s, end_s) of the estimate's segments (read_segments), for the drift figures."""
    s = {}
    inp = (stats or {}).get("input", {})
    est_ = (stats or {}).get("estimator", {})
    fe = (stats or {}).get("frontend", {})
    begin = float(gt[0, 0]) if len(gt) else inp.get("first_event_s")
    end = float(gt[-1, 0]) if len(gt) else inp.get("last_event_s")
    s["span_s"] = end - begin if begin is not None and end is not None else None
    s["initialized"] = bool(est_.get("initialized"))
    s["init_attempts"] = est_.get("init_attempts")
    s["init_s"] = est_["initialized_at_s"] - begin if s["initialized"] and begin is not None else None
    onset = motion_onset(gt)
    s["motion_onset_s"] = onset - begin if onset is not None else None
    s["init_after_onset_s"] = (s["init_s"] - s["motion_onset_s"]) if s["init_s"] is not None and onset is not None else None
    # A run given data only from a start offset on cannot start before it: its start delay counts from
    # the later of the onset and the offset (the first textured motion the run sees).
    s["data_start_s"] = data_start_s
    s["init_after_data_s"] = (s["init_s"] - max(s["motion_onset_s"], data_start_s)
                              if s["init_after_onset_s"] is not None else None)
    s["coverage"] = coverage(est[:, 0], begin, end) if s["span_s"] else 0.0
    # The same from the motion onset: a monocular start needs motion, so a still start bounds the above.
    moving = onset is not None and end is not None and end > onset
    s["coverage_after_onset"] = coverage(est[:, 0], onset, end) if moving else None
    s["events"] = (stats or {}).get("events")
    s["mean_active_features"] = fe.get("mean_active_features")
    s["median_active_features"] = fe.get("median_active_features")
    s["wall_s"] = (stats or {}).get("wall_time_s")
    s["real_time_factor"] = (stats or {}).get("real_time_factor")
    s["median_update_ms"] = (stats or {}).get("update_time", {}).get("median_ms")
    segments = est_.get("segments") or []
    s["segments"] = len(segments)
    s["segment_ends"] = [g.get("ended_by") for g in segments[:-1]]  # why each but the last ended
    s["max_median_residual_px"] = est_.get("max_median_residual_px")
    s["max_depth_ratio"] = est_.get("max_depth_ratio")
    if eval_json:
        path = eval_json.get("matched_gt_path_length_m") or 0.0
        s["path_m"] = path
        s["ate_m"] = eval_json["ate"]["trans_m"]["rmse"]
        s["ate_pct"] = 100.0 * s["ate_m"] / path if path > 0 else None
        rel = eval_json.get("relative_error", {}).get("per_length") or []
        s["rte10_pct"] = rel[0]["trans_perc"]["mean"] if rel else None
        vel = eval_json.get("velocity") or {}
        s["vel_pct"] = vel.get("linear_rmse_perc_of_mean_speed")
        # Direction of travel: the median angle between the estimated and the true body velocity, and
        # the share travelling in reverse. A Sim(3) fit of positions alone scores an estimate that moves
        # backwards through its map at a few % ATE; these figures, and the rotation error, do not.
        s["direction_deg"] = (vel.get("direction_deg") or {}).get("median")
        reversed_fraction = vel.get("reversed_fraction")
        s["reversed_pct"] = 100.0 * reversed_fraction if isinstance(reversed_fraction, (int, float)) else None
        s["ate_rot_deg"] = eval_json["ate"].get("rot_deg", {}).get("rmse")
        s["scale"] = eval_json.get("alignment", {}).get("scale")
        # How much of the ATE is drift: the same RMSE after aligning each 2 s window of a segment by its
        # own Sim(3), and how far the windows' scales spread (alignment.local_drift).
        local_m, scale_ratio, _ = alignment.local_drift(est, gt, segment_bounds)
        s["ate_local_pct"] = 100.0 * local_m / path if local_m is not None and path > 0 else None
        s["scale_drift_pct"] = 100.0 * (scale_ratio - 1.0) if scale_ratio is not None else None
    return s


def sensor_size(dataset):
    """(width, height) from the sequence's Kalibr camchain.yaml (the simulator writes one), else None."""
    try:
        with open(os.path.join(dataset, "camchain.yaml")) as f:
            m = re.search(r"resolution:\s*\[\s*(\d+)\s*,\s*(\d+)\s*\]", f.read())
    except OSError:
        return None
    return (int(m.group(1)), int(m.group(2))) if m else None


def config_for(config_path, dataset, run_dir):
    """The configuration file a run uses: `config_path` itself, or, when it has a `sensor:` section and
    the sequence is of another size, a copy in run_dir with the sequence's sensor size (a setting is
    judged on every sensor of the matrix; its sensor section only describes DAVIS240C text files)."""
    size = sensor_size(dataset)
    with open(config_path) as f:
        text = f.read()
    if size is None or not re.search(r"^sensor:", text, re.MULTILINE):
        return config_path
    resized = config_text.override_yaml(text, ["sensor.width=%d" % size[0], "sensor.height=%d" % size[1]], config_path)
    if resized == text:
        return config_path
    path = os.path.join(run_dir, "input_config.yaml")
    with open(path, "w") as f:
        f.write(resized)
    return path


def run_full(args):
    """`asynevo run` on the sequence: (record, stats.json)."""
    config = config_for(args.config, args.dataset, args.run_dir)
    cmd = [args.asynevo, "run", "--dataset", args.dataset, "--config", config, "--out", args.run_dir]
    if args.skip_ms:
        cmd += ["--skip-ms", "%g" % args.skip_ms]
    code, wall, out = run_logged(cmd, os.path.join(args.run_dir, "run.log"), args.timeout)
    rec = dict(command=cmd, exit_code=code, process_wall_s=round(wall, 2))
    if code is None:
        rec.update(status="timeout", message="stopped after the time limit of %g s" % args.timeout)
    elif code != 0:
        rec.update(status="failed", message=last_message(out))
    else:
        rec.update(status="ok", message="")
    return rec, read_json(os.path.join(args.run_dir, "stats.json"))


def replay_stats(recorded, run_dir, out, wall):
    """The stats a replay reports (its output `out` and its run_dir/segments.txt), with the recorded
    run's input and frontend."""
    segments = []
    if os.path.isfile(os.path.join(run_dir, "segments.txt")):
        with open(os.path.join(run_dir, "segments.txt")) as f:
            segments = [dict(ended_by=ln.split()[4]) for ln in f if ln.strip() and not ln.startswith("#")]
    m = re.search(r"initialized (true|false) at ([0-9.]+) s after ([0-9]+) attempt", out)
    loss = re.search(r"largest window median residual ([0-9.]+) px, largest depth ratio ([0-9.]+)", out)
    recorded_stats = read_json(os.path.join(recorded, "stats.json")) or {}
    stats = dict(input=recorded_stats.get("input", {}), frontend=recorded_stats.get("frontend", {}),
                 events=recorded_stats.get("events"), wall_time_s=wall,
                 estimator=dict(initialized=bool(m and m.group(1) == "true"),
                                initialized_at_s=float(m.group(2)) if m else 0.0,
                                init_attempts=int(m.group(3)) if m else None, segments=segments,
                                max_median_residual_px=float(loss.group(1)) if loss else None,
                                max_depth_ratio=float(loss.group(2)) if loss else None))  # fmt: skip
    return stats


def run_replay(args):
    """The backend alone on the tracks another setting's run recorded (its frontend configuration, the
    backend section of --config): (record, stats as far as the replay reports them)."""
    recorded = args.replay_of
    needed = [os.path.join(recorded, f) for f in ("config.yaml", "tracks.txt", "backend_feed.txt")]
    missing = [f for f in needed if not os.path.isfile(f)]
    if missing:
        return dict(status="failed", message="nothing to replay: %s missing" % ", ".join(missing)), None
    with open(needed[0]) as f, open(args.config) as g:
        config = config_text.with_backend_of(f.read(), g.read())
    with open(os.path.join(args.run_dir, "config.yaml"), "w") as f:
        f.write(config)
    for name in ("tracks.txt", "backend_feed.txt"):
        link = os.path.join(args.run_dir, name)
        if os.path.lexists(link):
            os.remove(link)
        os.symlink(os.path.abspath(os.path.join(recorded, name)), link)
    gt = os.path.join(recorded, "stamped_groundtruth.txt")
    if os.path.isfile(gt):
        shutil.copyfile(gt, os.path.join(args.run_dir, "stamped_groundtruth.txt"))
    est = os.path.join(args.run_dir, "stamped_traj_estimate.txt")
    cmd = [args.replay_bin, args.run_dir, args.dataset, est]
    if args.replay_skip_ms:
        cmd += ["--skip-ms", "%g" % args.replay_skip_ms]
    stale = os.path.join(args.run_dir, "segments.txt")  # an earlier replay's, read by replay_stats
    if os.path.lexists(stale):
        os.remove(stale)
    code, wall, out = run_logged(cmd, os.path.join(args.run_dir, "replay.log"), args.timeout)
    rec = dict(command=cmd, exit_code=code, process_wall_s=round(wall, 2), replay_of=recorded)
    if os.path.isfile(est + ".velocities.txt"):
        os.replace(est + ".velocities.txt", os.path.join(args.run_dir, "velocities.txt"))
    if os.path.isfile(est + ".segments.txt"):
        os.replace(est + ".segments.txt", os.path.join(args.run_dir, "segments.txt"))
    stats = replay_stats(recorded, args.run_dir, out, wall)
    if code is None:
        rec.update(status="timeout", message="stopped after the time limit of %g s" % args.timeout)
    elif code != 0:
        rec.update(status="failed", message=last_message(out))
    elif not stats["estimator"]["initialized"]:
        rec.update(status="failed", message="initialization never succeeded (replay)")
    else:
        rec.update(status="ok", message="")
    return rec, stats


def evaluate(args, rec):
    """`asynevo eval` of a finished run; eval.json or None (the record then says why)."""
    cmd = [args.asynevo, "eval", "--gt", os.path.join(args.run_dir, "stamped_groundtruth.txt"),
           "--est", os.path.join(args.run_dir, "stamped_traj_estimate.txt"),
           "--velocities", os.path.join(args.run_dir, "velocities.txt"), "--align", "sim3", "--out", args.run_dir]  # fmt: skip
    code, _, out = run_logged(cmd, os.path.join(args.run_dir, "eval.log"))
    if code != 0:
        rec.update(status="failed", message="evaluation failed: " + last_message(out))
        return None
    return read_json(os.path.join(args.run_dir, "eval.json"))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--asynevo", required=True)
    p.add_argument("--dataset", required=True)
    p.add_argument("--config", required=True)
    p.add_argument("--run-dir", required=True)
    p.add_argument("--score", required=True)
    p.add_argument("--sequence", default="")
    p.add_argument("--timeout", type=float, default=0, help="seconds; 0 = none")
    p.add_argument("--replay-of", help="replay the tracks this run folder recorded (backend section of --config)")
    p.add_argument("--replay-bin", help="bench_replay_tracks (with --replay-of)")
    p.add_argument("--replay-skip-ms", type=float, default=0.0,
                   help="with --replay-of: skip the tracks' first MS milliseconds (start offsets)")
    p.add_argument("--skip-ms", type=float, default=0.0,
                   help="a full run: skip the events' first MS milliseconds (start offsets)")
    p.add_argument("--rescore", action="store_true",
                   help="do not run: evaluate the run already in --run-dir again and rewrite --score (after a "
                        "change of the evaluation; the run's own record and stats.json are kept)")
    args = p.parse_args()
    if args.replay_of and not args.replay_bin:
        p.error("--replay-of needs --replay-bin")
    if args.skip_ms and args.replay_of:
        p.error("--skip-ms is for full runs; a replay takes --replay-skip-ms")
    if not (args.skip_ms >= 0 and args.replay_skip_ms >= 0):
        p.error("--skip-ms and --replay-skip-ms take durations >= 0")
    os.makedirs(args.run_dir, exist_ok=True)
    if args.rescore:
        rec = read_json(args.score)
        if rec is None:
            p.error("--rescore: %s: no score to rescore" % args.score)
        if rec.get("replay_of"):  # a replay keeps its figures in its log, not in a stats.json
            with open(os.path.join(args.run_dir, "replay.log"), errors="replace") as f:
                stats = replay_stats(rec["replay_of"], args.run_dir, f.read(), rec.get("process_wall_s"))
        else:
            stats = read_json(os.path.join(args.run_dir, "stats.json"))
    else:
        rec, stats = run_replay(args) if args.replay_of else run_full(args)
    rec["sequence"] = args.sequence or os.path.basename(os.path.normpath(args.dataset))
    eval_json = evaluate(args, rec) if rec["status"] == "ok" else None
    gt = load_poses(os.path.join(args.dataset, "groundtruth.txt"))
    est = load_poses(os.path.join(args.run_dir, "stamped_traj_estimate.txt"))
    begin = float(gt[0, 0]) if len(gt) else None
    rec.update(score(eval_json, stats, gt, est, data_start(rec, stats, args.run_dir, begin), read_segments(args.run_dir)))
    tmp = args.score + ".tmp"
    with open(tmp, "w") as f:
        json.dump(rec, f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(tmp, args.score)
    print("%s: %s%s" % (rec["sequence"], rec["status"],
                        " ATE %.2f %%" % rec["ate_pct"] if rec.get("ate_pct") is not None else " " + rec["message"]))  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
