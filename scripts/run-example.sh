#!/usr/bin/env bash
# Quick start 1: installs what is missing, builds, and turns the bundled example tree into a
# watertight model out/tree_rtwig.glb, with its measurements (out/tree_rtwig.json), its cylinder
# table (out/tree_rtwig_qsm.csv), its skeleton (out/tree_rtwig_skeleton.ply) and a page that shows
# the cloud, the skeleton and the model in a browser (out/tree_rtwig.html).
set -euo pipefail
trap 'echo "run-example: failed (exit $?) at: $BASH_COMMAND" >&2' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# Builds the command-line tool alone (the tests are built by run-tests.sh).
TREESKEL_BUILD_TARGET=${TREESKEL_BUILD_TARGET:-treeskel} "$here/scripts/setup.sh"
mkdir -p "$here/out"
"${TREESKEL_BUILD_DIR:-$here/build}/cli/treeskel" model "$here/data/tree_rtwig.txt" -o "$here/out/tree_rtwig.glb" \
  --report "$here/out/tree_rtwig.json" --qsm "$here/out/tree_rtwig_qsm.csv" \
  --skeleton "$here/out/tree_rtwig_skeleton.ply" --html "$here/out/tree_rtwig.html" "$@"
