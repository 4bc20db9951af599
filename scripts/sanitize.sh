#!/usr/bin/env bash
# Runs the input side of AsynEVO under AddressSanitizer + UndefinedBehaviorSanitizer
# (docs/reliability.md): the core and io unit tests and every fuzz corpus replay, built in
# build-asan/ with ASYNEVO_SANITIZE=ON. Any sanitizer report fails the run (UBSan does not recover,
# ASan stops at the first error, leaks are reported).
# Usage: scripts/sanitize.sh            (after scripts/setup.sh has installed the packages)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-asan"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
# Warnings are enforced by the main build (scripts/setup.sh); the sanitizers change what GCC can prove
# about initialization, so this build does not turn warnings into errors.
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DASYNEVO_SANITIZE=ON \
  -DASYNEVO_BUILD_BENCH=OFF -DASYNEVO_WERROR=OFF >/dev/null
mapfile -t replays < <(cd "$root/fuzz" && ls ./*_fuzz.cpp | sed 's|^\./||; s|_fuzz\.cpp$||')
cmake --build "$build" -j "$(nproc)" --target test_core test_io "${replays[@]/#/fuzz_replay_}"
# libhdf5 (not ours) leaks and asks for sizes read from a corrupt file when it fails to open one
# (fuzz/lsan.supp, docs/reliability.md): its leaks are suppressed by library name, and ASan returns NULL
# for an impossible size as the real malloc does, so HDF5 fails cleanly and the reader reports it.
# fast_unwind_on_malloc=0: see scripts/fuzz.sh (the Blosc plugin's leak, suppressed through its libhdf5 frames).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:allocator_may_return_null=1:fast_unwind_on_malloc=0"
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
cd "$root"  # the tests read their fixtures relative to the source folder, as under ctest
for test in test_core test_io; do
  echo "sanitize: $test" >&2
  "$build/bin/$test" --gtest_brief=1 || status=1
done
for name in "${replays[@]}"; do
  echo "sanitize: fuzz replay $name" >&2
  "$build/bin/fuzz_replay_$name" "$root/fuzz/corpus/$name" >/dev/null || status=1
done
[ $status -eq 0 ] && echo "sanitize: no sanitizer report, every test passed" >&2
exit $status
