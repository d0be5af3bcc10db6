#!/usr/bin/env bash
# Scores `treeskel skeletonize` with any options on the 72 synthetic clouds of one seed: the means of
# SPD, BPC, EPC and their precision over all clouds, and BPC on each of the complex trees 4-6.
# A quick way to try an option on the benchmark (bench_accuracy is the full report).
# Usage: bench/score_synth.sh [--seed S] [SKELETONIZE_OPTION...]   (TREESKEL_EXE overrides build/cli/treeskel)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exe=${TREESKEL_EXE:-$here/build/cli/treeskel}
seed=1
if [ "${1:-}" = "--seed" ]; then seed=${2:?--seed needs a number}; shift 2; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$exe" synth "$work/clouds" --seed "$seed" -q
for cloud in "$work"/clouds/*.xyz; do
  name=$(basename "$cloud" .xyz)
  tree=${name%%_*}
  "$exe" skeletonize "$cloud" -o "$work/$name.json" -q "$@"
  printf '{"cloud":"%s","tree":"%s","scores":' "$name" "$tree"
  "$exe" eval "$work/$name.json" "$work/clouds/${tree}_truth.json" --json | tr -d '\n'
  echo '}'
done > "$work/scores.jsonl"
node -e '
  const rows = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n").map(JSON.parse);
  const mean = (list, key) => list.reduce((s, r) => s + r.scores[key], 0) / list.length;
  const keys = ["spd", "bpc", "epc", "bp_precision", "ep_precision"];
  const trees = [4, 5, 6].map(t => `tree${t} BPC ${mean(rows.filter(r => r.tree === "tree" + t), "bpc").toFixed(3)}`);
  console.log(`seed ${process.argv[2]}, ${rows.length} clouds: ` + keys.map(k => `${k} ${mean(rows, k).toFixed(3)}`).join(", ") +
              "; " + trees.join(", "));' "$work/scores.jsonl" "$seed"
