# Shared by bench/plan_all.sh and bench/plan_results.sh: the wearknit binary
# of the build folder given as $1 (default build), ../shared, and the output
# folder $OUT (default a temporary one, removed on exit); $WEARKNIT overrides the binary.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${1:-build}
shared=${WEARKNIT_SHARED:-../shared}
wearknit=${WEARKNIT:-$build/apps/wearknit/wearknit}
[ -x "$wearknit" ] || { echo "no $wearknit: build it first" >&2; exit 2; }
out=${OUT:-}
if [ -z "$out" ]; then
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
fi
mkdir -p "$out"

source bench/mesh_helpers.sh
