# Shared by bench/linking.sh and bench/arc_order.sh (after plan_common.sh):
# each mesh of $MESHES cut at 100 mm along its longest side with the
# defaults (`wearknit cut`), then its wearability stage over the mesh itself
# once per mode, one after the other, each in a copy of the cut.
#   wearability_modes MODE=OPTIONS ...
# Fills `rows` with NAME:MODE:FOLDER:WALL_SECONDS, one per run (read them
# with bench/wearability_runs.py), and prints the machine's load and each
# run's time on stderr.
wearability_modes() {
  echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)" >&2
  rows=()
  local mesh name spec mode extra dir start wall
  for mesh in $MESHES; do
    name=${mesh%.obj}
    "$wearknit" cut "$shared/meshes/$mesh" --scale "$(scale_to_100mm "$shared/meshes/$mesh")" \
      -o "$out/$name-cut" -q --no-pictures
    for spec in "$@"; do
      mode=${spec%%=*}
      extra=${spec#*=}
      dir="$out/$name-$mode"
      rm -rf "$dir"
      cp -r "$out/$name-cut" "$dir"
      start=$(date +%s.%N)
      # shellcheck disable=SC2086
      "$wearknit" wearability "$dir" --wearer "$shared/meshes/$mesh" --threads 2 --quiet \
        $extra >/dev/null 2>"$dir.err" || true
      wall=$(python3 -c "import time; print('%.1f' % (time.time() - $start))")
      echo "$name $mode: ${wall} s" >&2
      rows+=("$name:$mode:$dir:$wall")
    done
  done
}
