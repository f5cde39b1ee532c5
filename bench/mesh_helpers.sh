# Helpers of the bench scripts that run over the shared meshes (sourced).

# The factor that brings the longest side of the OBJ file $1 to 100 mm.
scale_to_100mm() {
  python3 -c 'import sys
v = [list(map(float, l.split()[1:4])) for l in open(sys.argv[1]) if l.startswith("v ")]
print(repr(100 / max(max(p[i] for p in v) - min(p[i] for p in v) for i in range(3))))' "$1"
}

# Runs the function $1 on each of the other arguments, $JOBS (default 2) at once.
for_each_mesh() {
  local run=$1 mesh
  shift
  for mesh in "$@"; do
    while [ "$(jobs -rp | wc -l)" -ge "${JOBS:-2}" ]; do wait -n; done
    "$run" "$mesh" &
  done
  wait
}
