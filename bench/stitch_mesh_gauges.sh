#!/usr/bin/env bash
# Stitch meshing at other gauges (docs/stitch-mesh.md, "Other gauges"): every
# cut folder meshed at every course x wale size of COURSES x WALES, counting
# the runs that give no valid stitch mesh (P086) and naming them.
#   bench/stitch_mesh_gauges.sh [CUT_DIR...]
# Without folders, every mesh of ../shared/meshes is scaled to 100 mm along
# its longest side and cut first (into $WORK/gauges/cut, kept for the next run).
# COURSES and WALES (mm, space-separated) override the sizes measured.
source "$(dirname "$0")/common.sh"
bench_build wearknit
W=$BUILD/apps/wearknit/wearknit
COURSES=${COURSES:-1.5 3 5 8 12}
WALES=${WALES:-1.5 3 5 8 12 20}
out=$WORK/gauges
mkdir -p "$out/cut"
dirs=("$@")
if [ ${#dirs[@]} -eq 0 ]; then
  for mesh in "$SHARED"/meshes/*.obj; do
    name=$(basename "$mesh" .obj)
    dir=$out/cut/$name
    if [ ! -s "$dir/cut-mesh.obj" ]; then
      scale=$(python3 -c 'import sys
v = [list(map(float, l.split()[1:4])) for l in open(sys.argv[1]) if l.startswith("v ")]
print(100 / max(max(p[i] for p in v) - min(p[i] for p in v) for i in range(3)))' "$mesh")
      rm -rf "$dir"
      "$W" cut "$mesh" --scale "$scale" -o "$dir" -q --no-pictures
    fi
    dirs+=("$dir")
  done
fi
runs=0
failed=0
for course in $COURSES; do
  for wale in $WALES; do
    size_failed=0
    for dir in "${dirs[@]}"; do
      name=$(basename "$dir")
      run=$out/run/$name
      rm -rf "$run"
      mkdir -p "$run"
      cp -r "$dir"/. "$run"/
      runs=$((runs + 1))
      if ! "$W" stitch-mesh "$run" -q --no-picture --stitch-mm "${course}x${wale}" \
        >"$out/stderr.txt" 2>&1; then
        size_failed=$((size_failed + 1))
        echo "  ${course}x${wale} $name: $(grep -m1 -o 'P[0-9]*.*' "$out/stderr.txt" | cut -c1-160)"
      fi
    done
    failed=$((failed + size_failed))
    printf '%5s x %-4s mm: %d of %d folders failed\n' "$course" "$wale" "$size_failed" "${#dirs[@]}"
  done
done
echo "== $failed of $runs runs gave no valid stitch mesh"
