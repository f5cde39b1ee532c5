#!/usr/bin/env bash
# The wearability figures of docs/wearability.md: cloth steps and projections
# per second, the distance-field build, and the whole elimination for the
# bunny cover (bunny-qd over bunny, one cut path split into 11 arcs).
# bench/strip_rate takes a folder written by `wearknit cut` or `wearknit plan`
# (it reads the proxy), not this hand-made cover.
#   bench/wearability.sh [BUILD_DIR]     (default build; needs ../shared)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shared=${WEARKNIT_SHARED:-../shared}
ninja -C "$build" cloth_bench make_cover_cut wearknit >/dev/null
echo "== machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
"$build/bench/cloth_bench" --benchmark_counters_tabular=true
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$build/bench/make_cover_cut" "$shared/meshes/bunny-qd.obj" "$dir/bunny-cut"
echo "== elimination, bunny cover, K=4, 2 threads"
/usr/bin/time -f "elapsed %e s, user %U s, system %S s" \
  "$build/apps/wearknit/wearknit" wearability "$dir/bunny-cut" \
  --wearer "$shared/meshes/bunny.obj" --threads 2 --seed 1 --quiet
echo "== machine after: load average $(cut -d' ' -f1-3 /proc/loadavg)"
