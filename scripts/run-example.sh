#!/usr/bin/env bash
# Quick start 1: installs what is missing, builds, and skeletonizes the bundled example tree into
# out/tree_rtwig_skeleton.ply (open it in MeshLab or CloudCompare).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$here/scripts/setup.sh"
mkdir -p "$here/out"
"${TREESKEL_BUILD_DIR:-$here/build}/cli/treeskel" skeletonize "$here/data/tree_rtwig.txt" -o "$here/out/tree_rtwig_skeleton.ply" "$@"
