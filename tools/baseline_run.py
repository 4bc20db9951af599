#!/usr/bin/python3
"""One backend on one sequence of the sliding-window vs full-history baselines comparison
(workflow/baselines.smk): `asynevo run --backend B`, `asynevo eval --align sim3` of the estimate and
its velocities, and a status file.

  baseline_run.py --asynevo BIN --dataset SEQ_DIR --backend B --run-dir DIR --status FILE
                  [--sequence NAME] [--config FILE] [--timeout S]

DIR is emptied first and becomes an ordinary run folder (run.log, eval.log and eval.json beside the
run's own files). FILE (JSON) is written in every case, with status
  ok        the run and its evaluation finished;
  failed    the run or its evaluation exited non-zero (for example "initialization never
            succeeded"); `message` is the line of its output that says why;
  timeout   the run was stopped after --timeout wall seconds; timing.csv keeps the rows of every
            backend update up to there (tools/benchmark_suite.py reports how far in event time it got).
A failed run is a result, not an error of this script, which exits 0 unless it could not write FILE.
The runs, the evaluation and the messages are those of tools/matrix_run.py (imported from it).

The module also holds the sequence table of workflow/baselines.yaml (load_sequences,
select_sequences, select_backends, simulate_args), used by the workflow and by
tools/benchmark_suite.py. Needs Debian's python3-numpy and python3-yaml; run with /usr/bin/python3.
"""

import argparse
import datetime
import json
import os
import re
import shutil
import sys
import types

import yaml

TOOLS_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(TOOLS_DIR)
sys.path.insert(0, TOOLS_DIR)
import matrix_run  # noqa: E402

SEQUENCES_FILE = os.path.join(REPO_DIR, "workflow", "baselines.yaml")
BACKENDS = ["window", "incremental", "incremental-frozen"]
NAME_RE = re.compile(r"^[A-Za-z0-9_.-]+$")
SEQUENCE_KEYS = {"scene", "motion", "seed", "duration", "default", "about"}


class BaselineError(Exception):
    """A sequence table, sequence or backend name that cannot be used; the message names it."""


def repo_path(p):
    return p if os.path.isabs(p) else os.path.join(REPO_DIR, p)


# ----------------------------------------------------------------------------- the sequence table


def load_sequences(path=SEQUENCES_FILE):
    """name -> {scene, motion, motion_is_file, seed, duration, default, about}, in the file's order.
    Raises BaselineError naming the file and the entry for anything wrong."""
    try:
        with open(path) as f:
            doc = yaml.safe_load(f)
    except OSError as e:
        raise BaselineError("%s: cannot read (%s)" % (path, e.strerror))
    except yaml.YAMLError as e:
        raise BaselineError("%s: not valid YAML (%s)" % (path, str(e).replace("\n", " ")))
    if not isinstance(doc, dict) or not isinstance(doc.get("sequences"), dict) or not doc["sequences"]:
        raise BaselineError("%s: expected a non-empty mapping 'sequences: {NAME: {scene, motion, seed, duration}}'" % path)
    table = {}
    for name, spec in doc["sequences"].items():
        where = "%s: sequence %s" % (path, name)
        if not isinstance(name, str) or not NAME_RE.match(name):
            raise BaselineError("%s: the name must be letters, digits, '_', '.' and '-'" % where)
        if not isinstance(spec, dict):
            raise BaselineError("%s: expected a mapping {scene, motion, seed, duration}" % where)
        unknown = sorted(set(spec) - SEQUENCE_KEYS)
        if unknown:
            raise BaselineError("%s: unknown key(s) %s (known: %s)" % (where, ", ".join(unknown), ", ".join(sorted(SEQUENCE_KEYS))))
        missing = sorted({"scene", "motion", "seed", "duration"} - set(spec))
        if missing:
            raise BaselineError("%s: missing key(s) %s" % (where, ", ".join(missing)))
        for key in ("scene", "motion"):
            if not isinstance(spec[key], str) or not spec[key].strip():
                raise BaselineError("%s: %r must be a name, got %r" % (where, key, spec[key]))
        seed, duration = spec["seed"], spec["duration"]
        if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
            raise BaselineError("%s: 'seed' must be an integer >= 0, got %r" % (where, seed))
        if not isinstance(duration, (int, float)) or isinstance(duration, bool) or duration <= 0:
            raise BaselineError("%s: 'duration' must be a number of seconds > 0, got %r" % (where, duration))
        if not isinstance(spec.get("default", False), bool):
            raise BaselineError("%s: 'default' must be true or false, got %r" % (where, spec["default"]))
        motion = spec["motion"]
        is_file = os.path.isfile(repo_path(motion))
        if not is_file and ("/" in motion or "." in motion):
            raise BaselineError("%s: motion file %s does not exist (paths are relative to the repository root)" % (where, motion))
        table[name] = dict(scene=spec["scene"], motion=motion, motion_is_file=is_file, seed=seed,
                           duration=float(duration), default=spec.get("default", False),
                           about=str(spec.get("about", "%s scene, motion %s" % (spec["scene"], motion))))  # fmt: skip
    if not any(s["default"] for s in table.values()):
        raise BaselineError("%s: no sequence is marked 'default: true'" % path)
    return table


def _names(value):
    """A comma-separated string (or a list) as a list of names without blanks or repeats."""
    items = value if isinstance(value, (list, tuple)) else str(value).split(",")
    out = []
    for n in (str(i).strip() for i in items):
        if n and n not in out:
            out.append(n)
    return out


def select_sequences(table, names=None):
    """The sequence names asked for (comma-separated or a list), or the default set; unknown names
    raise BaselineError naming them and the known ones."""
    if names is None or not _names(names):
        return [n for n, s in table.items() if s["default"]]
    chosen = _names(names)
    unknown = [n for n in chosen if n not in table]
    if unknown:
        raise BaselineError("unknown sequence(s) %s; known: %s (workflow/baselines.yaml)" % (", ".join(unknown), ", ".join(table)))
    return chosen


def select_backends(names=None):
    """The backends asked for (comma-separated or a list), or all three; unknown names raise."""
    if names is None or not _names(names):
        return list(BACKENDS)
    chosen = _names(names)
    unknown = [b for b in chosen if b not in BACKENDS]
    if unknown:
        raise BaselineError("unknown backend(s) %s; known: %s" % (", ".join(unknown), ", ".join(BACKENDS)))
    return chosen


def simulate_args(spec, duration=None):
    """The `asynevo simulate` arguments of a sequence (without the binary and --out); duration, when
    given, replaces the sequence's own."""
    motion = repo_path(spec["motion"]) if spec["motion_is_file"] else spec["motion"]
    return ["--scene", spec["scene"], "--motion", motion, "--duration", "%g" % (duration or spec["duration"]),
            "--seed", str(spec["seed"])]  # fmt: skip


# ----------------------------------------------------------------------------- one run


def run_backend(args):
    """Runs and evaluates one backend on one sequence; returns its status record (never raises for a
    failed run)."""
    if os.path.isdir(args.run_dir):
        shutil.rmtree(args.run_dir)
    os.makedirs(args.run_dir)
    cmd = [args.asynevo, "run", "--dataset", args.dataset, "--out", args.run_dir, "--backend", args.backend]
    if args.config:
        cmd += ["--config", args.config]
    load = list(os.getloadavg()) if hasattr(os, "getloadavg") else None
    started = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    code, wall, out = matrix_run.run_logged(cmd, os.path.join(args.run_dir, "run.log"), args.timeout)
    rec = dict(sequence=args.sequence, backend=args.backend, command=cmd, exit_code=code, wall_s=round(wall, 2),
               started=started, load_at_start=load)  # fmt: skip
    if code is None:
        rec.update(status="timeout", run_timeout_s=args.timeout,
                   message="stopped after the time limit of %g s (run_timeout_s)" % args.timeout)  # fmt: skip
    elif code != 0:
        rec.update(status="failed", message=matrix_run.last_message(out))
    else:
        rec.update(status="ok", message="")
        matrix_run.evaluate(types.SimpleNamespace(asynevo=args.asynevo, run_dir=args.run_dir), rec)
    return rec


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--asynevo", required=True)
    p.add_argument("--dataset", required=True, help="the simulated sequence folder")
    p.add_argument("--backend", required=True, choices=BACKENDS)
    p.add_argument("--run-dir", required=True)
    p.add_argument("--status", required=True, help="the status file (JSON) to write")
    p.add_argument("--sequence", default="", help="the sequence's name (default: the dataset folder's)")
    p.add_argument("--config", default="", help="asynevo run --config ('' = the built-in defaults)")
    p.add_argument("--timeout", type=float, default=0, help="wall seconds; 0 = none")
    args = p.parse_args(argv)
    args.sequence = args.sequence or os.path.basename(os.path.normpath(args.dataset))
    rec = run_backend(args)
    tmp = args.status + ".tmp"
    with open(tmp, "w") as f:
        json.dump(rec, f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(tmp, args.status)
    print("%s/%s: %s in %.1f s %s" % (args.sequence, args.backend, rec["status"], rec["wall_s"], rec["message"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
