# AsynEVO's sliding window against the full-history baselines: simulate -> run + evaluate -> report
# (docs/results/baselines.md). From the repository root:
#
#   snakemake -s workflow/baselines.smk --cores 2                          # default sequences, 3 backends
#   snakemake -s workflow/baselines.smk --cores 2 \
#       --config docs=docs/results/baselines.md docs_images=docs/images/results   # ... and the docs section
#   snakemake -s workflow/baselines.smk --cores 2 --config sequences=boxes_6dof \
#       backends=window,incremental-frozen duration=3                       # a quick check
#   snakemake -s workflow/baselines.smk --cores 2 -n                       # what would run
#
# Configuration (--config key=value):
#   out            output folder, relative to the repository root or absolute   [benchmark_results]
#   asynevo        the binary that simulates and runs                           [build/bin/asynevo]
#   sequences      comma-separated names from workflow/baselines.yaml   [the entries with default: true]
#   backends       comma-separated subset of window,incremental,incremental-frozen          [all three]
#   duration       seconds to simulate, replacing every sequence's own (smoke runs)  [each sequence's]
#   run_timeout_s  a run still going after this many wall seconds is stopped and reported as timeout,
#                  with the event time it reached; 0 = no limit                                    [0]
#   run_config     asynevo run --config; empty (run_config=) = the built-in defaults  [config/sim.yaml]
#   docs           also replace the generated section of this markdown file (between
#                  <!-- results:begin --> and <!-- results:end -->) and copy the figures to
#                  images/results/ beside it (or to docs_images)                               [none]
#   docs_images    the folder the docs section's figures are copied to    [images/results/ beside docs]
#   source_label   what the binary was built from, for the report's header  [git describe --dirty]
# Unknown keys, sequence names or backend names stop the workflow before anything runs.
#
# Layout of OUT:
#   sequences/SEQ/                 asynevo simulate output
#   runs/SEQ/BACKEND/              asynevo run folder + eval.json, run.log, eval.log
#   runs/SEQ/BACKEND.json          the run's status: ok, failed (with the message that says why) or
#                                  timeout (the report adds the event time it reached)
#   results.md, results.json       the report (tools/benchmark_suite.py) and every number of its tables
#   figures/*.png                  runtime over event time, runtime box plots, window size, trajectories
#   logs/                          one log per job; logs/simulate/SEQ.benchmark.tsv its wall time
#
# The rules are file-based: a sequence is simulated again only when its simulate arguments (or its
# motion file) change; a run is made again when the sequence, the run configuration (its content),
# the binary or the run's arguments change. A run that fails or times out is a result (its status
# file says so and it stays in every table): it never fails the workflow. Each run takes 2 cores
# (reader+frontend thread, backend thread), so with --cores 2 the runs go one at a time and their
# wall times are comparable. To redraw the report (or the docs section) from the runs OUT holds,
# without running anything: /usr/bin/python3 tools/benchmark_suite.py --out OUT [--sequences A,B]
# [--backends ...] [--docs FILE].

import hashlib
import os
import re
import shlex
import sys

from snakemake.exceptions import WorkflowError

workdir: os.path.dirname(os.path.dirname(os.path.abspath(workflow.snakefile)))
sys.path.insert(0, "tools")
import baseline_run  # noqa: E402

CONFIG_KEYS = ("out", "asynevo", "sequences", "backends", "duration", "run_timeout_s", "run_config", "docs",
               "docs_images", "source_label")
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else "python3"
FIGURES = ["runtime_over_time.png", "runtime_boxplots.png", "window_size.png", "trajectories.png"]

unknown_keys = sorted(set(config) - set(CONFIG_KEYS))
if unknown_keys:
    raise WorkflowError("baselines: unknown configuration key(s) %s; known: %s" % (", ".join(unknown_keys), ", ".join(CONFIG_KEYS)))


def number(key, default, minimum):
    value = config.get(key, default)
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise WorkflowError("baselines: %s must be a number, got %r" % (key, value))
    if value < minimum:
        raise WorkflowError("baselines: %s must be >= %g, got %g" % (key, minimum, value))
    return value


def text(key, default):
    value = config.get(key, default)
    return "" if value is None else str(value)  # `--config key=` gives None


OUT = text("out", "benchmark_results")
if not OUT:
    raise WorkflowError("baselines: out must name a folder")
ASYNEVO = os.path.abspath(text("asynevo", "build/bin/asynevo"))
RUN_CONFIG = text("run_config", "config/sim.yaml")
RUN_TIMEOUT_S = number("run_timeout_s", 0, 0)
DURATION = number("duration", 0, 0) or None  # None: each sequence's own
if DURATION is not None and DURATION < 0.5:
    raise WorkflowError("baselines: duration must be at least 0.5 s, got %g" % DURATION)
DOCS = text("docs", "")
DOCS_IMAGES = text("docs_images", "")
SOURCE_LABEL = text("source_label", "")
try:
    TABLE = baseline_run.load_sequences()
except baseline_run.BaselineError as e:
    raise WorkflowError("baselines: %s" % e)
bad_names = []
try:
    SEQ_NAMES = baseline_run.select_sequences(TABLE, config.get("sequences"))
except baseline_run.BaselineError as e:
    bad_names.append(str(e))
try:
    BACKENDS = baseline_run.select_backends(config.get("backends"))
except baseline_run.BaselineError as e:
    bad_names.append(str(e))
if bad_names:
    raise WorkflowError("baselines: %s" % "; ".join(bad_names))
if not os.access(ASYNEVO, os.X_OK):
    raise WorkflowError("baselines: %s is not an executable (build it, or give asynevo=BIN)" % ASYNEVO)
if RUN_CONFIG and not os.path.isfile(RUN_CONFIG):
    raise WorkflowError("baselines: run_config %s: no such file" % RUN_CONFIG)
if DOCS and not os.path.isfile(DOCS):
    raise WorkflowError("baselines: docs %s: no such file" % DOCS)

# the command named in the report's header: this workflow with the configuration it was given
COMMAND = shlex.join(["snakemake", "-s", "workflow/baselines.smk", "--cores", str(workflow.cores)] +
                     (["--config"] + ["%s=%s" % (k, text(k, "")) for k in CONFIG_KEYS if k in config] if config else []))  # fmt: skip


def file_digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()[:16]


def motion_inputs(wildcards):
    spec = TABLE[wildcards.seq]
    return [spec["motion"]] if spec["motion_is_file"] else []


wildcard_constraints:
    seq="|".join(re.escape(n) for n in TABLE),
    backend="|".join(re.escape(b) for b in baseline_run.BACKENDS),


rule all:
    input:
        os.path.join(OUT, "results.md"),


rule simulate:
    input:
        motion_inputs,
    output:
        directory(os.path.join(OUT, "sequences", "{seq}")),
    log:
        os.path.join(OUT, "logs", "simulate", "{seq}.log"),
    benchmark:
        os.path.join(OUT, "logs", "simulate", "{seq}.benchmark.tsv")
    params:
        args=lambda wc: shlex.join(baseline_run.simulate_args(TABLE[wc.seq], DURATION)),
    threads: 1
    shell:
        "{ASYNEVO} simulate {params.args} --out {output} > {log} 2>&1"


rule run:
    input:
        seq=os.path.join(OUT, "sequences", "{seq}"),
        asynevo=ASYNEVO,
        config=[RUN_CONFIG] if RUN_CONFIG else [],
    output:
        os.path.join(OUT, "runs", "{seq}", "{backend}.json"),
    log:
        os.path.join(OUT, "logs", "run", "{seq}", "{backend}.log"),
    params:
        run_dir=lambda wc: os.path.join(OUT, "runs", wc.seq, wc.backend),
        config_arg=shlex.join(["--config", RUN_CONFIG]) if RUN_CONFIG else "",
        # a changed configuration reruns the runs even when the file keeps its name and date
        config_digest=file_digest(RUN_CONFIG) if RUN_CONFIG else "",
        timeout=RUN_TIMEOUT_S,
    threads: 2  # reader+frontend thread and backend thread
    shell:
        "{PYTHON} tools/baseline_run.py --asynevo {ASYNEVO} --dataset {input.seq} --backend {wildcards.backend}"
        " --sequence {wildcards.seq} --run-dir {params.run_dir} --status {output} {params.config_arg}"
        " --timeout {params.timeout} > {log} 2>&1"


rule report:
    input:
        runs=expand(os.path.join(OUT, "runs", "{seq}", "{backend}.json"), seq=SEQ_NAMES, backend=BACKENDS),
        table="workflow/baselines.yaml",
    output:
        md=os.path.join(OUT, "results.md"),
        json=os.path.join(OUT, "results.json"),
        figures=[os.path.join(OUT, "figures", f) for f in FIGURES],
    log:
        os.path.join(OUT, "logs", "report.log"),
    params:
        args=shlex.join(["--out", OUT, "--sequences", ",".join(SEQ_NAMES), "--backends", ",".join(BACKENDS),
                         "--command", COMMAND] + (["--docs", DOCS] if DOCS else []) +
                        (["--docs-images", DOCS_IMAGES] if DOCS and DOCS_IMAGES else []) +
                        (["--source-label", SOURCE_LABEL] if SOURCE_LABEL else [])),  # fmt: skip
    threads: 1
    shell:
        "{PYTHON} tools/benchmark_suite.py {params.args} > {log} 2>&1"
