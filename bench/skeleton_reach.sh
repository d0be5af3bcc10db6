#!/usr/bin/env bash
# How near `treeskel skeletonize`'s skeleton comes to a cloud's points, with its defaults and with
# other options: one Markdown row per cloud, for each way its branch points and the share of the
# cloud's points within 1% and 2% of the cloud's height from the skeleton's axis (`bench_coverage
# --skeleton`). A skeleton that prunes more comes near fewer points; the synthetic benchmark
# (`bench_accuracy`) says whether what it pruned was a branch.
# Usage: bench/skeleton_reach.sh [--up y] [--other "OPTIONS"] CLOUD...
#        --other: the options of the second column (default: --prune-point-radius 0, the spur rule on
#        the nodes' radii). TREESKEL_BUILD_DIR overrides build/.
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}
up=z other="--prune-point-radius 0"
while [ "${1:-}" != "${1#--}" ]; do
  case $1 in
    --up) up=${2:?--up needs an axis}; shift 2 ;;
    --other) other=${2?--other needs options}; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
[ $# -gt 0 ] || { echo "usage: bench/skeleton_reach.sh [--up y] [--other \"OPTIONS\"] CLOUD..." >&2; exit 2; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
echo "| cloud | defaults: branch points | within 1% / 2% | \`$other\`: branch points | within 1% / 2% |"
echo "|---|---:|---:|---:|---:|"
status=0
for f in "$@"; do
  row="| $(basename "$f") |"
  for way in defaults other; do
    opts=()
    [ "$way" = other ] && read -r -a opts <<<"$other"
    if "$build/cli/treeskel" skeletonize "$f" --up "$up" "${opts[@]}" -q -o "$dir/s.json" --report "$dir/r.json" 2>"$dir/err" &&
       "$build/bench/bench_coverage" --up "$up" --skeleton "$dir/s.json" "$f" >"$dir/cov" 2>>"$dir/err"; then
      forks=$(grep -o '"branch_points": *[0-9]*' "$dir/r.json" | grep -o '[0-9]*$')
      shares=$(sed -n 's/^skeleton: within 1% \([0-9.]*\), within 2% \([0-9.]*\).*/\1 \/ \2/p' "$dir/cov")
      row="$row $forks | $shares |"
    else
      row="$row failed: $(tr '\n|' '  ' <"$dir/err") | |"
      status=1
    fi
  done
  echo "$row"
done
exit $status
