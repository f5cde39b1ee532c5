#!/usr/bin/env bash
# Builds the knitout parser fuzz target with clang (libFuzzer, address and
# undefined-behaviour sanitizers) and runs it from the saved inputs.
#   scripts/fuzz.sh [SECONDS]     default 300
# New crash inputs land in build-fuzz/crashes/; after fixing the bug, copy
# each into tests/knitout/fuzz_inputs/ so the ordinary tests replay it.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-300}
scripts/install-deps.sh
cmake -S . -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DWEARKNIT_FUZZ=ON -DWEARKNIT_TESTS=OFF -DWEARKNIT_BENCH=OFF >/dev/null
cmake --build build-fuzz --target knitout_parser_fuzz --parallel "$(nproc)"
mkdir -p build-fuzz/corpus build-fuzz/crashes
cp tests/knitout/fuzz_inputs/* build-fuzz/corpus/
build-fuzz/tests/fuzz/knitout_parser_fuzz build-fuzz/corpus -max_total_time="$seconds" \
  -max_len=4096 -artifact_prefix=build-fuzz/crashes/ -print_final_stats=1
