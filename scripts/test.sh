#!/usr/bin/env bash
# Installs what wearknit needs, then runs the checks CI runs:
#   scripts/test.sh           1. the .clang-format check on every source file;
#                             2. a strict build (warnings as errors) and every test;
#                             3. a build with address and undefined-behaviour
#                                sanitizers and the tests labelled fast.
#   scripts/test.sh --quick   1, and 2 with the tests labelled fast only.
# Every test is labelled fast (a unit: seconds) or slow (the shared meshes,
# whole plans, long simulations); docs/benchmarks.md, "Test suite", says
# where the time goes. Test data comes from $WEARKNIT_SHARED or ../shared;
# without it the tests that need it are reported as skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=false
case "${1:-}" in
  "") ;;
  --quick) quick=true ;;
  *) echo "usage: scripts/test.sh [--quick]" >&2; exit 2 ;;
esac
scripts/install-deps.sh
export WEARKNIT_JOBS=${WEARKNIT_JOBS:-$(nproc)}
# Prints how long the step before took (where a run's time goes).
step_start=$SECONDS
took() {
  echo "-- $1: $((SECONDS - step_start)) s"
  step_start=$SECONDS
}

echo "== format check"
scripts/check-format.sh
took "format check"

if $quick; then
  echo "== strict build + fast tests"
  scripts/build.sh strict
  took "strict build"
  ctest --test-dir build --output-on-failure --parallel "$WEARKNIT_JOBS" -L fast
  took "fast tests"
  exit 0
fi

echo "== strict build + every test"
scripts/build.sh strict
took "strict build"
ctest --test-dir build --output-on-failure --parallel "$WEARKNIT_JOBS"
took "every test"

echo "== sanitizer build + fast tests"
scripts/build.sh sanitize
took "sanitizer build"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure --parallel "$WEARKNIT_JOBS" -L fast
took "fast tests under the sanitizers"
