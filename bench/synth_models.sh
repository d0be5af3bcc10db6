#!/usr/bin/env bash
# The tree models of the 72 synthetic clouds of one seed (`treeskel synth`), where the truth is known:
# one Markdown row per cloud with the mesh checks (closed, manifold, components, self-intersections),
# the mesh's volume over the volume of the mesh of the true skeleton, and the share of the true
# skeleton's length inside the mesh (and within 1% of the height of its surface); then a summary.
# Usage: bench/synth_models.sh [--seed S] [MODEL_OPTION...]   (TREESKEL_BUILD_DIR overrides build/)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}
seed=1
if [ "${1:-}" = "--seed" ]; then seed=${2:?--seed needs a number}; shift 2; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/cli/treeskel" synth "$work/clouds" --seed "$seed" -q
# The true volume: the mesh of each true skeleton (a union, so the joins count once), along the true
# path as it is (--stiffness 0).
for truth in "$work"/clouds/*_truth.json; do
  tree=$(basename "$truth" _truth.json)
  "$build/cli/treeskel" model "$truth" -q --stiffness 0 -o "$work/$tree.glb" --report "$work/$tree.truth.json" 2>/dev/null
done
echo "| cloud | points | closed | manifold | components | self-intersections | volume / true | true skeleton inside | within 1% | seconds |"
echo "|---|---:|---|---|---:|---:|---:|---:|---:|---:|"
for cloud in "$work"/clouds/*.xyz; do
  name=$(basename "$cloud" .xyz)
  tree=${name%%_*}
  if "$build/cli/treeskel" model "$cloud" -q --local -o "$work/m.ply" --report "$work/r.json" "$@" 2>"$work/err"; then
    line=$("$build/bench/bench_coverage" --truth "$work/clouds/${tree}_truth.json" "$cloud" "$work/m.ply" | tail -1)
    node -e '
      const fs = require("fs");
      const j = JSON.parse(fs.readFileSync(process.argv[1], "utf8")), t = JSON.parse(fs.readFileSync(process.argv[2], "utf8"));
      const m = j.mesh, c = /inside the mesh ([\d.]+), within 1% of its surface ([\d.]+)/.exec(process.argv[4]);
      console.log(`| ${process.argv[3]} | ${j.points} | ${m.closed ? "yes" : "NO"} | ${m.manifold ? "yes" : "NO"} | ${m.components} | ` +
        `${m.self_intersections} | ${(m.volume / t.mesh.volume).toFixed(3)} | ${c[1]} | ${c[2]} | ${j.seconds.total.toFixed(2)} |`);' \
      "$work/r.json" "$work/$tree.truth.json" "$name" "$line"
  else
    echo "| $name | | | | | | | | | $(tr '\n|' '  ' <"$work/err") |"
  fi
done | tee "$work/rows.md"
node -e '
  const rows = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n").map(l => l.split("|").map(s => s.trim()));
  const ok = rows.filter(r => r[3] === "yes" && r[4] === "yes" && r[5] === "1" && r[6] === "0");
  const ratio = rows.filter(r => r[7]).map(r => +r[7]), inside = rows.filter(r => r[8]).map(r => +r[8]);
  const near = rows.filter(r => r[9]).map(r => +r[9]);
  const within = ratio.filter(x => Math.abs(x - 1) <= 0.10).length;
  const range = a => a.length ? `${Math.min(...a).toFixed(3)}-${Math.max(...a).toFixed(3)}` : "n/a";
  console.log(`\nseed ${process.argv[2]}, ${rows.length} clouds: ${ok.length} closed, manifold, one component, no self-intersection; ` +
    `volume / true ${range(ratio)} (${within} within 10%); true skeleton inside ${range(inside)}, within 1% ${range(near)}`);' \
  "$work/rows.md" "$seed"
