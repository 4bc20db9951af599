#!/usr/bin/python3
"""Robustness sweep: one backend setting judged on many runs instead of one (docs/backend.md,
"Outcomes are chaotic").

A single run on the real frontend's tracks flips between following the motion and losing its scale
with small changes, so a setting is judged here on SEQUENCES x TRACK SETS runs: eight simulated 10 s
sequences, each tracked by the frontend with a few equally plausible settings (the track sets). The
frontend runs once per (sequence, track set) with `asynevo run`, which also records the backend's exact
call sequence (`backend_feed.txt`); every backend setting is then an exact replay of those tracks
(`bench_replay_tracks`, a few seconds per run) followed by `asynevo eval --align sim3`.

  robustness_sweep.py --build build --out DIR --name NAME [--set backend.key=value ...]

prints one line per run (ATE in % of the path, velocity RMSE in % of the mean speed, mean RTE at
10 % of the path, initialization time), the mean per track set and over all runs, and how many runs
lose more than 2 % of the path. Everything is cached under DIR (sequences/, tracks/SEQ/SET/,
replays/NAME/...) and reused when the command that made it is the same. The tracks are keyed on the
configuration without its backend section, and every replay takes its backend section from --config
before the overrides, so a backend change in config/sim.yaml re-runs the replays, not the tracking.
`--set` values use the YAML syntax of the configuration files (lists without spaces:
backend.q_c=[10,10,10,0.3,0.3,0.3]).

Needs Debian's python3-numpy and python3-matplotlib (through benchmark_suite); run with /usr/bin/python3.
"""

import argparse
import json
import os
import re
import sys

TOOLS_DIR = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TOOLS_DIR)
from benchmark_suite import read_json, repo_path, run_logged, write_json  # noqa: E402
from config_text import override_yaml, with_backend_of, without_backend  # noqa: E402,F401

# The eight 10 s sequences of docs/backend.md ("Measured so far"): name -> simulate arguments.
SEQUENCES = {
    "demo": dict(scene="boxes", motion="6dof", seed=1),
    "room": dict(scene="room", motion="tests/data/ecd/poster_6dof_gt/groundtruth.txt", seed=4),
    "boxes5": dict(scene="boxes", motion="6dof", seed=5),
    "shapes_tr": dict(scene="shapes", motion="translation", seed=3),
    "boxes2": dict(scene="boxes", motion="6dof", seed=2),
    "boxes3": dict(scene="boxes", motion="6dof", seed=3),
    "poster": dict(scene="poster", motion="6dof", seed=1),
    "shapes6": dict(scene="shapes", motion="6dof", seed=2),
}
DURATION_S = 10.0

# Track sets: name -> frontend overrides. Hysteresis and measurement spacing change which events
# a tracker switches on and when it reports, not how well it tracks (docs/frontend.md).
TRACK_SETS = {
    "default": [],
    "hyst0.04": ["frontend.haste_hysteresis=0.04"],
    "mindt4": ["frontend.min_dt_ms=4"],
}


def log(msg):
    print("[sweep] " + msg, flush=True)


def cached(stamp_path, command):
    stamp = read_json(stamp_path)
    return stamp is not None and stamp.get("command") == command and stamp.get("status") == "ok"


def simulate(args, name, spec):
    seq_dir = os.path.join(args.out, "sequences", name)
    stamp = os.path.join(args.out, "sequences", name + ".json")
    motion = repo_path(spec["motion"]) if os.path.exists(repo_path(spec["motion"])) else spec["motion"]
    cmd = [args.asynevo, "simulate", "--scene", spec["scene"], "--motion", motion, "--duration",
           "%g" % DURATION_S, "--seed", str(spec["seed"]), "--out", seq_dir]  # fmt: skip
    if not cached(stamp, cmd):
        log("simulating %s ..." % name)
        os.makedirs(os.path.dirname(seq_dir), exist_ok=True)
        code, _, out = run_logged(cmd, seq_dir + ".log")
        if code != 0:
            raise SystemExit("simulating %s failed (exit %s); see %s.log" % (name, code, seq_dir))
        write_json(stamp, dict(command=cmd, status="ok"))
    return seq_dir


def record(args, seq, seq_dir, track_set, frontend_overrides):
    """`asynevo run` with the frontend overrides: the tracks and the backend feed to replay."""
    run_dir = os.path.join(args.out, "tracks", seq, track_set)
    stamp = run_dir + ".json"
    config_path = run_dir + ".config.yaml"
    config = override_yaml(args.config_text, frontend_overrides, args.config)
    cmd = [args.asynevo, "run", "--dataset", seq_dir, "--config", config_path, "--out", run_dir]
    key = cmd + [without_backend(config)]
    if not cached(stamp, key):
        log("tracking %s with %s ..." % (seq, track_set))
        os.makedirs(os.path.dirname(run_dir), exist_ok=True)
        with open(config_path, "w") as f:
            f.write(config)
        code, _, _ = run_logged(cmd, run_dir + ".log")
        if code != 0:
            raise SystemExit("asynevo run failed on %s/%s (exit %s); see %s.log" % (seq, track_set, code, run_dir))
        write_json(stamp, dict(command=key, status="ok"))
    return run_dir


def replay(args, seq, seq_dir, track_set, run_dir):
    """Exact backend replay of a recorded run with the --set overrides, evaluated; returns a row."""
    out = os.path.join(args.out, "replays", args.name, seq, track_set)
    stamp = out + ".json"
    with open(os.path.join(run_dir, "config.yaml")) as f:
        config = override_yaml(with_backend_of(f.read(), args.config_text), args.set, run_dir + "/config.yaml")
    est = os.path.join(out, "est.txt")
    cmd = [os.path.join(args.build, "bin", "bench_replay_tracks"), out, seq_dir, est]
    if not cached(stamp, cmd + [config]):
        os.makedirs(out, exist_ok=True)
        with open(os.path.join(out, "config.yaml"), "w") as f:
            f.write(config)
        for name in ("tracks.txt", "backend_feed.txt"):
            link = os.path.join(out, name)
            if os.path.lexists(link):
                os.remove(link)
            os.symlink(os.path.abspath(os.path.join(run_dir, name)), link)
        code, _, _ = run_logged(cmd, out + ".log")
        status = "ok"
        if code == 0:
            ev = [args.asynevo, "eval", "--gt", os.path.join(run_dir, "stamped_groundtruth.txt"), "--est", est,
                  "--velocities", est + ".velocities.txt", "--align", "sim3", "--out", os.path.join(out, "eval")]  # fmt: skip
            code, _, _ = run_logged(ev, out + ".eval.log")
            if code != 0:
                status = "eval failed (exit %s; %s.eval.log)" % (code, out)
        else:
            status = "replay failed (exit %s; %s.log)" % (code, out)
        write_json(stamp, dict(command=cmd + [config], status=status))
    stamp_status = read_json(stamp)["status"]
    row = dict(sequence=seq, track_set=track_set, status=stamp_status)
    e = read_json(os.path.join(out, "eval", "eval.json"))
    if stamp_status == "ok" and e:
        row["ate_pct"] = 100.0 * e["ate"]["trans_m"]["rmse"] / e["gt_path_length_m"]
        row["vel_pct"] = e.get("velocity", {}).get("linear_rmse_perc_of_mean_speed")
        rte = e["relative_error"]["per_length"]
        row["rte10_pct"] = rte[0]["trans_perc"]["mean"] if rte else None
    with open(out + ".log", errors="replace") as f:
        m = re.search(r"initialized (true|false) at ([0-9.]+) s", f.read())
    row["init_s"] = float(m.group(2)) if m and m.group(1) == "true" else None
    return row


def mean(values):
    values = [v for v in values if v is not None]
    return sum(values) / len(values) if values else float("nan")


def report(args, rows):
    def num(v, f="%.2f"):
        return f % v if v is not None else "–"

    print("\n%-10s %-10s %8s %8s %8s %7s  %s" % ("sequence", "tracks", "ATE %", "vel %", "RTE10 %", "init s", "status"))
    for r in rows:
        print("%-10s %-10s %8s %8s %8s %7s  %s" % (r["sequence"], r["track_set"], num(r.get("ate_pct")),
              num(r.get("vel_pct"), "%.1f"), num(r.get("rte10_pct"), "%.1f"), num(r.get("init_s")), r["status"]))  # fmt: skip
    failed = [r for r in rows if "ate_pct" not in r]
    ok = [r for r in rows if "ate_pct" in r]
    print()
    for ts in TRACK_SETS:
        sub = [r for r in ok if r["track_set"] == ts]
        print("track set %-10s mean ATE %.2f %% over %d runs" % (ts, mean(r["ate_pct"] for r in sub), len(sub)))
    above = sum(1 for r in ok if r["ate_pct"] > 2.0)
    print("%s: mean ATE %.2f %%, velocity %.1f %%, %d of %d runs above 2 %%, %d failed (counted apart)"
          % (args.name, mean(r["ate_pct"] for r in ok), mean(r.get("vel_pct") for r in ok), above, len(ok), len(failed)))  # fmt: skip
    write_json(os.path.join(args.out, "replays", args.name + ".json"), dict(set=args.set, rows=rows))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build", help="build folder with bin/asynevo and bin/bench_replay_tracks")
    p.add_argument("--out", required=True, help="cache and output folder")
    p.add_argument("--name", required=True, help="name of this backend setting (folder under replays/)")
    p.add_argument("--set", action="append", default=[], help="backend override section.key=value (repeatable)")
    p.add_argument("--config", default="config/sim.yaml", help="configuration the track sets start from")
    p.add_argument("--sequences", default=",".join(SEQUENCES), help="comma-separated subset of " + ", ".join(SEQUENCES))
    args = p.parse_args()
    args.build = os.path.abspath(repo_path(args.build))
    args.config = repo_path(args.config)
    args.out = os.path.abspath(args.out)
    args.asynevo = os.path.join(args.build, "bin", "asynevo")
    for tool in (args.asynevo, os.path.join(args.build, "bin", "bench_replay_tracks")):
        if not os.access(tool, os.X_OK):
            raise SystemExit("%s: not found or not executable (build the project first)" % tool)
    if not os.path.isfile(args.config):
        raise SystemExit("%s: no such configuration file" % args.config)
    with open(args.config) as f:
        args.config_text = f.read()
    names = [s for s in args.sequences.split(",") if s]
    unknown = [s for s in names if s not in SEQUENCES]
    if unknown:
        raise SystemExit("unknown sequence(s) %s; known: %s" % (", ".join(unknown), ", ".join(SEQUENCES)))
    rows = []
    for seq in names:
        seq_dir = simulate(args, seq, SEQUENCES[seq])
        for track_set, overrides in TRACK_SETS.items():
            run_dir = record(args, seq, seq_dir, track_set, overrides)
            rows.append(replay(args, seq, seq_dir, track_set, run_dir))
            r = rows[-1]
            log("%s/%s: %s" % (seq, track_set, "ATE %.2f %%" % r["ate_pct"] if "ate_pct" in r else r["status"]))
    report(args, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
