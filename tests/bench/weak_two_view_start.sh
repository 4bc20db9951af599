#!/bin/sh
# A weak two-view start that fits a depth-inverted map (docs/method/initialization.md, "Weak two-view
# starts"), replayed from recorded tracks (tests/data/sim/weak_two_view_start: the first 1.6 s of the
# evaluation matrix's d346-boxes-trans-tune run started 50 ms in, tests/data/SOURCES.md).
#  - as recorded (init_weak_two_view keep): the start is a two-view pose of 14 inliers, and the estimate
#    travels backwards: its direction of travel is reversed for most knots;
#  - with init_weak_two_view confirm: that attempt waits (counted as an 'agreement' rejection, its reason
#    in init_attempts), the start is built on the multi-view fit instead, and once past that start's
#    window (from 0.6 s) the estimate travels forward. (The multi-view start's own first knots, 0.08-0.4 s,
#    are reversed as well; its window's solve turns the direction round at 0.43 s.)
#  - with init_weak_two_view compare: the multi-view fit fails at that attempt, so the weak two-view start
#    is built on as recorded (the same start).
#  - with init_depth_reversal wait: the five-point pose of that attempt has a depth-reversed alternative
#    that fits its 16 features within 13 % (a tie, init_reversal_margin 0.2), and so has the multi-view
#    fit; the attempt waits (a 'reversal' rejection), and the start comes two attempts later from a
#    two-view pose whose alternative fits far worse; from 0.6 s the estimate travels forward.
#  - with direction_audit restart (the default; the rules above are replayed with it off): the recorded start is built on, the audits of its young
#    segment find the depth-reversed motion of the window cheaper (two votes in a row by 0.82 s), the
#    segment ends as a 'reversal', and the estimator starts again; the new segment travels forward.
#   weak_two_view_start.sh ASYNEVO BENCH_REPLAY_TRACKS DATA_DIR WORK_DIR
set -eu
asynevo=$1; replay=$2; data=$3; work=$4
rm -rf "$work"
mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
reversed_percent() {  # the evaluation's share of knots from ${3:-0.6} s on travelling in reverse, in %
  awk -v from="${3:-0.6}" '/^#/ || $1 >= from' "$1" > "$1.late"
  awk -v from="${3:-0.6}" '/^#/ || $1 >= from' "$1.velocities.txt" > "$1.late.velocities.txt"
  "$asynevo" eval --gt "$data/sequence/groundtruth.txt" --est "$1.late" --velocities "$1.late.velocities.txt" \
      --segments none --out "$2" > "$2.log" 2>&1 || fail "asynevo eval of $1: $(tail -1 "$2.log")"
  sed -n 's/.*in reverse (> 90 deg) \([0-9.]*\) % of.*/\1/p' "$2.log"
}
for rule in keep compare confirm reversal audit; do
  mkdir -p "$work/$rule/run" "$work/$rule/eval"
  cp "$data/run/tracks.txt" "$data/run/backend_feed.txt" "$work/$rule/run/"
  # The rules of the start are measured without the direction audit and with the window's triangulation
  # from all views (triangulation_views: all; with solved_then_all the confirm start's window keeps
  # travelling in reverse, docs/results/window_landmarks.md); the audit with the defaults.
  setting="init_weak_two_view: $rule\n  direction_audit: off\n  triangulation_views: all"
  [ "$rule" = reversal ] && setting="init_depth_reversal: wait\n  direction_audit: off\n  triangulation_views: all"
  [ "$rule" = audit ] && setting="direction_audit: restart"
  sed "s/^backend:\$/backend:\n  $setting/" "$data/run/config.yaml" > "$work/$rule/run/config.yaml"
  "$replay" "$work/$rule/run" "$data/sequence" "$work/$rule/traj.txt" > "$work/$rule/replay.log" 2>&1 ||
    fail "the replay with $rule: $(tail -1 "$work/$rule/replay.log")"
  grep -q "initialized true" "$work/$rule/replay.log" || fail "$rule: the replay never initialized"
done
keep_start=$(grep "^initial views" "$work/keep/replay.log")
confirm_start=$(grep "^initial views" "$work/confirm/replay.log")
compare_start=$(grep "^initial views" "$work/compare/replay.log")
[ "$compare_start" = "$keep_start" ] || fail "with compare the start differs from the recorded one: $compare_start"
echo "keep:    $keep_start"
echo "confirm: $confirm_start"
case "$keep_start" in *two-view*"14 inliers"*) ;; *) fail "as recorded the start is no longer the two-view pose of 14 inliers: $keep_start" ;; esac
case "$confirm_start" in *multi-view*) ;; *) fail "with confirm the start is not the multi-view fit: $confirm_start" ;; esac
grep -q "not confirmed" "$work/confirm/replay.log" || fail "with confirm no attempt says why it waited"
keep_rev=$(reversed_percent "$work/keep/traj.txt" "$work/keep/eval")
confirm_rev=$(reversed_percent "$work/confirm/traj.txt" "$work/confirm/eval")
echo "travelling in reverse from 0.6 s on: keep $keep_rev %, confirm $confirm_rev %"
awk -v k="$keep_rev" -v c="$confirm_rev" 'BEGIN { exit !(k > 80 && c < 5) }' ||
  fail "expected the recorded start's knots in reverse (> 80 %) and those of confirm forward (< 5 % reversed)"
reversal_start=$(grep "^initial views" "$work/reversal/replay.log")
echo "reversal: $reversal_start"
case "$reversal_start" in *two-view*) ;; *) fail "with init_depth_reversal wait the start is not a two-view pose: $reversal_start" ;; esac
[ "$reversal_start" != "$keep_start" ] || fail "with init_depth_reversal wait the recorded start was built on"
reversal_rev=$(reversed_percent "$work/reversal/traj.txt" "$work/reversal/eval")
echo "travelling in reverse from 0.6 s on with init_depth_reversal wait: $reversal_rev %"
grep -q "the depth-reversed motion fits 16 features within" "$work/reversal/replay.log" ||
  fail "with init_depth_reversal wait no attempt says that it waited for a tie of the depth-reversed motion"
awk -v r="$reversal_rev" 'BEGIN { exit !(r < 5) }' || fail "with init_depth_reversal wait the estimate still travels in reverse"
audit_start=$(grep "^initial views" "$work/audit/replay.log")
[ "$audit_start" = "$keep_start" ] || fail "with direction_audit restart the start differs from the recorded one: $audit_start"
segments="$work/audit/traj.txt.segments.txt"
first_end=$(awk '!/^#/ && $1 == 0 { print $5 }' "$segments")
second_start=$(awk '!/^#/ && $1 == 1 { print $2 }' "$segments")
[ "$first_end" = reversal ] || fail "with direction_audit restart the reversed segment did not end as a reversal: $(cat "$segments")"
[ -n "$second_start" ] || fail "with direction_audit restart the estimator did not start again: $(cat "$segments")"
grep -q " audit .* restart\$" "$work/audit/traj.txt.init_reversals.txt" || fail "no audit logged its restart"
audit_rev=$(reversed_percent "$work/audit/traj.txt" "$work/audit/eval" "$second_start")
echo "direction_audit restart: the first segment ended as a reversal; travelling in reverse from the second (at $second_start s): $audit_rev %"
awk -v r="$audit_rev" 'BEGIN { exit !(r < 5) }' || fail "with direction_audit restart the second segment still travels in reverse"
echo "a weak two-view start that travels backwards waits for the multi-view fit with confirm, and for a"
echo "later two-view pose when its depth-reversed alternative fits as well; the direction audit ends the"
echo "reversed segment it built and starts again"
