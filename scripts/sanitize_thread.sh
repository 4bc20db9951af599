#!/usr/bin/env bash
# Runs AsynEVO's threaded code under ThreadSanitizer (docs/reliability.md): the pipeline's two threads
# (frontend -> BoundedQueue -> backend, src/pipeline/pipeline.cpp) through the pipeline unit tests and the
# end-to-end `asynevo run` tests (offline and --realtime), and the event simulator's worker threads,
# built in build-tsan/ with ASYNEVO_TSAN=ON (GCC, RelWithDebInfo; TSan cannot share a build with ASan).
# Any report fails the run, also one made by an `asynevo` process a command-line test starts: every
# report goes to a log file (log_path) and the script fails when one exists.
# Usage: scripts/sanitize_thread.sh      (after scripts/setup.sh has installed the packages)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/sanitizer_tests.sh"
build="$root/build-tsan"

# What runs under TSan: "executable" or "executable:gtest filter" (times in docs/reliability.md).
tests=(
  "test_pipeline"            # BoundedQueue (blocking, close, a fast producer), both pipeline threads, errors
  # The overload test: asynevo run --realtime --speed 5 (pacing, a full queue, the lag counters), then the
  # same sequence offline. The other RunEndToEnd tests start the same two threads on the same input and
  # run under ASan (scripts/sanitize.sh); under TSan each costs 2-4 more minutes on a loaded 2-core machine.
  "test_cli:RunEndToEnd.FiveTimesFasterThanRealTimeEndsNormallyAndReportsTheLag"
  # The event simulator's worker threads (rows split over threads); its other tests are single-threaded.
  "test_sim:EventSimulator.ResultDoesNotDependOnThreadsAndFollowsTheSeed"
  # The builtin window solver's factor evaluation on several threads (backend.solver_threads > 1), the
  # projections of a knot interval sharing its segment cache.
  "test_backend:WindowSolverTest.FactorsEvaluatedOnSeveralThreads*"
)

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# No -Werror here either (scripts/sanitize.sh): GCC warns about what TSan does not model (-Wtsan).
# -g1 (line tables only) instead of -g: a report's stacks keep file and line, the build gets faster; -O2
# stays, since the real-time test's work against the wall clock depends on the speed under TSan.
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DASYNEVO_TSAN=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DASYNEVO_BUILD_BENCH=OFF -DASYNEVO_WERROR=OFF >/dev/null
targets=(asynevo)
for t in "${tests[@]}"; do targets+=("${t%%:*}"); done
started=$SECONDS
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"
echo "sanitize-thread: TSan build $((SECONDS - started)) s" >&2

# Every report, from a test or from an asynevo process it starts, is written to $logs/report.PID
# (log_path: https://github.com/google/sanitizers/wiki/SanitizerCommonFlags). halt_on_error=0 (the
# default) lets a run show every race, not only the first; second_deadlock_stack=1 prints both stacks of
# a lock-order inversion (https://github.com/google/sanitizers/wiki/ThreadSanitizerFlags).
# The test's input, 3 s of simulated events, is made by `asynevo simulate` once per build folder
# (tests/pipeline/sim_sequence.hpp). The simulation is deterministic for its seed and single-threaded, so
# when the main build already made it (CI runs the test suite first) it is copied instead of simulated
# again at TSan's speed.
sequence="test_sequences/boxes_6dof_3000ms"
if [ -f "$root/build/$sequence/events.txt" ] && [ ! -d "$build/$sequence" ]; then
  mkdir -p "$build/test_sequences" && cp -r "$root/build/$sequence" "$build/$sequence"
fi
logs="$build/sanitizer-reports"
rm -rf "$logs" && mkdir -p "$logs"
export TSAN_OPTIONS="halt_on_error=0:second_deadlock_stack=1:log_path=$logs/report"
status=0
cd "$root"
run_gtests sanitize-thread "$build" "${tests[@]}" || status=1
if compgen -G "$logs/report.*" >/dev/null; then
  echo "sanitize-thread: ThreadSanitizer reports:" >&2
  cat "$logs"/report.* >&2
  status=1
fi
[ $status -eq 0 ] && echo "sanitize-thread: no ThreadSanitizer report, every test passed" >&2
exit $status
