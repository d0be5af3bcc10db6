#!/usr/bin/env bash
# Prints one Markdown row per cloud: how much of it `treeskel model` (default options) shows: the
# share of the cloud's points within 1% and 2% of its height from the mesh's surface, the mesh's
# reach along the up axis over the cloud's, and the mesh's own coverage of the skeleton's length.
# A cloud with a `foliage` column (arbor's: 0 = wood) is measured on its wood points only.
# Usage: bench/coverage.sh [--up y] [--FLAG...] CLOUD...   (TREESKEL_BUILD_DIR overrides build/)
# Flags other than --up (e.g. --complete, --no-unite) go to `treeskel model` as they are.
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}
extra=()
up=z
while [ "${1:-}" != "${1#--}" ]; do
  if [ "$1" = "--up" ]; then extra+=(--up "$2"); up=$2; shift 2; else extra+=("$1"); shift; fi
done
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
echo "| cloud | points | within 1% | within 2% | reach | skeleton length in the mesh | seconds |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for f in "$@"; do
  name=$(basename "$f")
  input=$f
  if head -1 "$f" | grep -q foliage; then
    # Wood only: the column named foliage is 0.
    awk 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "foliage" && !c) c = i - 1; next }
         $c == 0 { print $1, $2, $3 }' "$f" > "$dir/wood.xyz"
    input=$dir/wood.xyz
    name="$name (wood)"
  fi
  if "$build/cli/treeskel" model "$input" "${extra[@]}" -q --local -o "$dir/m.ply" --report "$dir/r.json" 2>"$dir/err"; then
    line=$("$build/bench/bench_coverage" --up "$up" "$input" "$dir/m.ply")
    node -e '
      const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
      const m = /^(\d+) points.*within 1% ([\d.]+), within 2% ([\d.]+), reach ([\d.]+)/.exec(process.argv[3]);
      console.log(`| ${process.argv[2]} | ${m[1]} | ${m[2]} | ${m[3]} | ${m[4]} | ${j.mesh.skeleton_coverage.toFixed(3)} | ${j.seconds.total.toFixed(2)} |`);' \
      "$dir/r.json" "$name" "$line"
  else
    echo "| $name | | | | | | $(tr '\n|' '  ' <"$dir/err") |"
  fi
done
