#!/usr/bin/env bash
# Regenerates the figures of docs/guide/ from the demo: runs 'asynevo demo' (10 s boxes scene, 6-DoF
# motion, seed 1) into a scratch folder and copies its trajectory and relative-error plots into
# docs/images/guide/. About a minute of simulation and a run on two cores.
# Usage: scripts/guide_figures.sh [path/to/asynevo]     (default: build/bin/asynevo)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
asynevo="${1:-$root/build/bin/asynevo}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$asynevo" demo --out "$work/demo"
mkdir -p "$root/docs/images/guide"
cp "$work/demo/run/plots/trajectory.png" "$root/docs/images/guide/demo_trajectory.png"
cp "$work/demo/run/plots/relative_error.png" "$root/docs/images/guide/demo_relative_error.png"
echo "guide_figures: wrote docs/images/guide/demo_trajectory.png, demo_relative_error.png" >&2
