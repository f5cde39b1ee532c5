#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (address and undefined-behaviour
# sanitizers) and runs each from its saved inputs.
#   scripts/fuzz.sh [SECONDS [TARGET...]]   default 300 s each, every target
# Targets and their saved inputs (replayed by the ordinary tests):
#   knitout_parser_fuzz  tests/knitout/fuzz_inputs/
#   dat_reader_fuzz      tests/backends/fuzz_inputs/
#   device_frame_fuzz    tests/devices/fuzz_inputs/
#   mesh_reader_fuzz     tests/planner/fuzz_inputs/
# New crash inputs land in build-fuzz/crashes/TARGET/; after fixing the bug,
# copy each into the target's fuzz_inputs/ folder so the tests replay it.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-300}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(knitout_parser_fuzz dat_reader_fuzz device_frame_fuzz mesh_reader_fuzz)
fi
declare -A inputs=(
  [knitout_parser_fuzz]=tests/knitout/fuzz_inputs
  [dat_reader_fuzz]=tests/backends/fuzz_inputs
  [device_frame_fuzz]=tests/devices/fuzz_inputs
  [mesh_reader_fuzz]=tests/planner/fuzz_inputs
)
scripts/install-deps.sh
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DWEARKNIT_FUZZ=ON -DWEARKNIT_TESTS=OFF -DWEARKNIT_BENCH=OFF "${launcher[@]}" >/dev/null
cmake --build build-fuzz --target "${targets[@]}" --parallel "$(nproc)"
for target in "${targets[@]}"; do
  if [ -z "${inputs[$target]:-}" ]; then
    echo "scripts/fuzz.sh: no target $target" >&2
    exit 2
  fi
  corpus=build-fuzz/corpus/$target
  mkdir -p "$corpus" "build-fuzz/crashes/$target"
  cp "${inputs[$target]}"/* "$corpus"/
  echo "== $target, $seconds s"
  build-fuzz/tests/fuzz/"$target" "$corpus" -max_total_time="$seconds" -max_len=8192 -timeout=20 \
    -artifact_prefix="build-fuzz/crashes/$target/" -print_final_stats=1
done
