#!/usr/bin/python3
"""tools/reversal_truth.py on a synthetic run: which of a motion and its depth-reversed alternative is
nearer the ground truth, binned by their costs; malformed logs named with their line."""

import contextlib
import io
import os
import subprocess
import sys
import tempfile

tools = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools")
sys.path.insert(0, tools)
import reversal_truth  # noqa: E402

failures = []


def check(condition, what):
    print(("ok      " if condition else "FAILED  ") + what)
    if not condition:
        failures.append(what)


HEADER = "# t_a_s t_b_s method features parallax_px cost reversed_cost tx ty tz rx ry rz decision\n"

with tempfile.TemporaryDirectory() as root:
    # The camera moves along +x of the world without turning: from the first view to the second the
    # points move along -x, so the true t_b_a is (-1, 0, 0).
    seq = os.path.join(root, "sequences", "s-val")
    os.makedirs(seq)
    with open(os.path.join(seq, "groundtruth.txt"), "w") as f:
        f.write("# t px py pz qx qy qz qw\n")
        for k in range(101):
            f.write("%.2f %.3f 0 0 0 0 0 1\n" % (k * 0.01, 0.5 * k * 0.01))
    run = os.path.join(root, "runs", "s-val", "run")
    os.makedirs(run)
    with open(os.path.join(run, "init_reversals.txt"), "w") as f:
        f.write(HEADER)
        # right, alternative dearer by x2: the cheaper (the motion) is nearer
        f.write("0.1 0.3 two-view 20 0 1.0 2.0 -1 0 0 1 0 0 kept\n")
        # wrong, alternative cheaper by x1.5 and right: the cheaper (the alternative) is nearer
        f.write("0.2 0.4 two-view 20 0 3.0 2.0 1 0.1 0 -1 0 0 reversed\n")
        # right, alternative cheaper by x1.11 but wrong: the cheaper is not the nearer
        f.write("0.3 0.5 multi-view 40 0 1.0 0.9 -1 0 0.1 1 0 0 kept\n")
        # no alternative found: not counted
        f.write("0.3 0.5 two-view 20 0 1.0 0 -1 0 0 0 0 0 kept\n")
        # an audit of a window travelling in reverse, the alternative (right) cheaper by x2
        f.write("0.5 0.7 audit 30 12.5 3.0 1.5 1 0 0 -1 0 0 against\n")
    samples = reversal_truth.collect([os.path.join(root, "runs")], os.path.join(root, "sequences"))
    check(len(samples) == 4, "four comparisons with an alternative (got %d)" % len(samples))
    by_ratio = sorted(samples, key=lambda s: s[2])
    check([s[3] for s in by_ratio] == [True, False, True, True],
          "the cheaper is nearer at x0.5, x1.5 and x2, not at x1.11 (got %s)" % [s[3] for s in by_ratio])
    check([s[4] for s in by_ratio] == [False, False, True, True], "the alternative is nearer only at x1.5 and x2")
    check(all(s[0] == "validation" for s in samples), "a -val sequence counts as validation")
    text = "\n".join(reversal_truth.table(samples))
    check("validation, two-view: 2 comparisons" in text and "validation, multi-view: 1 comparisons" in text
          and "validation, audit: 1 comparisons" in text,
          "the table counts per method:\n" + text)
    check("0.00-0.80:    1; the cheaper nearer the truth    1 (100 %)" in text, "the x0.5 comparison in the first bin")
    # A malformed line is named with its file and line, and the tool exits non-zero.
    with open(os.path.join(run, "init_reversals.txt"), "a") as f:
        f.write("0.4 0.6 two-view 20 0 1.0 nan -1 0 0 1 0 0 kept\n")
    result = subprocess.run([sys.executable, os.path.join(tools, "reversal_truth.py"), "--sequences",
                             os.path.join(root, "sequences"), os.path.join(root, "runs")],
                            capture_output=True, text=True)
    check(result.returncode != 0 and "init_reversals.txt line 7" in result.stderr,
          "a non-finite cost is an error naming the line (got %d: %s)" % (result.returncode, result.stderr.strip()))

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
