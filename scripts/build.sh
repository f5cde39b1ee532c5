#!/usr/bin/env bash
# Configures and builds wearknit into a build folder.
#   scripts/build.sh [release|strict|sanitize] [extra cmake -D options...]
#   release:  optimised, no tests (build-release/)
#   strict:   optimised with debug info, warnings as errors, tests and benchmarks (build/)
#   sanitize: address + undefined-behaviour sanitizers, warnings as errors, tests (build-asan/)
set -euo pipefail
cd "$(dirname "$0")/.."
kind=${1:-release}
shift || true
jobs=${WEARKNIT_JOBS:-$(nproc)}
# The strict and sanitizer builds keep line tables and function names only
# (-g1): enough for backtraces, sanitizer reports and perf, and a quarter
# less compile time than full debug information (docs/benchmarks.md).
case "$kind" in
  release)  dir=build-release; opts=(-DCMAKE_BUILD_TYPE=Release -DWEARKNIT_TESTS=OFF -DWEARKNIT_BENCH=OFF) ;;
  strict)   dir=build;         opts=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DWEARKNIT_WERROR=ON
                                     "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG") ;;
  sanitize) dir=build-asan;    opts=(-DCMAKE_BUILD_TYPE=Debug -DWEARKNIT_WERROR=ON -DWEARKNIT_SANITIZE=ON -DWEARKNIT_BENCH=OFF
                                     "-DCMAKE_CXX_FLAGS_DEBUG=-g1") ;;
  *) echo "usage: scripts/build.sh [release|strict|sanitize]" >&2; exit 2 ;;
esac
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
# ccache (when installed) keeps compiled objects between builds and clones:
# paths under the checkout are hashed relative to it, and the build folder
# is left out of the hash (the debug info of an object reused from another
# clone names that clone's folder).
if command -v ccache >/dev/null 2>&1; then
  opts+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
fi
if [ ! -f "$dir/CMakeCache.txt" ]; then
  cmake -S . -B "$dir" "${generator[@]}" "${opts[@]}" "$@"
else
  cmake -S . -B "$dir" "${opts[@]}" "$@" >/dev/null
fi
cmake --build "$dir" --parallel "$jobs"
echo "$dir"
