#!/usr/bin/env bash
# Installs what wearknit needs, builds it, and runs the main job on its
# built-in default: `wearknit demo`, writing ./wearknit-demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release >/dev/null
exec build-release/apps/wearknit/wearknit demo "$@"
