#!/usr/bin/env bash
# The repeated-texture experiment (docs/results/repeated_texture.md; the AsynEVO paper's first
# experiment): simulate the 'grating' scene along the 'speed-ramp' preset with 30 Hz frames, run AsynEVO
# on the events and the frame-based KLT baseline on the frames (same backend, same configuration; the
# baseline with 3 and with 1 pyramid level), evaluate all and draw the speed-over-time figure with the
# per-phase error table. Then the fairness check: the first 2 s alone (walking speed, no aliasing).
#
# Usage: scripts/repeated_texture.sh [OUT_DIR] [FIGURE_PREFIX]
#   OUT_DIR        work folder (default: build/repeated_texture): seq/, seq_slow/, run folders, *.json, table.md
#   FIGURE_PREFIX  figures FIGURE_PREFIX.png and FIGURE_PREFIX_slow.png (default: OUT_DIR/repeated_texture)
# Environment: ASYNEVO (default build/bin/asynevo), CONFIG (default config/sim.yaml), FRAME_RATE (30),
# SEED (1). About 1.5 minutes on the 2-core VM.
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

evaluate() {  # RUN_DIR: Sim(3) on the whole trajectory, and on the first 30 knots (1.5 s of walking)
  "$asynevo" eval --gt "$1/stamped_groundtruth.txt" --est "$1/stamped_traj_estimate.txt" --out "$1/eval_all" > /dev/null
  "$asynevo" eval --gt "$1/stamped_groundtruth.txt" --est "$1/stamped_traj_estimate.txt" --align-frames 30 \
    --out "$1/eval_slow" > /dev/null
}

experiment() {  # NAME DURATION_S FIGURE TITLE
  local seq="$out/seq$1"
  echo "repeated_texture: simulating grating / speed-ramp, $2 s, frames at $frame_rate Hz" >&2
  "$asynevo" simulate --scene grating --motion speed-ramp --duration "$2" --seed "$seed" \
    --frame-rate "$frame_rate" --binary --no-text --out "$seq" > "$out/simulate$1.log"
  echo "repeated_texture: AsynEVO on the events, KLT baseline on the frames" >&2
  "$asynevo" run --dataset "$seq" --config "$config" --out "$out/events$1" > "$out/events$1.log"
  "$asynevo" run --frames "$seq" --config "$config" --out "$out/frames$1" > "$out/frames$1.log"
  "$asynevo" run --frames "$seq" --config "$config" --klt-levels 1 --out "$out/frames_l1$1" > "$out/frames_l1$1.log"
  for run in events frames frames_l1; do evaluate "$out/$run$1"; done
  /usr/bin/python3 "$root/tools/repeated_texture.py" --gt "$seq/groundtruth.txt" --run "asynevo=$out/events$1" \
    --run "klt30=$out/frames$1" --run "klt30_l1=$out/frames_l1$1" --differenced klt30 klt30_l1 \
    --out-figure "$3" --out-json "$out/results$1.json" --title "$4"
}

{
  echo "## grating / speed-ramp, 5 s"
  experiment "" 5 "$figure.png" "grating wall at 3 m (period 0.29 m), speed-ramp, DAVIS240C; frames at $frame_rate Hz"
  echo
  echo "## the walking phase alone (2 s at 1.4 m/s)"
  experiment _slow 2 "${figure}_slow.png" "the same scene, walking phase only (2 s at 1.4 m/s); frames at $frame_rate Hz"
} | tee "$out/table.md"
echo "repeated_texture: done in $(( $(date +%s) - start )) s; figures $figure.png, ${figure}_slow.png" >&2
