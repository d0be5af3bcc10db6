#!/usr/bin/env bash
# Quick start 2: installs what is missing, builds, and runs the whole test suite in parallel.
# Usage: scripts/run-tests.sh [--quick] [ctest options...]
#        --quick   the library's unit tests alone (ctest -L unit): no MeshLab, no glTF validator
set -euo pipefail
trap 'echo "run-tests: failed (exit $?) at: $BASH_COMMAND" >&2' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}
jobs=$(nproc 2>/dev/null || echo 2)
if [ "${1:-}" = --quick ]; then
  shift
  "$here/scripts/setup.sh"
  exec ctest --test-dir "$build" -j "$jobs" --output-on-failure -L unit "$@"
fi
# The suite includes the MeshLab plugin's tests in the real (headless) MeshLab.
TREESKEL_MESHLAB_PLUGIN=1 "$here/scripts/setup.sh"
ctest --test-dir "$build" -j "$jobs" --output-on-failure "$@" || {
  echo "run-tests: some tests failed (listed above); rerun one with ctest --test-dir $build -R NAME -V" >&2
  exit 1; }
