#!/usr/bin/env bash
# Runs AsynEVO under AddressSanitizer + UndefinedBehaviorSanitizer (docs/reliability.md): the core, io,
# pipeline and backend unit tests (not the estimator tests: see below), the end-to-end `asynevo run` tests and every fuzz corpus replay, built in
# build-asan/ with ASYNEVO_SANITIZE=ON. (ThreadSanitizer, which cannot be combined with ASan, is
# scripts/sanitize_thread.sh; .ci/run runs both.) Any sanitizer report fails the run (UBSan
# does not recover, ASan stops at the first error, leaks are reported), also one made by an `asynevo`
# process a command-line test starts: every report goes to a log file (log_path) and the script fails
# when one exists, whatever the test made of the child's exit code.
# Usage: scripts/sanitize.sh            (after scripts/setup.sh has installed the packages)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/sanitizer_tests.sh"
build="$root/build-asan"

# What runs under ASan + UBSan: "executable" or "executable:gtest filter". Times under ASan on a loaded
# 2-core machine are in docs/reliability.md. The estimator tests (test_backend_estimator) are left out:
# they run 8-15 times slower under ASan than in Release (all 46: 826 s) and their build alone would take
# CI past its budget; the code they exercise runs under ASan through the end-to-end runs below (start,
# sliding window, marginalization, segments) and the backend's cost-function tests.
tests=(
  "test_core"
  "test_io"
  "test_pipeline"                                  # BoundedQueue, both pipeline threads, run folder
  "test_backend"                                   # the Ceres cost functions and GP bundle adjustment
  # simulate, run and eval as a user runs them, one with a gap in the events. Left out: the determinism
  # test (two more runs of the same input) and the --realtime overload test (under TSan instead,
  # scripts/sanitize_thread.sh).
  "test_cli:RunEndToEnd.SimulateRunEvalReachesTheMeasuredAccuracy:RunEndToEnd.AGapInTheEventsGivesTwoSegmentsThatEvalScoresApart"
)

generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# Warnings are enforced by the main build (scripts/setup.sh); the sanitizers change what GCC can prove
# about initialization, so this build does not turn warnings into errors.
# -O1 -g1 instead of RelWithDebInfo's -O2 -g: -O1 is what the ASan documentation recommends, and -g1 keeps
# the line tables a report's stack needs but no variable info. Together they compile the backend's Eigen-heavy
# files in 0.55x the time (factors_test.cpp: 160 s -> 87 s), the largest share of CI's time.
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DASYNEVO_SANITIZE=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DASYNEVO_BUILD_BENCH=OFF -DASYNEVO_WERROR=OFF >/dev/null
mapfile -t replays < <(cd "$root/fuzz" && ls ./*_fuzz.cpp | sed 's|^\./||; s|_fuzz\.cpp$||')
targets=(asynevo "${replays[@]/#/fuzz_replay_}")
for t in "${tests[@]}"; do targets+=("${t%%:*}"); done
started=$SECONDS
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"
echo "sanitize: ASan build $((SECONDS - started)) s" >&2

# Every report, from a test or from an asynevo process it starts, is written to $logs/report.PID
# (log_path, a common sanitizer flag: https://github.com/google/sanitizers/wiki/SanitizerCommonFlags).
logs="$build/sanitizer-reports"
rm -rf "$logs" && mkdir -p "$logs"
# libhdf5 (not ours) leaks and asks for sizes read from a corrupt file when it fails to open one
# (fuzz/lsan.supp, docs/reliability.md): its leaks are suppressed by library name, and ASan returns NULL
# for an impossible size as the real malloc does, so HDF5 fails cleanly and the reader reports it.
# fast_unwind_on_malloc=0: the Blosc plugin's leak, suppressed through its libhdf5 frames (fuzz/lsan.supp).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:allocator_may_return_null=1:fast_unwind_on_malloc=0:log_path=$logs/report"
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$logs/report"
status=0
cd "$root"
run_gtests sanitize "$build" "${tests[@]}" || status=1
started=$SECONDS
for name in "${replays[@]}"; do
  "$build/bin/fuzz_replay_$name" "$root/fuzz/corpus/$name" >/dev/null || { echo "sanitize: fuzz replay $name failed" >&2; status=1; }
done
echo "sanitize: ${#replays[@]} fuzz replays $((SECONDS - started)) s" >&2
# A report is an error, a UBSan finding or a leak. allocator_may_return_null=1 also logs a warning
# ("AddressSanitizer failed to allocate ...") each time libhdf5 asks for an impossible size on a corrupt
# fuzz input and gets NULL, which is the allowance above working, not a finding: those files are shown,
# not counted.
reports=()
for f in "$logs"/report.*; do
  [ -e "$f" ] || continue
  if grep -qE 'ERROR: |runtime error|LeakSanitizer' "$f"; then reports+=("$f"); fi
done
if [ ${#reports[@]} -gt 0 ]; then
  echo "sanitize: sanitizer reports (ASan/UBSan/LSan):" >&2
  cat "${reports[@]}" >&2
  status=1
elif compgen -G "$logs/report.*" >/dev/null; then
  echo "sanitize: allocation warnings only (libhdf5 on corrupt fuzz inputs, allowed):" >&2
  grep -h "failed to allocate" "$logs"/report.* | sort | uniq -c >&2 || true
fi
[ $status -eq 0 ] && echo "sanitize: no sanitizer report, every test passed" >&2
exit $status
