#!/usr/bin/python3
"""tools/matrix_offsets.py on synthetic score.json files: per-sequence medians over offsets, the half's
median of them, failed runs as infinitely bad, the comparison with a reference."""

import contextlib
import io
import json
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import matrix_offsets  # noqa: E402

failures = []


def check(condition, what):
    print(("ok      " if condition else "FAILED  ") + what)
    if not condition:
        failures.append(what)


def write_runs(root, name, ates, coverage=None):
    """ates: {sequence: ATE or None (a failed run)}; coverage: {sequence: share} where given."""
    for seq, ate in ates.items():
        os.makedirs(os.path.join(root, name, seq))
        score = dict(status="failed", message="never started") if ate is None else dict(status="ok", ate_pct=ate)
        if coverage and seq in coverage and ate is not None:
            score["coverage"] = coverage[seq]
        with open(os.path.join(root, name, seq, "score.json"), "w") as f:
            json.dump(score, f)


with tempfile.TemporaryDirectory() as root:
    # Three offsets of a reference: a-val 1, 5, 2 (median 2); b-val 3, 3, 4 (3); c-val 1, failed, 1 (1);
    # x-tune 0.5 at each offset.
    write_runs(root, "ref0", {"a-val": 1.0, "b-val": 3.0, "c-val": 1.0, "x-tune": 0.5})
    write_runs(root, "ref50", {"a-val": 5.0, "b-val": 3.0, "c-val": None, "x-tune": 0.5})
    write_runs(root, "ref100", {"a-val": 2.0, "b-val": 4.0, "c-val": 1.0, "x-tune": 0.5, "only-val": 9.0})
    dirs = [os.path.join(root, n) for n in ("ref0", "ref50", "ref100")]
    data = matrix_offsets.load_setting(dirs, "ate_pct")
    check(sorted(data) == ["a-val", "b-val", "c-val", "x-tune"], "only sequences every offset has are kept")
    check(math.isinf(data["c-val"][1]), "a failed run counts as infinitely bad")
    summary = matrix_offsets.summarize(data)
    runs, med, per_offset = summary["validation"]
    check(runs == 3 and med == 2.0, "validation: the median of the per-sequence medians (2, 3, 1) is 2")
    check(per_offset == [1.0, 5.0, 2.0], "validation: the half's median at each offset (1, 5, 2)")
    check(summary["tuning"][1] == 0.5, "tuning half kept apart")
    # A setting better on a-val and worse on b-val, printed against the reference.
    write_runs(root, "new0", {"a-val": 1.0, "b-val": 6.0, "c-val": 1.0})
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = matrix_offsets.main(["ref=" + ",".join(dirs), "new=" + os.path.join(root, "new0"), "--sequences"])
    text = out.getvalue()
    check(code == 0, "the command exits 0")
    check("validation against ref: 1 sequences better, 1 worse" in text,
          "the comparison counts better and worse sequences")
    check("a-val" in text and "median 2.00" in text, "--sequences prints each sequence's median")

    # Coverage: higher is better, and a failed run is the worst (no coverage at all).
    write_runs(root, "cov_ref", {"a-val": 1.0, "b-val": 1.0, "c-val": 1.0}, {"a-val": 0.9, "b-val": 0.9, "c-val": 0.9})
    write_runs(root, "cov_new", {"a-val": 1.0, "b-val": 1.0, "c-val": None}, {"a-val": 0.95, "b-val": 0.8})
    cov = matrix_offsets.load_setting([os.path.join(root, "cov_new")], "coverage")
    check(cov["c-val"] == [-math.inf], "coverage: a failed run counts as minus infinity")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        matrix_offsets.main(["ref=" + os.path.join(root, "cov_ref"), "new=" + os.path.join(root, "cov_new"),
                             "--metric", "coverage"])
    check("validation against ref: 1 sequences better, 2 worse" in out.getvalue(),
          "coverage: more is better (a-val), less and a failed run are worse (b-val, c-val)")

sys.exit(1 if failures else 0)
