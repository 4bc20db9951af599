#!/usr/bin/env bash
# The repeated-texture experiment (docs/results/repeated_texture.md; the AsynEVO paper's first
# experiment): simulate the 'grating' scene along the 'speed-ramp' preset with 30 Hz frames, run AsynEVO
# on the events and the frame-based KLT baseline on the frames (same backend, same configuration; the
# baseline with 3 pyramid levels, with 1, and with 1 and a constant-velocity start), evaluate all and
# draw the speed-over-time figure with the per-phase error table. Then the fairness check: the first 2 s
# alone (walking speed, no aliasing).
#
# Usage: scripts/repeated_texture.sh [OUT_DIR] [FIGURE_PREFIX]
#   OUT_DIR        work folder (default: build/repeated_texture): seq/, seq_slow/, run folders, *.json, table.md
#   FIGURE_PREFIX  figures FIGURE_PREFIX.png and FIGURE_PREFIX_slow.png (default: OUT_DIR/repeated_texture)
# Environment: ASYNEVO (default build/bin/asynevo), CONFIG (default config/sim.yaml), FRAME_RATE (30),
# SEED (1). About 1 minute on the 2-core VM.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/build/repeated_texture}"
figure="${2:-$out/repeated_texture}"
asynevo="${ASYNEVO:-$root/build/bin/asynevo}"
config="${CONFIG:-$root/config/sim.yaml}"
frame_rate="${FRAME_RATE:-30}"
seed="${SEED:-1}"
mkdir -p "$out"
start=$(date +%s)

evaluate() {  # RUN_DIR: Sim(3) on the whole trajectory, and on the first 30 knots (1.5 s; fewer if the run
  # has fewer). A run that lost track and restarted (segments.txt) is scaled as one piece all the same:
  # the figure shows one speed per run.
  local est="$1/stamped_traj_estimate.txt" first
  "$asynevo" eval --gt "$1/stamped_groundtruth.txt" --est "$est" --segments none --out "$1/eval_all" > /dev/null
  first=$(/usr/bin/python3 -c "import json, sys; print(min(30, json.load(open(sys.argv[1]))['association']['matched']))" \
    "$1/eval_all/eval.json")
  "$asynevo" eval --gt "$1/stamped_groundtruth.txt" --est "$est" --segments none --align-frames "$first" \
    --out "$1/eval_slow" > /dev/null
}

experiment() {  # NAME FIGURE TITLE TOOL_ARGS -- SIMULATE_ARGS
  local name="$1" fig="$2" title="$3" tool_args=() seq="$out/seq$1"
  shift 3
  while [ "$1" != "--" ]; do tool_args+=("$1"); shift; done
  shift
  echo "repeated_texture: simulating grating / speed-ramp $*, frames at $frame_rate Hz" >&2
  "$asynevo" simulate --scene grating --motion speed-ramp "$@" --seed "$seed" \
    --frame-rate "$frame_rate" --binary --no-text --out "$seq" > "$out/simulate$name.log"
  echo "repeated_texture: AsynEVO on the events, the KLT baseline (three variants) on the frames" >&2
  "$asynevo" run --dataset "$seq" --config "$config" --out "$out/events$name" > "$out/events$name.log"
  "$asynevo" run --frames "$seq" --config "$config" --out "$out/frames$name" > "$out/frames$name.log"
  "$asynevo" run --frames "$seq" --config "$config" --klt-levels 1 --out "$out/frames_l1$name" \
    > "$out/frames_l1$name.log"
  "$asynevo" run --frames "$seq" --config "$config" --klt-levels 1 --klt-predict --out "$out/frames_predict$name" \
    > "$out/frames_predict$name.log"
  for run in events frames frames_l1 frames_predict; do evaluate "$out/$run$name"; done
  /usr/bin/python3 "$root/tools/repeated_texture.py" --gt "$seq/groundtruth.txt" --run "asynevo=$out/events$name" \
    --run "klt30=$out/frames$name" --run "klt30_l1=$out/frames_l1$name" \
    --run "klt30_predict=$out/frames_predict$name" --differenced klt30 "${tool_args[@]}" \
    --out-figure "$fig" --out-json "$out/results$name.json" --title "$title"
}

{
  echo "## grating / speed-ramp, 5 s"
  experiment "" "$figure.png" "grating wall at 3 m (period 0.29 m), speed-ramp, DAVIS240C; frames at $frame_rate Hz" \
    -- --duration 5
  echo
  echo "## the walking phase alone (2 s at 1.4 m/s)"
  experiment _slow "${figure}_slow.png" "the same scene, walking phase only (2 s at 1.4 m/s); frames at $frame_rate Hz" \
    --single-phase walking -- --duration 2
} | tee "$out/table.md"
echo "repeated_texture: done in $(( $(date +%s) - start )) s; figures $figure.png, ${figure}_slow.png" >&2
