#!/usr/bin/python3
"""The evaluation matrix (workflow/matrix.yaml, docs/evaluation_matrix.md): loading, checking and
expanding it into sequences.

  matrix.py check  [--matrix FILE] [--asynevo BIN]     check the file (and its names against the binary)
  matrix.py list   [--matrix FILE] [--half H]          one line per sequence: name, half, simulate args

A sequence is one variant of a cell; its name is CELL-tune (first variant, tuning half) or CELL-val
(second variant, validation half). Every problem is reported with the cell it is in, before anything
runs. Used by workflow/Snakefile; needs Debian's python3-yaml (a dependency of snakemake).
"""

import argparse
import os
import re
import subprocess
import sys

import yaml

REPO_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_MATRIX = os.path.join(REPO_DIR, "workflow", "matrix.yaml")
HALVES = ("tuning", "validation")
SUFFIX = {"tuning": "tune", "validation": "val"}
SCENE_KINDS = ("planar", "boxes", "room", "sparse", "dense")
MOTION_KINDS = ("preset", "mocap", "fast", "slow-start")
NAME_RE = re.compile(r"^[a-z0-9][a-z0-9-]*$")


class MatrixError(Exception):
    """A matrix file that cannot be used; the message names the file and the entry."""


def _require(cond, where, what):
    if not cond:
        raise MatrixError("%s: %s" % (where, what))


def _number(value, where, key, minimum=None):
    _require(isinstance(value, (int, float)) and not isinstance(value, bool), where,
             "%r must be a number, got %r" % (key, value))  # fmt: skip
    _require(minimum is None or value >= minimum, where, "%r must be >= %g, got %g" % (key, minimum, value))
    return value


def load(path=DEFAULT_MATRIX):
    """The checked matrix as a dict, with `sequences` (list of dicts, tuning and validation) added.
    Raises MatrixError naming the file and the entry for anything wrong."""
    try:
        with open(path) as f:
            doc = yaml.safe_load(f)
    except OSError as e:
        raise MatrixError("%s: cannot read (%s)" % (path, e.strerror))
    except yaml.YAMLError as e:
        raise MatrixError("%s: not valid YAML (%s)" % (path, str(e).replace("\n", " ")))
    _require(isinstance(doc, dict), path, "expected a mapping at the top level")
    for key in ("duration_s", "sensors", "noise_levels", "scenes", "motions", "cells"):
        _require(key in doc, path, "missing key %r" % key)
    duration = _number(doc["duration_s"], path, "duration_s", 0.5)
    sensors, noises = doc["sensors"], doc["noise_levels"]
    _require(isinstance(sensors, list) and sensors, path, "'sensors' must be a non-empty list")
    _require(isinstance(noises, list) and noises, path, "'noise_levels' must be a non-empty list")
    scenes, motions = doc["scenes"], doc["motions"]
    _require(isinstance(scenes, dict) and scenes, path, "'scenes' must be a mapping name: kind")
    for name, kind in scenes.items():
        _require(kind in SCENE_KINDS, "%s: scene %s" % (path, name),
                 "kind %r is not one of %s" % (kind, ", ".join(SCENE_KINDS)))  # fmt: skip
    _require(isinstance(motions, dict) and motions, path, "'motions' must be a mapping")
    for name, m in motions.items():
        where = "%s: motion %s" % (path, name)
        _require(isinstance(m, dict), where, "expected {preset: NAME, kind: K} or {file: PATH, kind: K}")
        _require(("preset" in m) != ("file" in m), where, "give exactly one of 'preset' and 'file'")
        _require(m.get("kind") in MOTION_KINDS, where, "kind %r is not one of %s" % (m.get("kind"), ", ".join(MOTION_KINDS)))
        if "file" in m:
            _require(os.path.isfile(os.path.join(REPO_DIR, m["file"])), where, "no such file %s" % m["file"])
    cells = doc["cells"]
    _require(isinstance(cells, list) and cells, path, "'cells' must be a non-empty list")
    sequences, seen = [], set()
    for i, cell in enumerate(cells):
        where = "%s: cell %d" % (path, i + 1)
        _require(isinstance(cell, dict), where, "expected a mapping")
        name = cell.get("name")
        _require(isinstance(name, str) and NAME_RE.match(name), where,
                 "'name' must be lower-case letters, digits and '-', got %r" % name)  # fmt: skip
        where = "%s: cell %s" % (path, name)
        _require(name not in seen, where, "the name is used twice")
        seen.add(name)
        unknown = set(cell) - {"name", "sensor", "noise", "scene", "motion", "variants", "duration_s"}
        _require(not unknown, where, "unknown key(s) %s" % ", ".join(sorted(unknown)))
        _require(cell.get("sensor") in sensors, where, "unknown sensor %r (known: %s)" % (cell.get("sensor"), ", ".join(sensors)))
        _require(cell.get("noise") in noises, where, "unknown noise level %r (known: %s)" % (cell.get("noise"), ", ".join(noises)))
        _require(cell.get("scene") in scenes, where, "unknown scene %r (known: %s)" % (cell.get("scene"), ", ".join(scenes)))
        _require(cell.get("motion") in motions, where, "unknown motion %r (known: %s)" % (cell.get("motion"), ", ".join(motions)))
        cell_duration = _number(cell.get("duration_s", duration), where, "duration_s", 0.5)
        variants = cell.get("variants")
        _require(isinstance(variants, list) and len(variants) == 2, where,
                 "'variants' must list exactly two {seed, start} (tuning, validation)")  # fmt: skip
        motion = motions[cell["motion"]]
        for half, variant in zip(HALVES, variants):
            vwhere = "%s, %s variant" % (where, half)
            _require(isinstance(variant, dict) and set(variant) <= {"seed", "start"} and "seed" in variant, vwhere,
                     "expected {seed: N, start: S}")  # fmt: skip
            seed = variant["seed"]
            _require(isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0, vwhere, "'seed' must be an integer >= 0")
            start = _number(variant.get("start", 0), vwhere, "start", 0)
            sequences.append(dict(
                name="%s-%s" % (name, SUFFIX[half]), cell=name, half=half, sensor=cell["sensor"],
                noise=cell["noise"], scene=cell["scene"], scene_kind=scenes[cell["scene"]],
                motion=cell["motion"], motion_kind=motion["kind"],
                motion_arg=motion.get("preset") or motion["file"], motion_is_file="file" in motion,
                seed=seed, start_s=start, duration_s=cell_duration))  # fmt: skip
    doc["sequences"] = sequences
    doc["path"] = path
    return doc


def simulate_args(seq):
    """The `asynevo simulate` arguments of a sequence (without the binary and --out)."""
    motion = os.path.join(REPO_DIR, seq["motion_arg"]) if seq["motion_is_file"] else seq["motion_arg"]
    return ["--sensor", seq["sensor"], "--noise-level", seq["noise"], "--scene", seq["scene"], "--motion", motion,
            "--start", "%g" % seq["start_s"], "--duration", "%g" % seq["duration_s"], "--seed", str(seq["seed"]),
            "--binary", "--no-text"]  # fmt: skip


def binary_names(asynevo):
    """What the binary knows: {"scenes": [...], "motions": [...], "sensors": [...], "noise-levels": [...]},
    from `asynevo simulate --list`."""
    try:
        out = subprocess.run([asynevo, "simulate", "--list"], capture_output=True, text=True, timeout=60)
    except OSError as e:
        raise MatrixError("%s: cannot run (%s); build the project first" % (asynevo, e.strerror))
    if out.returncode != 0:
        raise MatrixError("%s simulate --list failed: %s" % (asynevo, (out.stderr or out.stdout).strip()[:300]))
    names = {}
    for line in out.stdout.splitlines():
        m = re.match(r"^([a-z-]+):\s*(.*)$", line.strip())
        if m:
            names[m.group(1)] = m.group(2).split()
    return names


def check_against_binary(matrix, asynevo):
    """Every sensor, noise level, scene and motion preset the matrix names exists in the binary."""
    names = binary_names(asynevo)
    for key, values in (("sensors", matrix["sensors"]), ("noise-levels", matrix["noise_levels"]),
                        ("scenes", list(matrix["scenes"])),
                        ("motions", [m["preset"] for m in matrix["motions"].values() if "preset" in m])):  # fmt: skip
        known = names.get(key)
        _require(known is not None, asynevo, "'simulate --list' does not list %s" % key)
        for v in values:
            _require(v in known, "%s: %s %s" % (matrix["path"], key.rstrip("s"), v),
                     "not known to %s (it knows: %s)" % (asynevo, " ".join(known)))  # fmt: skip


def select(matrix, half="all"):
    """The sequences of one half ('tuning', 'validation') or of both ('all')."""
    if half not in HALVES + ("all",):
        raise MatrixError("half must be tuning, validation or all, got %r" % half)
    return [s for s in matrix["sequences"] if half == "all" or s["half"] == half]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("command", choices=["check", "list"])
    p.add_argument("--matrix", default=DEFAULT_MATRIX)
    p.add_argument("--asynevo", help="also check the names against this binary")
    p.add_argument("--half", default="all")
    args = p.parse_args()
    try:
        m = load(args.matrix)
        if args.asynevo:
            check_against_binary(m, args.asynevo)
        seqs = select(m, args.half)
    except MatrixError as e:
        print("matrix: error: %s" % e, file=sys.stderr)
        return 1
    if args.command == "check":
        print("%s: %d cells, %d sequences (%d tuning, %d validation)" % (
            args.matrix, len(m["cells"]), len(m["sequences"]), len(select(m, "tuning")), len(select(m, "validation"))))  # fmt: skip
    else:
        for s in seqs:
            print("%-28s %-10s %s" % (s["name"], s["half"], " ".join(simulate_args(s))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
