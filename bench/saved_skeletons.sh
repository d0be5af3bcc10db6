#!/usr/bin/env bash
# The way in through a saved skeleton, against the way in through the cloud: for every cloud given,
# `treeskel skeletonize CLOUD -o s.json && treeskel model s.json` beside `treeskel model CLOUD`, one
# Markdown row each: the saved skeleton's mesh checks (closed, manifold, components, self-
# intersections, share of the skeleton inside), then DBH and wood volume both ways, and a third way:
# the skeleton `model CLOUD --skeleton f.json` saves (its radii fitted to the points), modelled again.
# A skeleton from `skeletonize` carries the level sets' radii, not circles fitted to the points, so
# it differs where those radii do (docs/models.md, "Other ways in").
# Usage: bench/saved_skeletons.sh [--up y] CLOUD... (TREESKEL_EXE overrides build/cli/treeskel)
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exe=${TREESKEL_EXE:-$here/build/cli/treeskel}
extra=()
if [ "${1:-}" = "--up" ]; then extra=(--up "$2"); shift 2; fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
echo "| cloud | triangles | closed, manifold | components | self-intersections | skeleton in the mesh | DBH: from the cloud / skeletonize's skeleton / model's skeleton | wood volume: the same three | seconds (skeletonize's skeleton's model) |"
echo "|---|---:|---|---:|---:|---:|---:|---:|---:|"
for f in "$@"; do
  name=$(basename "$f")
  if ! "$exe" model "$f" "${extra[@]}" -q -o "$dir/direct.glb" --report "$dir/direct.json" --skeleton "$dir/f.json" 2>"$dir/err" ||
     ! "$exe" skeletonize "$f" "${extra[@]}" -q -o "$dir/s.json" 2>"$dir/err" ||
     ! "$exe" model "$dir/s.json" -q -o "$dir/m.glb" --report "$dir/saved.json" 2>"$dir/err" ||
     ! "$exe" model "$dir/f.json" -q -o "$dir/m2.glb" --report "$dir/fitted.json" 2>"$dir/err"; then
    echo "| $name | | | | | | | | $(tr '\n|' '  ' <"$dir/err") |"
    continue
  fi
  node -e '
    const fs = require("fs");
    const [d, s, f] = process.argv.slice(1, 4).map((p) => JSON.parse(fs.readFileSync(p, "utf8")));
    const m = s.mesh, dbh = (j) => (j.measurements.dbh === null ? "n/a" : j.measurements.dbh.toFixed(3));
    const volume = (j) => j.measurements.volume.toFixed(3);
    console.log(`| ${process.argv[4]} | ${m.triangles} | ${m.closed && m.manifold ? "yes" : "NO"} | ${m.components} | ` +
      `${m.self_intersections} | ${m.skeleton_coverage.toFixed(3)} | ${dbh(d)} / ${dbh(s)} / ${dbh(f)} | ` +
      `${volume(d)} / ${volume(s)} / ${volume(f)} | ${s.seconds.total.toFixed(2)} |`);' \
    "$dir/direct.json" "$dir/saved.json" "$dir/fitted.json" "$name"
done
