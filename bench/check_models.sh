#!/usr/bin/env bash
# Runs 'treeskel model' on every cloud given and prints one Markdown row per cloud: points, mesh
# size, the checks (closed, manifold, self-intersections, components, volume), what the sweep gave
# up or thinned, DBH and time. A cloud whose mesh fails its checks shows the error instead.
# Usage: bench/check_models.sh [--up y] CLOUD... (TREESKEL_EXE overrides build/cli/treeskel)
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exe=${TREESKEL_EXE:-$here/build/cli/treeskel}
extra=()
if [ "${1:-}" = "--up" ]; then extra=(--up "$2"); shift 2; fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
echo "| cloud | points | triangles | closed | manifold | self-intersections | components | volume | twigs inside joins | thinned / left out | DBH | seconds |"
echo "|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|"
for f in "$@"; do
  name=$(basename "$f")
  if "$exe" model "$f" "${extra[@]}" -q -o "$dir/m.glb" --report "$dir/r.json" 2>"$dir/err"; then
    node -e '
      const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8")), m = j.mesh;
      const dbh = j.measurements.dbh === null ? "n/a" : j.measurements.dbh.toFixed(3);
      console.log(`| ${process.argv[2]} | ${j.points} | ${m.triangles} | ${m.closed ? "yes" : "NO"} | ${m.manifold ? "yes" : "NO"} | ` +
        `${m.self_intersections} | ${m.components} | ${m.volume.toPrecision(3)} | ${m.twigs_absorbed} | ` +
        `${m.joins_thinned + m.repaired_shrunk} / ${m.joins_dropped + m.repaired_dropped} | ${dbh} | ${j.seconds.total.toFixed(2)} |`);' "$dir/r.json" "$name"
  else
    echo "| $name | | | | | | | | | | | $(tr '\n|' '  ' <"$dir/err") |"
  fi
done
