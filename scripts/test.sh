#!/usr/bin/env bash
# Installs what wearknit needs, then runs every check CI runs:
#   1. the .clang-format check on every source file;
#   2. a strict build (warnings as errors) and the whole test suite;
#   3. a build with address and undefined-behaviour sanitizers and the whole
#      test suite again.
# Test data comes from $WEARKNIT_SHARED or ../shared; without it the tests
# that need it are reported as skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
export WEARKNIT_JOBS=${WEARKNIT_JOBS:-$(nproc)}

echo "== format check"
scripts/check-format.sh

echo "== strict build + tests"
scripts/build.sh strict
ctest --test-dir build --output-on-failure --parallel "$WEARKNIT_JOBS" --timeout 900

echo "== sanitizer build + tests"
scripts/build.sh sanitize
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure --parallel "$WEARKNIT_JOBS" --timeout 1200
