#!/usr/bin/env bash
# Stitch meshing speed: a bunny cover 10 cm tall at the default gauge (the
# paper's 40x40 seed swatch, 42 x 115 mm: course 1.05 mm, wale 2.875 mm;
# about 8,000 stitches) must be meshed in under 10 s.
#   bench/stitch_mesh.sh
source "$(dirname "$0")/common.sh"
bench_build stitch_mesh_bench wearknit
W=$BUILD/apps/wearknit/wearknit
mesh=$SHARED/meshes/bunny-qd.obj
dir=$WORK/bunny-10cm
rm -rf "$dir"
# Scale so the bunny is 100 mm tall (y is up in the Stanford bunny).
"$W" cut "$mesh" -o "$dir" -q --no-pictures
scale=$(python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print(100.0 / r['input']['size_mm'][1])" "$dir/report.json")
rm -rf "$dir"
"$W" cut "$mesh" -o "$dir" --scale "$scale" -q --no-pictures
echo "== $mesh scaled by $scale (100 mm tall), cut into $dir"
echo "== stitch_mesh_bench (remeshing only, in memory, one core)"
"$BUILD/bench/stitch_mesh_bench" "$dir" --benchmark_min_time=2
echo "== whole wearknit stitch-mesh run (read cut folder, mesh, write .smobj/.obj/.png/report; median of 3)"
read -r s kb < <(median_run 3 "$W" stitch-mesh "$dir")
"$W" stitch-mesh "$dir" --no-picture
printf 'wearknit stitch-mesh %8.3f s  %7d KB peak RSS\n' "$s" "$kb"
awk -v s="$s" 'BEGIN { printf "budget: 10 s; the whole run takes %.1f%% of it\n", 100 * s / 10 }'
