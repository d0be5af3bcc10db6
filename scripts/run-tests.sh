#!/usr/bin/env bash
# Quick start 2: installs what is missing, builds, and runs the whole test suite in parallel.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# The suite includes the MeshLab plugin's tests in the real (headless) MeshLab.
TREESKEL_MESHLAB_PLUGIN=1 "$here/scripts/setup.sh"
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir "${TREESKEL_BUILD_DIR:-$here/build}" -j "$jobs" --output-on-failure "$@"
