#!/usr/bin/env bash
# What setting the leaves aside does to the models of a plot: the synthetic plots of bench_plots
# (seeds 1-3, leaves as clusters at the twigs' tips, the truth per point), each run through
# `treeskel plot` by default (each tree that looks leafy modelled from its wood: --wood-if-leafy) and
# with --keep-leaves. Each model is scored against its matched true tree's wood points with
# bench_coverage: the share of the wood within 1% and 2% of the tree's height from the mesh (recall),
# the mesh's reach along z over the wood's, and the share of the mesh's vertices within 1% and 2% of
# a wood point (precision: how little of the model lies in the leaves). Prints one Markdown row per
# plot and setting (means over its trees) and the plot's seconds.
# Usage: bench/plot_wood.sh [SEED...]   (TREESKEL_BUILD_DIR overrides build/; default seeds 1 2 3)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2 3)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$build/bench/bench_plots" --write "$dir/plots" >/dev/null
echo "| plot | setting | trees modelled from their wood | wood within 1% | within 2% | reach | mesh within 1% of the wood | within 2% | seconds |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|"
for seed in "${seeds[@]}"; do
  plot=$dir/plots/plot_$seed.ply
  [ -f "$plot" ] || { echo "plot_wood: bench_plots wrote no plot of seed $seed" >&2; exit 1; }
  for setting in default --keep-leaves; do
    out=$dir/out_${seed}_${setting#--}
    args=(--model ply --local -q)
    [ "$setting" = default ] || args+=("$setting")
    start=$(date +%s.%N)
    "$build/cli/treeskel" plot "$plot" -o "$out" "${args[@]}" >/dev/null
    seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
    node "$here/bench/plot_truth.js" "$plot" "$out" "$out/truth" >/dev/null
    for truth in "$out"/truth/tree_*_wood.xyz; do
      name=$(basename "$truth" _wood.xyz)
      "$build/bench/bench_coverage" --precision --frame "$out/trees/$name.ply" "$truth" "$out/trees/${name}_mesh.ply" |
        tr '\n' ' '
      echo
    done >"$out/coverage.txt"
    from_wood=$( (grep -l '"leaves_set_aside": true' "$out"/trees/tree_*_report.json || true) | wc -l)
    awk -v plot="$seed" -v setting="$setting" -v wood="$from_wood" -v seconds="$seconds" '
      { gsub(",", ""); r1 += $7; r2 += $10; reach += $12; p1 += $19; p2 += $22; n++ }
      END { printf "| %s | %s | %d of %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.1f |\n", plot, setting, wood, n,
            r1 / n, r2 / n, reach / n, p1 / n, p2 / n, seconds }' "$out/coverage.txt"
  done
done
