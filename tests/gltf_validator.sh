#!/usr/bin/env bash
# Exports the bundled example as .glb (with the skeleton as lines) and .gltf and runs the Khronos
# glTF validator on both: any error fails the test.
# Usage: tests/gltf_validator.sh TREESKEL_EXE
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exe=$1
validator="$here/tools/validate_gltf.js"
[ -f "$here/tools/node_modules/gltf-validator/package.json" ] || {
  echo "the glTF validator is not installed: run scripts/setup.sh" >&2; exit 1; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$exe" model "$here/data/tree_rtwig.txt" -q -o "$dir/tree.glb" --with-skeleton
"$exe" model "$here/data/tree_adtree1.xyz" -q -o "$dir/tree.gltf"
node "$validator" "$dir/tree.glb" "$dir/tree.gltf"
