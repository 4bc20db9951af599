#!/usr/bin/env bash
# Fuzzes AsynEVO's readers with libFuzzer (docs/reliability.md).
# Usage: scripts/fuzz.sh [SECONDS] [HARNESS ...]     (default: 60 s each, every harness)
# Builds build-fuzz/ with clang-14 (ASan + UBSan + libFuzzer), then runs each harness for SECONDS with
# the committed corpus fuzz/corpus/NAME as seeds; new inputs go to build-fuzz/fuzz/corpus/NAME, crashes
# to build-fuzz/fuzz/findings/NAME/. A crash found becomes a fix, a unit test and a file in
# fuzz/corpus/NAME (the ctest test fuzz.replay.NAME then replays it on every build). The HDF5 harnesses
# run unguarded and their artifacts are sorted afterwards (tools/fuzz_triage.py): only a finding stays
# in findings/NAME/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
shift || true
build="$root/build-fuzz"
if ! command -v clang++-14 >/dev/null || ! ls /usr/lib/llvm-14/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  echo "fuzz: needs clang-14 and libFuzzer: apt-get install clang-14 libclang-rt-14-dev" >&2
  exit 2
fi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DASYNEVO_FUZZ=ON -DASYNEVO_SANITIZE=ON -DASYNEVO_BUILD_BENCH=OFF -DASYNEVO_FUZZ_SECONDS="$seconds" >/dev/null
fi
mapfile -t harnesses < <(cd "$root/fuzz" && ls ./*_fuzz.cpp | sed 's|^\./||; s|_fuzz\.cpp$||')
[ $# -gt 0 ] && harnesses=("$@")
cmake --build "$build" -j "$(nproc)" --target "${harnesses[@]/#/fuzz_}"
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp:print_suppressions=0"
# A size libhdf5 reads from a corrupt file can exceed what ASan can allocate; the real malloc returns
# NULL there and HDF5 fails cleanly, so ASan must too (our own code would still throw std::bad_alloc,
# which the harnesses report). Beyond 2000 MB ASan returns NULL before libFuzzer's malloc limit (the
# -rss_limit_mb, 2048 MB) would call the allocation an out-of-memory crash.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}allocator_may_return_null=1:max_allocation_size_mb=2000"
# Each input is written to a file (the readers take paths): in memory where /dev/shm is writable.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
status=0
for name in "${harnesses[@]}"; do
  mkdir -p "$build/fuzz/corpus/$name" "$build/fuzz/findings/$name"
  echo "fuzz: $name for $seconds s" >&2
  options=(-max_total_time="$seconds" -rss_limit_mb=2048 -artifact_prefix="$build/fuzz/findings/$name/")
  hdf5=false
  grep -q hdf5_harness "$root/fuzz/${name}_fuzz.cpp" && hdf5=true
  if $hdf5; then
    # The HDF5 harnesses parse each input in the fuzzer's own process, not in a child first (a fork per
    # input held them to about 45 executions per second; unguarded they run about 1,400), and libFuzzer goes on
    # past faults, in child processes of its own (-fork=1). Afterwards tools/fuzz_triage.py sorts what
    # faulted: libhdf5's own faults, which the child contains in every run, move to
    # build-fuzz/fuzz/contained/NAME/; anything else stays a finding (fuzz/hdf5_harness.hpp).
    export ASYNEVO_FUZZ_HDF5_UNGUARDED=1
    options+=(-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 -timeout=10)
  else
    unset ASYNEVO_FUZZ_HDF5_UNGUARDED
    options+=(-print_final_stats=1)
  fi
  code=0
  "$build/bin/fuzz_$name" "${options[@]}" "$build/fuzz/corpus/$name" "$root/fuzz/corpus/$name" \
    > "$build/fuzz/$name.log" 2>&1 || code=$?
  # With -fork=1 libFuzzer exits with the code of its last job, an ignored crash included: for the HDF5
  # harnesses the triage below decides, and only a run that never finished counts here.
  if $hdf5 && grep -q '^INFO: exiting: ' "$build/fuzz/$name.log"; then code=0; fi
  if [ "$code" -ne 0 ]; then
    echo "fuzz: $name FOUND something: $build/fuzz/$name.log, $build/fuzz/findings/$name/" >&2
    status=1
  fi
  if $hdf5; then
    unset ASYNEVO_FUZZ_HDF5_UNGUARDED
    # The last status line: "#RUNS: cov: .. exec/s N oom/timeout/crash: O/T/C time: Ss job: J ..."
    grep -E '^#[0-9]+: cov:' "$build/fuzz/$name.log" | tail -1 | sed "s/^/  $name /" >&2 || true
    if ! /usr/bin/python3 "$root/tools/fuzz_triage.py" "$build/bin/fuzz_$name" "$build/fuzz/findings/$name" \
        --move-contained "$build/fuzz/contained/$name" > "$build/fuzz/$name.triage" 2>&1; then
      echo "fuzz: $name FOUND something: $build/fuzz/$name.triage, $build/fuzz/findings/$name/" >&2
      status=1
    fi
    tail -1 "$build/fuzz/$name.triage" | sed "s/^/  $name /" >&2
  else
    grep -E '^stat::number_of_executed_units|^stat::new_units_added' "$build/fuzz/$name.log" | sed "s/^/  $name /" >&2 || true
  fi
done
exit $status
