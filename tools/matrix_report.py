#!/usr/bin/python3
"""The evaluation matrix's report (docs/evaluation_matrix.md): per-sequence table, the median and worst
per half and per factor (sensor, noise level, scene kind, motion kind), and one figure of the
distributions. Failed runs stay in every table: they count as the worst value of every figure.

  matrix_report.py --matrix FILE --runs OUT/runs/NAME --name NAME --out REPORT.md [--half H]
                   [--config FILE] [--docs docs/results/matrix.md --docs-images docs/images/matrix]

Writes REPORT.md, results.json and distributions.png beside it. With --docs, the section between
`<!-- matrix:begin -->` and `<!-- matrix:end -->` of that file is replaced by the report and the figure
is copied to --docs-images. Needs Debian's python3-numpy, python3-matplotlib and python3-yaml.
"""

import argparse
import datetime
import json
import math
import os
import shutil
import subprocess
import sys

TOOLS_DIR = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TOOLS_DIR)
import matrix as matrix_lib  # noqa: E402
from matrix_run import read_json  # noqa: E402
from plot_run import save  # noqa: E402  (selects matplotlib's Agg backend, hints at missing packages)
import matplotlib.pyplot as plt  # noqa: E402

# A run whose median direction of travel is further than this from the truth's is counted apart: its
# ATE can look fine while its camera moves backwards or sideways through its map (a failed run counts).
MISDIRECTED_DEG = 30.0
BEGIN_MARKER = "<!-- matrix:begin -->"
END_MARKER = "<!-- matrix:end -->"
FACTORS = [("sensor", "sensor"), ("noise", "noise level"), ("scene_kind", "scene"), ("motion_kind", "motion")]
# figure -> (label, unit, higher is better)
METRICS = {
    "ate_pct": ("ATE", "% of path", False),
    "rte10_pct": ("RTE@10 %", "% ", False),
    "vel_pct": ("velocity", "% of speed", False),
    "direction_deg": ("direction", "deg", False),
    "init_s": ("init", "s", False),
    "coverage_pct": ("coverage", "%", True),
    "coverage_onset_pct": ("coverage after onset", "%", True),
}


def rows_of(matrix, half, runs_dir):
    """One row per sequence of the matrix: its factors and its score (status 'missing' when the run
    left no score)."""
    rows = []
    for seq in matrix_lib.select(matrix, half):
        score = read_json(os.path.join(runs_dir, seq["name"], "score.json"))
        row = dict(seq)
        if score is None:
            row.update(status="missing", message="no score.json (the run did not finish)")
        else:
            row.update(score)
        row["coverage_pct"] = 100.0 * row["coverage"] if row.get("coverage") is not None else 0.0
        after = row.get("coverage_after_onset")
        row["coverage_onset_pct"] = 100.0 * after if after is not None else row["coverage_pct"]
        rows.append(row)
    return rows


def value(row, key):
    """A figure of a row for ranking: a failed or missing figure is the worst possible."""
    _, _, higher_better = METRICS[key]
    v = row.get(key) if row.get("status") == "ok" or key in ("coverage_pct", "coverage_onset_pct") else None
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return -math.inf if higher_better else math.inf
    return float(v)


def median(values):
    v = sorted(values)
    if not v:
        return None
    n = len(v)
    if n % 2:
        return v[n // 2]
    a, b = v[n // 2 - 1], v[n // 2]
    if math.isinf(a) or math.isinf(b):
        return a if math.isinf(a) else b
    return 0.5 * (a + b)


def summarize(rows):
    """{metric: (median, worst)} and counts over rows."""
    out = dict(n=len(rows), failed=sum(1 for r in rows if r.get("status") != "ok"),
               above2=sum(1 for r in rows if value(r, "ate_pct") > 2.0),
               misdirected=sum(1 for r in rows if value(r, "direction_deg") > MISDIRECTED_DEG))
    for key, (_, _, higher_better) in METRICS.items():
        vals = [value(r, key) for r in rows]
        worst = (min(vals) if higher_better else max(vals)) if vals else None
        out[key] = dict(median=median(vals), worst=worst)
    return out


def cell(x, digits=2):
    if x is None:
        return "–"
    if isinstance(x, float) and math.isinf(x):
        return "failed"
    return "%.*f" % (digits, x)


def summary_table(groups):
    """Markdown table: one row per (label, summary)."""
    head = ("| | runs | failed | ATE > 2 %% or failed | direction > %g° or failed | " % MISDIRECTED_DEG
            + " | ".join("%s median / worst" % METRICS[k][0] for k in METRICS) + " |")
    lines = [head, "|---|---|---|---|---|" + "---|" * len(METRICS)]
    for label, s in groups:
        cells = []
        for k in METRICS:
            d = 1 if k in ("rte10_pct", "vel_pct", "direction_deg", "coverage_pct", "coverage_onset_pct") else 2
            cells.append("%s / %s" % (cell(s[k]["median"], d), cell(s[k]["worst"], d)))
        lines.append("| %s | %d | %d | %d | %d | %s |" % (label, s["n"], s["failed"], s["above2"], s["misdirected"],
                                                          " | ".join(cells)))
    return "\n".join(lines)


def features(r):
    """Active features: mean over event time, and the median over it where the run recorded it."""
    mean = cell(r.get("mean_active_features"), 0)
    median = r.get("median_active_features")
    return mean if median is None else "%s / %d" % (mean, median)


def sequence_table(rows):
    lines = ["| sequence | half | sensor | noise | scene | motion | status | ATE % | RTE@10 % | vel % | direction ° (reversed %) | "
             "init s (attempts) | init after onset s | coverage % (after onset) | segments | features mean / median | note |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in rows:
        ok = r.get("status") == "ok"
        init = "%s (%s)" % (cell(r.get("init_s")), r.get("init_attempts", "–")) if r.get("init_s") is not None else \
            "never (%s)" % r.get("init_attempts", "–")  # fmt: skip
        ends = r.get("segment_ends") or []
        segments = "%s (%s)" % (r["segments"], ", ".join(ends)) if ends else cell(r.get("segments"), 0)
        direction = "%s (%s)" % (cell(r.get("direction_deg"), 1), cell(r.get("reversed_pct"), 0)) if ok else "–"
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["name"], r["half"], r["sensor"], r["noise"], r["scene"], r["motion"], r.get("status"),
            cell(r.get("ate_pct")) if ok else "–", cell(r.get("rte10_pct"), 1) if ok else "–",
            cell(r.get("vel_pct"), 1) if ok else "–", direction, init, cell(r.get("init_after_onset_s")),
            "%s (%s)" % (cell(r.get("coverage_pct"), 1), cell(r.get("coverage_onset_pct"), 1)), segments, features(r),
            (r.get("message") or "").replace("|", "/")[:160]))  # fmt: skip
    return "\n".join(lines)


def figure(rows, path):
    """ATE per sequence against each factor; tuning and validation apart; failures on top."""
    fig, axes = plt.subplots(1, len(FACTORS), figsize=(4.2 * len(FACTORS), 4.2), sharey=True)
    finite = [value(r, "ate_pct") for r in rows if math.isfinite(value(r, "ate_pct"))]
    top = max(finite + [1.0]) * 2.0
    for ax, (key, label) in zip(axes, FACTORS):
        levels = sorted({r[key] for r in rows})
        for half, marker, color, dx in (("tuning", "x", "tab:gray", -0.12), ("validation", "o", "tab:blue", 0.12)):
            xs, ys, fx = [], [], []
            for r in rows:
                if r["half"] != half:
                    continue
                v = value(r, "ate_pct")
                (xs if math.isfinite(v) else fx).append(levels.index(r[key]) + dx)
                if math.isfinite(v):
                    ys.append(v)
            ax.scatter(xs, ys, marker=marker, color=color, label=half if key == "sensor" else None)
            ax.scatter(fx, [top] * len(fx), marker="v", color="tab:red",
                       label="failed" if key == "sensor" and half == "validation" else None)  # fmt: skip
        ax.set_xticks(range(len(levels)))
        ax.set_xticklabels(levels, rotation=30, ha="right")
        ax.set_title(label)
        ax.set_yscale("log")
        ax.grid(True, axis="y", alpha=0.3)
    axes[0].set_ylabel("ATE, % of the evaluated path (log); failures at the top")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    save(fig, os.path.dirname(path), os.path.basename(path))


def git_commit():
    try:
        out = subprocess.run(["git", "-C", TOOLS_DIR, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
        dirty = subprocess.run(["git", "-C", TOOLS_DIR, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.strip()  # fmt: skip
        return out.stdout.strip() + ("+changes" if dirty else "")
    except OSError:
        return "unknown"


def report(matrix, rows, args, figure_name):
    halves = [h for h in matrix_lib.HALVES if any(r["half"] == h for r in rows)]
    main_half = "validation" if "validation" in halves else halves[0]
    main_rows = [r for r in rows if r["half"] == main_half]
    md = ["### Evaluation matrix: `%s`" % args.name, "",
          "Setting `%s` (configuration `%s`), commit %s, %s. %d sequences of %s (%d cells, %s)." % (
              args.name, args.config or "–", git_commit(), datetime.date.today().isoformat(), len(rows),
              os.path.relpath(matrix["path"], matrix_lib.REPO_DIR), len(matrix["cells"]), ", ".join(halves)),
          "",
          "ATE: RMSE after Sim(3) alignment in % of the evaluated ground-truth path; RTE@10 %: mean relative "
          "translation error over sub-trajectories of 10 % of the path; velocity: RMSE of the body velocity in % "
          "of the mean speed; direction: median angle between the estimated and the true direction of travel "
          "(body frame, where the camera moves; reversed: share of knots above 90°), which the ATE does not see; init: event time from the start of the sequence to the first successful "
          "initialization; coverage: share of the sequence with an estimate (after onset: of the part from the "
          "motion onset on, since a monocular start needs motion). A failed run is the worst value "
          "of every figure ('failed').", "",
          "**Per half**", "",
          summary_table([(h, summarize([r for r in rows if r["half"] == h])) for h in halves]), ""]  # fmt: skip
    for key, label in FACTORS:
        levels = sorted({r[key] for r in main_rows})
        md += ["**By %s (%s half)**" % (label, main_half), "",
               summary_table([(lv, summarize([r for r in main_rows if r[key] == lv])) for lv in levels]), ""]  # fmt: skip
    md += ["![ATE distributions](%s)" % figure_name, "", "**Every sequence**", "", sequence_table(rows), ""]
    return "\n".join(md)


def replace_section(path, text):
    with open(path) as f:
        doc = f.read()
    a, b = doc.find(BEGIN_MARKER), doc.find(END_MARKER)
    if a < 0 or b < a:
        raise SystemExit("%s: no %s ... %s section to replace" % (path, BEGIN_MARKER, END_MARKER))
    doc = doc[: a + len(BEGIN_MARKER)] + "\n" + text + "\n" + doc[b:]
    with open(path, "w") as f:
        f.write(doc)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--matrix", default=matrix_lib.DEFAULT_MATRIX)
    p.add_argument("--runs", required=True, help="folder with SEQ/score.json per sequence")
    p.add_argument("--name", required=True)
    p.add_argument("--out", required=True, help="report file (Markdown); results.json and the figure go beside it")
    p.add_argument("--half", default="all")
    p.add_argument("--config", default="")
    p.add_argument("--docs", help="also replace the matrix section of this Markdown file")
    p.add_argument("--docs-images", default="docs/images/matrix")
    args = p.parse_args()
    try:
        matrix = matrix_lib.load(args.matrix)
        rows = rows_of(matrix, args.half, args.runs)
    except matrix_lib.MatrixError as e:
        print("matrix_report: error: %s" % e, file=sys.stderr)
        return 1
    out_dir = os.path.dirname(os.path.abspath(args.out))
    os.makedirs(out_dir, exist_ok=True)
    fig_path = os.path.join(out_dir, "distributions.png")
    figure(rows, fig_path)
    summary = {h: summarize([r for r in rows if r["half"] == h]) for h in matrix_lib.HALVES}
    with open(os.path.join(out_dir, "results.json"), "w") as f:
        json.dump(dict(name=args.name, config=args.config, commit=git_commit(), rows=rows, summary=summary), f,
                  indent=1, sort_keys=True, default=str)  # fmt: skip
        f.write("\n")
    with open(args.out, "w") as f:
        f.write(report(matrix, rows, args, "distributions.png") + "\n")
    if args.docs:
        os.makedirs(args.docs_images, exist_ok=True)
        target = os.path.join(args.docs_images, "%s_distributions.png" % args.name)
        shutil.copyfile(fig_path, target)
        rel = os.path.relpath(target, os.path.dirname(os.path.abspath(args.docs)))
        replace_section(args.docs, report(matrix, rows, args, rel))
    print("wrote %s (%d sequences, %d not ok)" % (args.out, len(rows), sum(1 for r in rows if r.get("status") != "ok")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
