#!/usr/bin/env bash
# Scores `treeskel skeletonize` with any options on the synthetic clouds of one seed: the means of SPD,
# BPC, EPC and their precision over all clouds, and BPC on each of the complex trees 4-6; with
# --set hard, on the harder trees of docs/accuracy.md instead, the means per set (crowded crowns,
# sparse scans of 2,000-3,000 and of 4,000-6,200 points, every degradation at once).
# A quick way to try an option on the benchmark (bench_accuracy is the full report). With --model,
# the skeleton scored is the one `treeskel model --skeleton` writes, and the options are model's
# (--complete-all, ...): its own pruning, stubs and grafts, straightened limbs.
# Usage: bench/score_synth.sh [--seed S] [--set paper|hard] [--model] [SKELETONIZE_OR_MODEL_OPTION...]
#        (TREESKEL_EXE overrides build/cli/treeskel)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
exe=${TREESKEL_EXE:-$here/build/cli/treeskel}
seed=1 set=paper model=0
while [ $# -gt 0 ]; do
  case $1 in
    --seed) seed=${2:?--seed needs a number}; shift 2 ;;
    --set) set=${2:?--set needs paper or hard}; shift 2 ;;
    --model) model=1; shift ;;
    *) break ;;
  esac
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$exe" synth "$work/clouds" --seed "$seed" --set "$set" -q
for cloud in "$work"/clouds/*.xyz; do
  name=$(basename "$cloud" .xyz)
  truth="$work/clouds/${name}_truth.json"                              # the harder trees: one per cloud
  [ -f "$truth" ] || truth="$work/clouds/${name%%_*}_truth.json"       # the paper's: one per tree
  if [ "$model" = 1 ]; then
    "$exe" model "$cloud" -o "$work/mesh.ply" --skeleton "$work/$name.json" -q "$@" 2>"$work/err" ||
      { echo "$name: treeskel model failed: $(cat "$work/err")" >&2; exit 1; }
  else
    "$exe" skeletonize "$cloud" -o "$work/$name.json" -q "$@"
  fi
  printf '{"cloud":"%s","scores":' "$name"
  "$exe" eval "$work/$name.json" "$truth" --json | tr -d '\n'
  echo '}'
done > "$work/scores.jsonl"
node -e '
  const rows = require("fs").readFileSync(process.argv[1], "utf8").trim().split("\n").map(JSON.parse);
  const mean = (list, key) => list.reduce((s, r) => s + r.scores[key], 0) / list.length;
  const keys = ["spd", "bpc", "epc", "bp_precision", "ep_precision"];
  const line = list => keys.map(k => `${k} ${mean(list, k).toFixed(3)}`).join(", ");
  const [, , seed, set] = process.argv;
  if (set === "paper") {
    const tree = r => r.cloud.split("_")[0];
    const trees = [4, 5, 6].map(t => `tree${t} BPC ${mean(rows.filter(r => tree(r) === "tree" + t), "bpc").toFixed(3)}`);
    console.log(`seed ${seed}, ${rows.length} clouds: ` + line(rows) + "; " + trees.join(", "));
  } else {
    // The sets by name: crowdedN_P, sparseB_Vviews_P (P points), treeN_all.
    const kind = r => r.cloud.endsWith("_all") ? "every degradation at once"
      : r.cloud.startsWith("crowded") ? "crowded crowns"
      : Number(r.cloud.split("_").pop()) < 3500 ? "sparse scans, 2,000-3,000 points" : "sparse scans, 4,000-6,200 points";
    const kinds = [...new Set(rows.map(kind))].sort();
    for (const k of kinds) {
      const list = rows.filter(r => kind(r) === k);
      console.log(`seed ${seed}, ${k} (${list.length} clouds): ` + line(list));
    }
  }' "$work/scores.jsonl" "$seed" "$set"
