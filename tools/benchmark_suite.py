#!/usr/bin/python3
"""Benchmark suite report: AsynEVO's sliding window vs the full-history smoother baselines (issues 7 and 8).

workflow/baselines.smk simulates the sequences (exact ground truth), runs every backend on each with
`asynevo run --backend B` and evaluates the estimate and its velocities with `asynevo eval --align
sim3` (tools/baseline_run.py; rpg_trajectory_evaluation definitions, body-velocity error after the
Sim(3) scale). This script is its report step: it reads what the workflow wrote into OUT

  OUT/sequences/SEQ/                   'asynevo simulate' output (sim.yaml, groundtruth.txt)
  OUT/runs/SEQ/BACKEND/                'asynevo run' folder + eval.json
  OUT/runs/SEQ/BACKEND.json            the run's status (ok / failed / timeout, with its message)

and writes

  OUT/results.json     every number below, machine-readable
  OUT/results.md       accuracy table, runtime table, time ratios and their growth, figures, targets
  OUT/figures/*.png    runtime over event time, runtime box plots, window size over time, trajectories

With --docs FILE the generated section of FILE (between `<!-- results:begin -->` and
`<!-- results:end -->`) is replaced by the same fragment and the PNGs are copied to --docs-images.
Run alone, it redraws the report from the runs OUT holds without running anything. A run that failed
or was stopped by the workflow's run_timeout_s stays in every table with its message; a requested run
without a status file is left out (and named on the console).

Needs Debian's python3-numpy, python3-matplotlib and python3-yaml; run with /usr/bin/python3.
"""

import argparse
import datetime
import json
import os
import platform
import re
import shlex
import shutil
import subprocess
import sys

TOOLS_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(TOOLS_DIR)

sys.path.insert(0, TOOLS_DIR)
# plot_run selects matplotlib's Agg backend, and exits with an installation hint when Debian's
# python3-numpy / python3-matplotlib are missing.
from plot_run import load_table, save  # noqa: E402
import numpy as np  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
from matrix_run import read_json  # noqa: E402
from baseline_run import BACKENDS, BaselineError, load_sequences, select_backends, select_sequences  # noqa: E402

BEGIN_MARKER = "<!-- results:begin -->"
END_MARKER = "<!-- results:end -->"

# Sequences: workflow/baselines.yaml (name -> scene, motion, seed, duration, default, about).
BACKEND_LABELS = {
    "window": "AsynEVO (window)",
    "incremental": "full-history smoother (A)",
    "incremental-frozen": "frozen-history smoother (B)",
}
BACKEND_COLORS = {"window": "tab:blue", "incremental": "tab:red", "incremental-frozen": "tab:orange"}

# Issue 7 targets.
TARGET_ATE_PERC = 1.0
TARGET_RTE10_PERC = 2.0
TARGET_VEL_PERC = 10.0
TARGET_RTF = 1.0


# ----------------------------------------------------------------------------- small helpers


def log(msg):
    print("[benchmark] " + msg, flush=True)


def write_json(path, obj):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(obj, f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(tmp, path)


def fmt(x, digits=2):
    """A number for a table cell; '–' for missing."""
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "–"
    if isinstance(x, int):
        return str(x)
    if abs(x) >= 1000:
        return "%.0f" % x
    return "%.*f" % (digits, x)


def mark(value, target):
    if value is None:
        return "–"
    return "met" if value <= target else "**missed**"


# ----------------------------------------------------------------------------- sequences and runs


def sequence_info(out, name, spec):
    """What the report says about a simulated sequence: its table entry, the duration, event count and
    ground-truth path length of the folder the workflow simulated, and the simulation's wall time."""
    seq_dir = os.path.join(out, "sequences", name)
    info = dict(name=name, dir=seq_dir, scene=spec["scene"], motion=spec["motion"], duration_s=spec["duration"],
                seed=spec["seed"], about=spec.get("about", ""))  # fmt: skip
    gt = load_table(os.path.join(seq_dir, "groundtruth.txt"), 8)
    info["gt_path_length_m"] = float(np.linalg.norm(np.diff(gt[:, 1:4], axis=0), axis=1).sum()) if gt is not None else None
    info["events"] = None
    try:
        with open(os.path.join(seq_dir, "sim.yaml")) as f:
            text = f.read()
        m = re.search(r"^\s+events:\s*([0-9]+)\s*$", text, re.MULTILINE)
        info["events"] = int(m.group(1)) if m else None
        b = re.search(r"^begin_s:\s*([-0-9.eE+]+)\s*$", text, re.MULTILINE)
        e = re.search(r"^end_s:\s*([-0-9.eE+]+)\s*$", text, re.MULTILINE)
        if b and e:  # the duration simulated (the workflow's `duration` may have replaced the table's)
            info["duration_s"] = round(float(e.group(1)) - float(b.group(1)), 6)
    except OSError:
        pass
    info["simulate_wall_s"] = None
    try:  # Snakemake's benchmark file of the simulate job: a header line, then "s h:m:s ..."
        with open(os.path.join(out, "logs", "simulate", name + ".benchmark.tsv")) as f:
            info["simulate_wall_s"] = round(float(f.read().splitlines()[1].split("\t")[0]), 1)
    except (OSError, IndexError, ValueError):
        pass
    return info


def load_run(out, seq, backend):
    """The record of one run (tools/baseline_run.py's status file, its run folder's stats.json,
    eval.json and timing.csv, and the summary of them), or None when the run has no status file."""
    run_dir = os.path.join(out, "runs", seq["name"], backend)
    rec = read_json(os.path.join(out, "runs", seq["name"], backend + ".json"))
    if rec is None:
        return None
    rec = dict(rec)
    rec["run_dir"] = run_dir
    rec["stats"] = read_json(os.path.join(run_dir, "stats.json"))
    rec["eval"] = read_json(os.path.join(run_dir, "eval.json")) if rec["status"] == "ok" else None
    rec["timing"] = load_timing(os.path.join(run_dir, "timing.csv"))
    rec["summary"] = summarize_run(rec, seq)
    if rec["status"] == "timeout":
        rec["message"] = timeout_message(rec, seq)
    return rec


def timeout_message(rec, seq):
    """What a stopped run's table cells say: the limit, and how far in event time its timing.csv got."""
    msg = rec.get("message") or "stopped by its time limit (run_timeout_s)"
    reached = rec["summary"].get("event_time_reached_s")
    if reached is None:
        return msg + ", before its first backend update (no timing rows)"
    return msg + " at event time %.1f s of the %g s sequence (runtime figures cover its %d updates up to there)" % (
        reached, seq["duration_s"], rec["summary"].get("updates", 0))


# ----------------------------------------------------------------------------- metrics


def load_timing(path):
    """dict column -> array from timing.csv, or None. Rows with the wrong number of fields or
    non-numbers are skipped (a run stopped by its time limit can leave a truncated last line)."""
    if not os.path.isfile(path):
        return None
    header, rows = None, []
    with open(path) as f:
        for line in f:
            fields = [v.strip() for v in line.strip().split(",")]
            if header is None:
                header = fields
                continue
            if len(fields) != len(header):
                continue
            try:
                rows.append([float(v) for v in fields])
            except ValueError:
                continue
    if header is None or not rows:
        return None
    data = np.array(rows)
    return {h: data[:, k] for k, h in enumerate(header)}


def velocity_summary(ev):
    """The body-velocity error of eval.json's "velocity" entry (asynevo eval: linear part times the
    Sim(3) scale against the ground truth's central differences; docs/evaluation.md), or the reason
    it is missing."""
    v = (ev or {}).get("velocity")
    if not v:
        return dict(velocity_error="eval.json has no velocity entry (no velocities.txt?)")
    if not v.get("samples"):
        return dict(velocity_error="no velocity inside the ground-truth span", velocity_samples=0)
    return dict(
        velocity_samples=v["samples"],
        vel_rmse_mps=v["linear_mps"]["rmse"],
        mean_speed_mps=v["mean_gt_speed_mps"],
        vel_rmse_perc=v["linear_rmse_perc_of_mean_speed"],
        omega_rmse_dps=v["angular_dps"]["rmse"],
        omega_rmse_perc=v["angular_rmse_perc_of_mean_rate"],
    )


def quarter_medians(t, x, span=None):
    """Medians of x over the four quarters of the event-time span (default: t's own) (None for an
    empty quarter)."""
    if t is None or len(t) == 0:
        return [None] * 4
    edges = np.linspace(*(span or (t[0], t[-1])), 5)
    out = []
    for k in range(4):
        sel = (t >= edges[k]) & ((t < edges[k + 1]) if k < 3 else (t <= edges[k + 1]))
        out.append(float(np.median(x[sel])) if np.any(sel) else None)
    return out


def summarize_run(rec, seq):
    s = {}
    tm = rec["timing"]
    if tm is not None and "total_ms" in tm and len(tm["total_ms"]):
        t, ms = tm["t_s"] if "t_s" in tm else tm[next(iter(tm))], tm["total_ms"]
        s["updates"] = int(len(ms))
        s["update_median_ms"] = float(np.median(ms))
        s["update_p95_ms"] = float(np.percentile(ms, 95))
        s["update_max_ms"] = float(np.max(ms))
        s["backend_total_s"] = float(np.sum(ms) / 1000)
        s["event_time_reached_s"] = float(t[-1])
        q = quarter_medians(t, ms)
        s["quarter_median_ms"] = q
        s["growth_q4_over_q1"] = q[3] / q[0] if q[0] and q[3] is not None else None
        if len(t) >= 3 and np.ptp(t) > 0:
            s["slope_ms_per_s"] = float(np.polyfit(t - t[0], ms, 1)[0])
        if "window_knots" in tm:
            s["window_knots_max"] = int(np.max(tm["window_knots"]))
            s["window_knots_median"] = float(np.median(tm["window_knots"]))
    st = rec.get("stats") or {}
    for key in ("wall_time_s", "real_time_factor", "peak_memory_mb", "event_time_span_s", "knots", "initialized"):
        if key in st:
            s[key] = st[key]
    ev = rec.get("eval")
    if ev:
        L = ev.get("gt_path_length_m")
        s["path_length_m"] = L
        s["scale"] = ev["alignment"]["scale"]
        s["ate_rmse_m"] = ev["ate"]["trans_m"].get("rmse")
        s["ate_perc"] = 100 * s["ate_rmse_m"] / L if L else None
        s["ate_rot_rmse_deg"] = ev["ate"]["rot_deg"].get("rmse")
        s["rte"] = [
            dict(length_m=e["length_m"], trans_perc_mean=e["trans_perc"].get("mean"),
                 rot_deg_mean=e["rot_deg"].get("mean"), samples=e["num_samples"])
            for e in ev["relative_error"]["per_length"]
        ]  # fmt: skip
        s["rte10_perc"] = s["rte"][0]["trans_perc_mean"] if s["rte"] else None
        s["rte_pooled_perc"] = ev["relative_error"]["pooled"]["trans_perc"].get("mean")
        s["rte_pooled_rot_deg"] = ev["relative_error"]["pooled"]["rot_deg"].get("mean")
        a = ev["association"]
        span_gt = a["gt_time_s"][1] - a["gt_time_s"][0]
        s["coverage_perc"] = 100 * (a["est_time_s"][1] - a["est_time_s"][0]) / span_gt if span_gt > 0 else None
        s.update(velocity_summary(ev))
        est = load_table(os.path.join(rec["run_dir"], "stamped_traj_estimate.txt"), 8)
        if est is not None and len(est) > 1:
            s["max_gap_s"] = float(np.max(np.diff(est[:, 0])))
            s["nonfinite_poses"] = int(np.sum(~np.all(np.isfinite(est[:, 1:8]), axis=1)))
    return s


# ----------------------------------------------------------------------------- figures


def legend(ax, **kw):
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kw)
    else:
        ax.text(0.5, 0.5, "no data (no run got this far: see the tables)", transform=ax.transAxes, ha="center", va="center", color="grey")


def save_fig(fig, fig_dir, name):
    return save(fig, fig_dir, name, dpi=80)


def runs_of(results, seq_name):
    return [r for r in results if r["sequence"] == seq_name]


def plot_timing_series(seqs, results, fig_dir, column, ylabel, name, **style):
    """One panel per sequence: a timing.csv column over event time, one line per backend (log y)."""
    fig, axes = plt.subplots(len(seqs), 1, figsize=(8, 2.3 * len(seqs) + 0.4), squeeze=False)
    for ax, seq in zip(axes[:, 0], seqs):
        for r in runs_of(results, seq["name"]):
            tm = r["timing"]
            if tm is None or column not in tm:
                continue
            label = BACKEND_LABELS[r["backend"]] + ("" if r["status"] == "ok" else " (%s)" % r["status"])
            ax.plot(tm["t_s"], tm[column], color=BACKEND_COLORS[r["backend"]], label=label, **style)
        ax.set_yscale("log")
        ax.set_title(seq["name"], fontsize=9)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        legend(ax, fontsize=7, loc="upper left")
    axes[-1, 0].set_xlabel("event time [s]")
    fig.tight_layout()
    return save_fig(fig, fig_dir, name)


def plot_runtime_boxes(seqs, results, fig_dir):
    fig, axes = plt.subplots(1, len(seqs), figsize=(2.9 * len(seqs) + 0.6, 3.4), squeeze=False)
    for ax, seq in zip(axes[0], seqs):
        data, labels, colors = [], [], []
        for r in runs_of(results, seq["name"]):
            tm = r["timing"]
            if tm is None or "total_ms" not in tm or not len(tm["total_ms"]):
                continue
            data.append(tm["total_ms"])
            labels.append({"window": "window", "incremental": "full (A)", "incremental-frozen": "frozen (B)"}[r["backend"]])
            colors.append(BACKEND_COLORS[r["backend"]])
        if data:
            bp = ax.boxplot(data, showfliers=False, patch_artist=True, widths=0.6)
            ax.set_xticks(range(1, len(labels) + 1))
            ax.set_xticklabels(labels, fontsize=8)
            for patch, c in zip(bp["boxes"], colors):
                patch.set_facecolor(c)
                patch.set_alpha(0.5)
        ax.set_yscale("log")
        ax.set_title(seq["name"], fontsize=9)
        ax.grid(True, which="both", axis="y", alpha=0.3)
    axes[0, 0].set_ylabel("ms per update (whiskers 1.5 IQR)")
    fig.tight_layout()
    return save_fig(fig, fig_dir, "runtime_boxplots.png")


def plot_trajectories(seqs, results, fig_dir):
    fig, axes = plt.subplots(1, len(seqs), figsize=(3.2 * len(seqs) + 0.4, 3.4), squeeze=False)
    for ax, seq in zip(axes[0], seqs):
        drawn_gt = False
        for r in runs_of(results, seq["name"]):
            if r["status"] != "ok" or not r["eval"]:
                continue
            gt = load_table(os.path.join(r["run_dir"], "stamped_groundtruth.txt"), 8)
            est = load_table(os.path.join(r["run_dir"], "stamped_traj_estimate.txt"), 8)
            if gt is None or est is None:
                continue
            if not drawn_gt:
                ax.plot(gt[:, 1], gt[:, 2], "k-", lw=1.2, label="ground truth")
                drawn_gt = True
            a = r["eval"]["alignment"]
            p = a["scale"] * est[:, 1:4] @ np.array(a["rotation"]).T + np.array(a["translation"])
            ax.plot(p[:, 0], p[:, 1], lw=0.8, color=BACKEND_COLORS[r["backend"]], label=BACKEND_LABELS[r["backend"]])
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(seq["name"] + " (top view, Sim(3))", fontsize=9)
        ax.set_xlabel("x [m]")
        ax.grid(True, alpha=0.3)
        legend(ax, fontsize=6)
    axes[0, 0].set_ylabel("y [m]")
    fig.tight_layout()
    return save_fig(fig, fig_dir, "trajectories.png")


# ----------------------------------------------------------------------------- report


def md_table(head, rows):
    """A markdown table; short rows are filled with '–'."""
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for cells in rows:
        lines.append("| " + " | ".join(list(cells) + ["–"] * (len(head) - len(cells))) + " |")
    return "\n".join(lines)


def rte_lengths(results):
    """The number of relative-error lengths to tabulate (the toolbox's 10..50 %)."""
    n = 0
    for r in results:
        n = max(n, len(r["summary"].get("rte", [])))
    return n


def accuracy_table(seqs, results):
    n_len = rte_lengths(results)
    pct = ["%d %%" % (10 * (k + 1)) for k in range(n_len)]
    head = ["sequence", "backend", "status", "path m", "ATE m", "ATE % path"]
    head += ["RTE @%s %%" % p.replace(" %", "") for p in pct]
    head += ["RTE rot ° (pooled mean)", "vel RMSE % mean speed", "ω RMSE °/s", "scale", "coverage %", "max gap s"]
    rows = []
    for seq in seqs:
        for r in runs_of(results, seq["name"]):
            s = r["summary"]
            if r["status"] != "ok":
                msg = r.get("message", "").replace("|", "/")
                rows.append([seq["name"], r["backend"], "**%s**: %s" % (r["status"], msg)])
                continue
            rte = s.get("rte", [])
            cells = [seq["name"], r["backend"], "ok", fmt(s.get("path_length_m")), fmt(s.get("ate_rmse_m"), 3),
                     fmt(s.get("ate_perc"))]  # fmt: skip
            for k in range(n_len):
                cells.append(fmt(rte[k]["trans_perc_mean"], 1) if k < len(rte) else "–")
            cells += [fmt(s.get("rte_pooled_rot_deg")), fmt(s.get("vel_rmse_perc"), 1), fmt(s.get("omega_rmse_dps"), 1),
                      fmt(s.get("scale"), 3), fmt(s.get("coverage_perc"), 1), fmt(s.get("max_gap_s"), 3)]  # fmt: skip
            rows.append(cells)
    return md_table(head, rows)


def runtime_table(seqs, results):
    head = ["sequence", "backend", "status", "updates", "median ms", "p95 ms", "max ms", "backend s",
            "wall s", "real-time factor", "peak MB", "max knots"]  # fmt: skip
    rows = []
    for seq in seqs:
        for r in runs_of(results, seq["name"]):
            s = r["summary"]
            status = r["status"]
            if status == "timeout" and "event_time_reached_s" in s:
                status = "timeout at event time %.1f s" % s["event_time_reached_s"]
            cells = [seq["name"], r["backend"], status, fmt(s.get("updates")), fmt(s.get("update_median_ms"), 1),
                     fmt(s.get("update_p95_ms"), 1), fmt(s.get("update_max_ms"), 1), fmt(s.get("backend_total_s"), 1),
                     fmt(s.get("wall_time_s", r.get("wall_s")), 1), fmt(s.get("real_time_factor")),
                     fmt(s.get("peak_memory_mb"), 0), fmt(s.get("window_knots_max"))]  # fmt: skip
            rows.append(cells)
    return md_table(head, rows)


def ratio_table(seqs, results):
    """Median-time ratio baseline / window per sequence, overall and per quarter of the run."""
    head = ["sequence", "baseline", "median ratio", "Q1", "Q2", "Q3", "Q4", "baseline Q4/Q1",
            "window Q4/Q1", "baseline slope ms/s", "window slope ms/s", "backend-time ratio"]  # fmt: skip
    rows = []
    summary = []
    for seq in seqs:
        by = {r["backend"]: r for r in runs_of(results, seq["name"])}
        w = by.get("window")
        for b in ("incremental", "incremental-frozen"):
            r = by.get(b)
            if r is None or w is None:
                continue
            sw, sb = w["summary"], r["summary"]
            if "update_median_ms" not in sw or "update_median_ms" not in sb:
                rows.append([seq["name"], b, "no timing (%s / %s)" % (w["status"], r["status"])])
                continue
            ratio = sb["update_median_ms"] / sw["update_median_ms"]
            # quarters of one common event-time span (a stopped baseline has no later quarters)
            tw, tb = w["timing"]["t_s"], r["timing"]["t_s"]
            span = (min(tw[0], tb[0]), max(tw[-1], tb[-1]))
            qw_all = quarter_medians(tw, w["timing"]["total_ms"], span)
            qb_all = quarter_medians(tb, r["timing"]["total_ms"], span)
            qs = [qb / qw if qb is not None and qw else None for qb, qw in zip(qb_all, qw_all)]
            tot = sb["backend_total_s"] / sw["backend_total_s"] if sw.get("backend_total_s") else None
            note = "" if r["status"] == "ok" else " (%s)" % r["status"]
            cells = [seq["name"], b + note, fmt(ratio)] + [fmt(q) for q in qs]
            cells += [fmt(sb.get("growth_q4_over_q1")), fmt(sw.get("growth_q4_over_q1")),
                      fmt(sb.get("slope_ms_per_s"), 1), fmt(sw.get("slope_ms_per_s"), 1), fmt(tot)]  # fmt: skip
            rows.append(cells)
            summary.append(dict(sequence=seq["name"], baseline=b, median_ratio=ratio, quarter_ratios=qs,
                                backend_time_ratio=tot, baseline_status=r["status"]))  # fmt: skip
    return md_table(head, rows), summary


def targets_table(seqs, results):
    head = ["sequence", "backend", "ATE ≤ 1 % of path", "RTE @10 % ≤ 2 %", "velocity ≤ 10 % of mean speed",
            "real-time factor ≤ 1"]  # fmt: skip
    rows = []
    for seq in seqs:
        for r in runs_of(results, seq["name"]):
            s = r["summary"]
            if r["status"] != "ok":
                rows.append([seq["name"], r["backend"]] + ["**%s**" % r["status"]] * 4)
                continue
            cell = lambda v, tgt, d=2: "%s (%s)" % (mark(v, tgt), fmt(v, d))  # noqa: E731
            rows.append([seq["name"], r["backend"], cell(s.get("ate_perc"), TARGET_ATE_PERC),
                         cell(s.get("rte10_perc"), TARGET_RTE10_PERC, 1),
                         cell(s.get("vel_rmse_perc"), TARGET_VEL_PERC, 1),
                         cell(s.get("real_time_factor"), TARGET_RTF)])  # fmt: skip
    return md_table(head, rows)


def machine_description():
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    mem = None
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal"):
                    mem = int(line.split()[1]) / 1024 / 1024
                    break
    except OSError:
        pass
    return dict(cpu=cpu, cores=os.cpu_count(), mem_gb=mem, os=platform.platform(),
                load=list(os.getloadavg()) if hasattr(os, "getloadavg") else None)  # fmt: skip


def git_describe():
    try:
        out = subprocess.run(["git", "-C", REPO_DIR, "describe", "--always", "--dirty"], capture_output=True,
                             text=True, timeout=20)  # fmt: skip
        return out.stdout.strip() or None
    except (OSError, subprocess.SubprocessError):
        return None


def runs_made(results):
    """When the reported runs were made: 'DATE' or 'FIRST – LAST' (from their status files)."""
    dates = sorted(r["started"] for r in results if r.get("started"))
    if not dates:
        return "?"
    return dates[0] if dates[0] == dates[-1] else "%s – %s" % (dates[0], dates[-1])


def write_report(args, seqs, results, figures, machine, started, img_prefix):
    ratios_md, ratios = ratio_table(seqs, results)
    lines = []
    lines.append("_Generated by `tools/benchmark_suite.py` on %s from runs made %s, source `%s`; command:_"
                 % (started, runs_made(results), args.source_label or git_describe() or "?"))  # fmt: skip
    lines.append("")
    lines.append("```sh\n%s\n```" % args.command)
    lines.append("")
    m = machine
    lines.append("Machine: %s, %d cores visible (shared with other jobs), %s GB RAM, %s; load average at start %s."
                 % (m["cpu"], m["cores"] or 0, fmt(m["mem_gb"], 1), m["os"],
                    " / ".join("%.1f" % x for x in m["load"]) if m["load"] else "?"))  # fmt: skip
    lines.append("")
    lines.append("Sequences (simulated, exact ground truth):")
    lines.append("")
    lines.append("| sequence | scene | motion | duration s | seed | events | GT path m |")
    lines.append("|---|---|---|---|---|---|---|")
    for s in seqs:
        ev = s.get("events")
        lines.append("| %s | %s | %s | %g | %d | %s | %s |" % (
            s["name"], s["scene"], s["motion"], s["duration_s"], s["seed"], "%.2f M" % (ev / 1e6) if ev else "–",
            fmt(s.get("gt_path_length_m"))))  # fmt: skip
    lines.append("")
    lines.append("#### Targets (issue 7)")
    lines.append("")
    lines.append(targets_table(seqs, results))
    lines.append("")
    lines.append("#### Accuracy (Sim(3) alignment, rpg_trajectory_evaluation definitions)")
    lines.append("")
    lines.append("RTE: mean relative translation error in % of the sub-trajectory length at 10 … 50 % of the "
                 "ground-truth path; rotation: pooled mean relative rotation error; velocity: RMSE of the "
                 "body-frame linear velocity (times the Sim(3) scale) in % of the mean ground-truth speed; "
                 "ω: body angular-velocity RMSE; coverage: estimate span ÷ ground-truth span.")  # fmt: skip
    lines.append("")
    lines.append(accuracy_table(seqs, results))
    lines.append("")
    lines.append("#### Runtime (per backend update, `timing.csv` `total_ms`)")
    lines.append("")
    lines.append("Real-time factor: whole-pipeline wall time ÷ event-time span (`stats.json`); backend s: sum of "
                 "`total_ms`; max knots: the most knots optimized in one update.")  # fmt: skip
    lines.append("")
    lines.append(runtime_table(seqs, results))
    lines.append("")
    lines.append("#### Median time ratio baseline ÷ AsynEVO, and its growth along the sequence")
    lines.append("")
    lines.append("Q1…Q4: ratio of the median update times within each quarter of the sequence's event-time "
                 "span (the same quarters for both; '–' where a stopped run did not get to); "
                 "Q4/Q1: a backend's own median in the last quarter of its own span ÷ the first; slope: least-squares fit of "
                 "ms per update against event time; backend-time ratio: total backend time (the baselines "
                 "also update on new measurements, so they make more updates than the window).")  # fmt: skip
    lines.append("")
    lines.append(ratios_md)
    lines.append("")
    lines.append("#### Figures")
    lines.append("")
    captions = {
        "runtime_over_time.png": "Per-update backend time over event time (log scale)",
        "runtime_boxplots.png": "Per-update backend time per sequence and backend",
        "window_size.png": "Knots in the problem per update (`timing.csv` `window_knots`): the window for "
        "AsynEVO, the whole history for both baselines (option B holds all but the newest 20 constant)",
        "trajectories.png": "Estimates after Sim(3) alignment vs ground truth (top view)",
    }
    for path in figures:
        name = os.path.basename(path)
        lines.append("![%s](%s%s)" % (captions.get(name, name), img_prefix, name))
        lines.append("")
        lines.append("*%s.*" % captions.get(name, name))
        lines.append("")
    failed = [r for r in results if r["status"] != "ok"]
    if failed:
        lines.append("Runs that did not finish (messages in the accuracy table): " + ", ".join(
            "%s/%s %s" % (r["sequence"], r["backend"], r["status"]) for r in failed) + ".")
        lines.append("")
    return "\n".join(lines).rstrip() + "\n", ratios


def update_docs(docs_path, fragment):
    with open(docs_path) as f:
        text = f.read()
    b, e = text.find(BEGIN_MARKER), text.find(END_MARKER)
    if b < 0 or e < b:
        raise RuntimeError("%s has no '%s' ... '%s' section to replace" % (docs_path, BEGIN_MARKER, END_MARKER))
    text = text[: b + len(BEGIN_MARKER)] + "\n" + fragment + text[e:]
    with open(docs_path, "w") as f:
        f.write(text)


# ----------------------------------------------------------------------------- main


def parse_args(argv):
    try:
        table = load_sequences()
    except BaselineError as e:
        sys.exit("benchmark_suite.py: %s" % e)
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="sequences (workflow/baselines.yaml): " + ", ".join(
                                    "%s%s (%s)" % (k, "*" if v["default"] else "", v["about"])
                                    for k, v in table.items()) + "; * = default")  # fmt: skip
    p.add_argument("--out", default="benchmark_results", help="the workflow's output folder: reads its sequences/ "
                   "and runs/, writes results.md, results.json and figures/ into it")  # fmt: skip
    p.add_argument("--sequences", default=None, help="comma-separated sequence names (default: the default set)")
    p.add_argument("--backends", default=",".join(BACKENDS), help="comma-separated subset of " + ",".join(BACKENDS))
    p.add_argument("--command", default=None, help="the command the report names as the one that made the runs "
                   "(the workflow passes its snakemake command; default: this script's own command line)")  # fmt: skip
    p.add_argument("--source-label", default=None, help="what the binary was built from, for the report "
                   "(default: git describe of this checkout)")  # fmt: skip
    p.add_argument("--docs", default=None, help="markdown file whose generated section is replaced "
                   "(docs/results/baselines.md)")  # fmt: skip
    p.add_argument("--docs-images", default=None, help="folder for the PNGs referenced by --docs "
                   "(default: images/results/ next to --docs)")  # fmt: skip
    args = p.parse_args(argv)
    try:
        args.sequence_names = select_sequences(table, args.sequences)
        args.backend_names = select_backends(args.backends)
    except BaselineError as e:
        sys.exit("benchmark_suite.py: %s" % e)
    args.table = table
    if args.command is None:
        args.command = shlex.join(["tools/benchmark_suite.py"] + argv)
    return args


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    args = parse_args(argv)
    started = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    args.out = os.path.abspath(args.out)
    if not os.path.isdir(args.out):
        sys.exit("benchmark_suite.py: %s does not exist (run workflow/baselines.smk first)" % args.out)

    seqs, results = [], []
    for name in args.sequence_names:
        seq = sequence_info(args.out, name, args.table[name])
        runs = []
        for b in args.backend_names:
            rec = load_run(args.out, seq, b)
            if rec is None:
                log("run %s/%s: no status file in %s, left out of the report" % (name, b, args.out))
                continue
            runs.append(rec)
        if runs:
            seqs.append(seq)
            results.extend(runs)
    if not results:
        sys.exit("benchmark_suite.py: %s holds none of the requested runs (run workflow/baselines.smk first)" % args.out)

    # the load average "at start" is the one the earliest run recorded when it started
    machine = machine_description()
    first = min((r for r in results if r.get("started")), key=lambda r: r["started"], default=None)
    if first is not None and first.get("load_at_start"):
        machine["load"] = first["load_at_start"]

    fig_dir = os.path.join(args.out, "figures")
    os.makedirs(fig_dir, exist_ok=True)
    figures = [
        plot_timing_series(seqs, results, fig_dir, "total_ms", "ms per update", "runtime_over_time.png", lw=0.6),
        plot_runtime_boxes(seqs, results, fig_dir),
        plot_timing_series(seqs, results, fig_dir, "window_knots", "knots in the problem", "window_size.png",
                           lw=0.8, drawstyle="steps-post"),
        plot_trajectories(seqs, results, fig_dir),
    ]  # fmt: skip
    report, ratios = write_report(args, seqs, results, figures, machine, started, "figures/")
    with open(os.path.join(args.out, "results.md"), "w") as f:
        f.write(report)
    slim = [{k: v for k, v in r.items() if k not in ("timing", "eval", "stats")} for r in results]
    write_json(os.path.join(args.out, "results.json"),
               dict(started=started, runs_made=runs_made(results), command=args.command, machine=machine,
                    source=args.source_label or git_describe(), sequences=seqs, runs=slim, ratios=ratios))  # fmt: skip
    log("report: %s" % os.path.join(args.out, "results.md"))
    if args.docs:
        docs = os.path.abspath(args.docs)
        img_dir = os.path.abspath(args.docs_images or os.path.join(os.path.dirname(docs), "images", "results"))
        os.makedirs(img_dir, exist_ok=True)
        for path in figures:
            shutil.copy(path, os.path.join(img_dir, os.path.basename(path)))
        prefix = os.path.relpath(img_dir, os.path.dirname(docs)).replace(os.sep, "/") + "/"
        fragment, _ = write_report(args, seqs, results, figures, machine, started, prefix)
        update_docs(docs, fragment)
        log("updated %s and %s" % (docs, img_dir))
    return 0


if __name__ == "__main__":
    sys.exit(main())
