#!/usr/bin/env bash
# Fuzzes AsynEVO's readers with libFuzzer (docs/reliability.md).
# Usage: scripts/fuzz.sh [SECONDS] [HARNESS ...]     (default: 60 s each, every harness)
# Builds build-fuzz/ with clang-14 (ASan + UBSan + libFuzzer), then runs each harness for SECONDS with
# the committed corpus fuzz/corpus/NAME as seeds; new inputs go to build-fuzz/fuzz/corpus/NAME, crashes
# to build-fuzz/fuzz/findings/NAME/. A crash found becomes a fix, a unit test and a file in
# fuzz/corpus/NAME (the ctest test fuzz.replay.NAME then replays it on every build).
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
# which the harnesses report).
asan_options="${ASAN_OPTIONS:+$ASAN_OPTIONS:}allocator_may_return_null=1"
# Each input is written to a file (the readers take paths): in memory where /dev/shm is writable.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
status=0
for name in "${harnesses[@]}"; do
  mkdir -p "$build/fuzz/corpus/$name" "$build/fuzz/findings/$name"
  echo "fuzz: $name for $seconds s" >&2
  # fast_unwind_on_malloc=0, for the HDF5 harnesses only: the Blosc filter plugin (no frame pointers, unloaded
  # by libhdf5 before the leak check) leaks its global context, and only the full unwind reaches the libhdf5
  # frames that fuzz/lsan.supp names. Unwinding every allocation in full makes a text reader's harness
  # about 3x slower, so the others keep the fast unwinder.
  ASAN_OPTIONS="$asan_options"
  grep -q hdf5_harness "$root/fuzz/${name}_fuzz.cpp" && ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0"
  export ASAN_OPTIONS
  if ! "$build/bin/fuzz_$name" -max_total_time="$seconds" -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$build/fuzz/findings/$name/" "$build/fuzz/corpus/$name" "$root/fuzz/corpus/$name" \
      > "$build/fuzz/$name.log" 2>&1; then
    echo "fuzz: $name FOUND something: $build/fuzz/$name.log, $build/fuzz/findings/$name/" >&2
    status=1
  fi
  grep -E '^stat::number_of_executed_units|^stat::new_units_added' "$build/fuzz/$name.log" | sed "s/^/  $name /" >&2 || true
done
exit $status
