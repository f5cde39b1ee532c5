#!/usr/bin/env bash
# The proxy Q made two ways on every shared mesh (docs/cutting.md, "The proxy
# Q"): `wearknit cut --proxy remesh` (field-aligned quads, a quad-dominant
# input kept as it is) and `--proxy field` (the field-guided triangle proxy,
# which also replaces a quad-dominant input that is not clean), with square
# growth for the field proxy. Each mesh of ../shared/meshes is scaled to
# 100 mm along its longest side, every other option at its default;
# bench/proxy_table.py prints a Markdown table (the command at its head): per
# mesh the smoothest field's singularities on the surface, Q's singular
# vertices, adjacent +1/-1 pairs, cut-arcs, mean arc length (edges and mm) and
# chord / length and how far Q lies from the garment (its vertices and face
# centroids, the farthest), each as "remesh → field", and which closed meshes meet the
# targets of docs/cutting.md, §9 (singular vertices, arcs, adjacent pairs).
#   bench/proxy_singularities.sh [BUILD_DIR]      (default build; needs ../shared)
# Environment: OUT the work folder (default a temporary one, removed), JOBS
# meshes cut at once (default 2), MESHES file names instead of every mesh,
# WEARKNIT_SHARED.
source "$(dirname "$0")/plan_common.sh"
command="bench/proxy_singularities.sh $build"
[ -z "${MESHES:-}" ] || command="MESHES=\"$MESHES\" $command"
meshes=${MESHES:-$(cd "$shared/meshes" && ls ./*.obj | sed 's|^\./||')}

# cut_both MESH: OUT/NAME-remesh and OUT/NAME-field.
cut_both() {
  local mesh=$1 name=${1%.obj} scale
  scale=$(scale_to_100mm "$shared/meshes/$mesh")
  "$wearknit" cut "$shared/meshes/$mesh" --scale "$scale" --proxy remesh \
    -o "$out/$name-remesh" -q --no-pictures >"$out/$name-remesh.log" 2>&1 ||
    echo "$name: cut --proxy remesh failed (see $out/$name-remesh.log)" >&2
  "$wearknit" cut "$shared/meshes/$mesh" --scale "$scale" --proxy field --growth square \
    -o "$out/$name-field" -q --no-pictures >"$out/$name-field.log" 2>&1 ||
    echo "$name: cut --proxy field failed (see $out/$name-field.log)" >&2
}

# shellcheck disable=SC2086 # one mesh per word
for_each_mesh cut_both $meshes
python3 bench/proxy_table.py "$out" "$command" $(echo "$meshes" | sed 's|\.obj||g')
