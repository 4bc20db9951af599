#!/bin/sh
# bench_replay_tracks on a run folder (tracks.txt + backend_feed.txt) must reproduce the run's backend
# exactly: the same final knots and velocities, byte for byte (docs/backend.md, "Where the error comes
# from"). A run that never initialized would compare two empty trajectories: checked first. Then
# --skip-ms: the first 400 ms of tracks skipped, the replay starts later and skips measurements.
# REPLAY_LOG_PATTERN (optional): an extended regular expression the replay's report must match (that a
# configuration's feature was at work in the run compared).
#   replay_reproduces_run.sh ASYNEVO BENCH_REPLAY_TRACKS CONFIG WORK_DIR [REPLAY_LOG_PATTERN]
set -eu
asynevo=$1; replay=$2; config=$3; work=$4; pattern=${5:-}
rm -rf "$work"
mkdir -p "$work"
"$asynevo" simulate --scene boxes --motion 6dof --seed 1 --duration 2.5 --out "$work/sequence" > "$work/simulate.log"
"$asynevo" run --dataset "$work/sequence" --config "$config" --out "$work/run" > "$work/run.log"
"$replay" "$work/run" "$work/sequence" "$work/replay.txt" > "$work/replay.log"
grep -v '^#' "$work/run/stamped_traj_estimate.txt" > "$work/run_traj.txt"
grep -v '^#' "$work/replay.txt" > "$work/replay_traj.txt"
knots=$(wc -l < "$work/run_traj.txt")
if [ "$knots" -lt 10 ]; then
  echo "FAIL: the run wrote $knots knots; the test needs a run that initializes" >&2
  exit 1
fi
if grep -q "no backend_feed.txt" "$work/replay.log"; then
  echo "FAIL: the replay did not find the run's backend_feed.txt" >&2
  exit 1
fi
cmp "$work/run_traj.txt" "$work/replay_traj.txt"
grep -v '^#' "$work/run/velocities.txt" > "$work/run_vel.txt"
grep -v '^#' "$work/replay.txt.velocities.txt" > "$work/replay_vel.txt"
cmp "$work/run_vel.txt" "$work/replay_vel.txt"
echo "replay reproduces the run: $knots knots identical"
if [ -n "$pattern" ] && ! grep -Eq "$pattern" "$work/replay.log"; then
  echo "FAIL: the replay's report does not match '$pattern':" >&2
  cat "$work/replay.log" >&2
  exit 1
fi
"$replay" "$work/run" "$work/sequence" "$work/skip.txt" --skip-ms 400 > "$work/skip.log"
first_run=$(head -n 1 "$work/run_traj.txt" | cut -d' ' -f1)
first_measurement=$(grep -v '^#' "$work/run/tracks.txt" | head -n 1 | cut -d' ' -f2)
first_skip=$(grep -v '^#' "$work/skip.txt" | head -n 1 | cut -d' ' -f1)
if ! awk -v m="$first_measurement" -v b="$first_skip" 'BEGIN { exit !(b >= m + 0.4) }'; then
  echo "FAIL: with --skip-ms 400 the estimate begins at $first_skip s, less than 0.4 s after the first" \
       "measurement ($first_measurement s)" >&2
  exit 1
fi
if ! grep -Eq "fed [0-9]+ measurements \([1-9][0-9]* skipped\)" "$work/skip.log"; then
  echo "FAIL: --skip-ms 400 skipped no measurement" >&2
  exit 1
fi
echo "--skip-ms 400: the estimate begins at $first_skip s instead of $first_run s"
# Lines of tracks.txt follow the frontend's output order, not strictly time: a measurement a little
# older than the first line must still be fed without --skip-ms (a replay feeds what the run fed).
mkdir -p "$work/older"
cp "$work/run/config.yaml" "$work/run/backend_feed.txt" "$work/older/"
awk '/^#/ { print; next } !done { print; printf "999999 %.9f %s %s\n", $2 - 0.000001, $3, $4; done = 1; next } { print }' \
  "$work/run/tracks.txt" > "$work/older/tracks.txt"
lines=$(grep -vc '^#' "$work/older/tracks.txt")
"$replay" "$work/older" "$work/sequence" "$work/older.txt" > "$work/older.log"
if ! grep -q "fed $lines measurements (0 skipped)" "$work/older.log"; then
  echo "FAIL: a measurement older than the first line was not fed: $(grep 'fed ' "$work/older.log")" >&2
  exit 1
fi
echo "a measurement older than the first line is fed: $lines of $lines"
# The oracle diagnostics: --oracle-scale 1, a cut no error reaches and a scaling from an age no track
# reaches change nothing; --oracle-scale 0
# gives the exact positions that --oracle 0 gives; a 0.3 px cut drops measurements.
"$replay" "$work/run" "$work/sequence" "$work/scale1.txt" --oracle-scale 1 > "$work/scale1.log"
"$replay" "$work/run" "$work/sequence" "$work/nocut.txt" --oracle-cut 1000 > "$work/nocut.log"
# --oracle-min-age-ms: the scaling only from that age on; no track of the 2.5 s run lives 100 s.
"$replay" "$work/run" "$work/sequence" "$work/young.txt" --oracle-scale 0 --oracle-min-age-ms 100000 > "$work/young.log"
for f in scale1 nocut young; do
  grep -v '^#' "$work/$f.txt" > "$work/${f}_traj.txt"
  cmp "$work/run_traj.txt" "$work/${f}_traj.txt"
done
"$replay" "$work/run" "$work/sequence" "$work/scale0.txt" --oracle-scale 0 > "$work/scale0.log"
"$replay" "$work/run" "$work/sequence" "$work/exact.txt" --oracle 0 > "$work/exact.log"
cmp "$work/scale0.txt" "$work/exact.txt"
grep -v '^#' "$work/exact.txt" > "$work/exact_traj.txt"
if cmp -s "$work/run_traj.txt" "$work/exact_traj.txt"; then
  echo "FAIL: the exact positions gave the run's trajectory" >&2
  exit 1
fi
# From 100 ms of age on, exact positions: neither the run's trajectory nor that of exact positions throughout.
"$replay" "$work/run" "$work/sequence" "$work/aged.txt" --oracle-scale 0 --oracle-min-age-ms 100 > "$work/aged.log"
grep -v '^#' "$work/aged.txt" > "$work/aged_traj.txt"
if cmp -s "$work/aged_traj.txt" "$work/run_traj.txt" || cmp -s "$work/aged_traj.txt" "$work/exact_traj.txt"; then
  echo "FAIL: --oracle-min-age-ms 100 changed nothing, or everything" >&2
  exit 1
fi
"$replay" "$work/run" "$work/sequence" "$work/cut.txt" --oracle-cut 0.3 > "$work/cut.log"
if ! grep -Eq "oracle cut: [1-9][0-9]* measurements of [1-9][0-9]* features" "$work/cut.log"; then
  echo "FAIL: --oracle-cut 0.3 cut nothing: $(grep 'oracle cut' "$work/cut.log")" >&2
  exit 1
fi
echo "oracle diagnostics: scale 1 and an unreached cut reproduce the run; $(grep 'oracle cut' "$work/cut.log")"
