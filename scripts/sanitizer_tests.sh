# Sourced by scripts/sanitize.sh and scripts/sanitize_thread.sh: runs the listed tests of a sanitizer
# build folder from the source root (the tests read their fixtures relative to it, as under ctest).
# run_gtests NAME BUILD_DIR TEST...: each TEST is "executable" or "executable:gtest filter"; prints each
# test's time as "NAME: executable N s"; returns 1 when any test failed.
run_gtests() {
  local name=$1 build=$2 failed=0 t test filter started
  shift 2
  for t in "$@"; do
    test="${t%%:*}"
    filter="*"
    [ "$t" != "$test" ] && filter="${t#*:}"
    started=$SECONDS
    "$build/bin/$test" --gtest_brief=1 --gtest_filter="$filter" || failed=1
    echo "$name: $test $((SECONDS - started)) s" >&2
  done
  return $failed
}
