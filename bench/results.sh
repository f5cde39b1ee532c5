#!/usr/bin/env bash
# Writes docs/results.md: the current figures of the planner, from one run of
# one wearknit binary over the shared meshes.
#   bench/results.sh [BUILD_DIR]             (default build)
# The run is bench/same_output.sh's: the knit branch (cut, stitch-mesh,
# schedule, defaults) of every mesh of ../shared/meshes scaled to 100 mm along
# its longest side, the whole plan of the small closed meshes in $PLAN_MESHES
# (default torus-quad-coarse, 3torus-quad) and `wearknit demo`. The four covers
# of the paper's examples are then scheduled again in the seed pattern.
# bench/results_tables.py makes the tables; the command heads the file.
# Environment: OUT the work folder (default a temporary one, removed),
# RESULTS the file to write (default docs/results.md), MESHES and
# PLAN_MESHES as for bench/same_output.sh, WEARKNIT_SHARED.
source "$(dirname "$0")/plan_common.sh"
results=${RESULTS:-docs/results.md}
command="bench/results.sh $build"
[ -z "${MESHES:-}" ] || command="MESHES=\"$MESHES\" $command"
[ -z "${PLAN_MESHES:-}" ] || command="PLAN_MESHES=\"$PLAN_MESHES\" $command"
machine="$(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the start"
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
git diff --quiet HEAD -- . ':!docs' 2>/dev/null || commit="$commit with uncommitted changes"

bench/same_output.sh run "$build" "$out/run"

# The paper's covers in the seed pattern (§8: its bunny takes 16 min plain,
# 33 min seed), on copies of the plain folders.
for name in bunny-qd fertility-qd rockerarm-qd torus-qd; do
  [ -f "$out/run/knit/$name/stitch-mesh.smobj" ] || continue
  rm -rf "$out/seed/$name"
  mkdir -p "$out/seed"
  cp -r "$out/run/knit/$name" "$out/seed/$name"
  "$wearknit" schedule "$out/seed/$name" --pattern seed -q >"$out/seed/$name.log" 2>&1 || true
done

python3 bench/results_tables.py "$out" "$command" "$machine" "$commit" >"$results.tmp"
# The proxy made both ways (docs/cutting.md, "The proxy Q").
{
  printf '\n## The proxy: singularities and cut-arcs\n\n'
  OUT="$out/proxy" bench/proxy_singularities.sh "$build"
} >>"$results.tmp"
mv "$results.tmp" "$results"
echo "wrote $results" >&2
