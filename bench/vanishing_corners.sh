#!/usr/bin/env bash
# The vanishing corners of §4.1 chosen two ways on every shared mesh: each
# triangle's most acute corner (`wearknit cut --vanishing acute`, the paper's
# rule, the default) and the corners that minimise the sum of |corners - 4| over Q's
# interior vertices (`--vanishing optimal`; docs/cutting.md, §3).
# Each mesh of ../shared/meshes is scaled to 100 mm along its longest side
# and cut both ways, every other option at its default; bench/vanishing_table.py
# prints a Markdown table (the command at its head): per mesh the sum of
# |corners - 4|, irregular and singular vertices of Q, cut-arcs and cut
# edges per arc, each as "acute → optimal".
#   bench/vanishing_corners.sh [BUILD_DIR]        (default build; needs ../shared)
# Environment: OUT the work folder (default a temporary one, removed), JOBS
# meshes cut at once (default 2), MESHES file names instead of every mesh,
# WEARKNIT_SHARED.
source "$(dirname "$0")/plan_common.sh"
command="bench/vanishing_corners.sh $build"
[ -z "${MESHES:-}" ] || command="MESHES=\"$MESHES\" $command"
meshes=${MESHES:-$(cd "$shared/meshes" && ls ./*.obj | sed 's|^\./||')}

# cut_both MESH: OUT/NAME-acute and OUT/NAME-optimal.
cut_both() {
  local mesh=$1 name=${1%.obj} scale rule
  scale=$(scale_to_100mm "$shared/meshes/$mesh")
  for rule in acute optimal; do
    "$wearknit" cut "$shared/meshes/$mesh" --scale "$scale" --vanishing "$rule" \
      -o "$out/$name-$rule" -q --no-pictures >"$out/$name-$rule.log" 2>&1 ||
      echo "$name: cut --vanishing $rule failed (see $out/$name-$rule.log)" >&2
  done
}

# shellcheck disable=SC2086 # one mesh per word
for_each_mesh cut_both $meshes
python3 bench/vanishing_table.py "$out" "$command" $(echo "$meshes" | sed 's|\.obj||g')
