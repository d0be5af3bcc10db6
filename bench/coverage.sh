#!/usr/bin/env bash
# Prints one Markdown row per cloud: how much of it `treeskel model` (default options) shows: the
# share of the cloud's points within 1% and 2% of its height from the mesh's surface, the mesh's
# reach along the up axis over the cloud's, the mesh's own coverage of the skeleton's length, and the
# written file's checks as a reader meets it (bench_coverage --check). Two more columns say whose
# loss the rest is: the share of the points within 1% / 2% of the height from the skeleton's own axis
# (the skeleton `model --skeleton` writes, which the mesh is swept along), and of the points farther
# than 2% from the mesh, the share within 2% of that axis (what the mesh lost of what the skeleton
# reached; the others the skeleton never came near). The column before the last is the mesh's
# volume over the wood volume the report gives (its frustums): where a repair thinned a trunk with
# all it carries, the shares above can stay high (a thin stem still lies within 1% of the height of
# its bark) while this falls (TreeLS's pine at 0.23 until 6 December 2026). That ratio also falls
# where the frustums overlap (a branch's first segment inside its parent, a path that folds back),
# which they count twice and the mesh once; the last column does not: the share of the frustums'
# volume that lies inside the mesh (4,000 seeded samples, bench_coverage's "wood" line).
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
echo "| cloud | points | within 1% | within 2% | reach | skeleton length in the mesh | skeleton's axis: within 1% / 2% | of the points missed, near the axis | seconds | file read back: closed and manifold, components, self-intersections | mesh / wood volume | wood inside the mesh |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|"
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
  if "$build/cli/treeskel" model "$input" "${extra[@]}" -q --local -o "$dir/m.ply" --skeleton "$dir/s.ply" --report "$dir/r.json" 2>"$dir/err"; then
    if ! "$build/bench/bench_coverage" --check --skeleton "$dir/s.ply" --up "$up" "$input" "$dir/m.ply" >"$dir/cov" 2>"$dir/err"; then
      echo "| $name | | | | | | | | | the file read back: $(tr '\n|' '  ' <"$dir/err") | | |"
      continue
    fi
    node -e '
      const fs = require("fs");
      const j = JSON.parse(fs.readFileSync(process.argv[1], "utf8")), out = fs.readFileSync(process.argv[3], "utf8");
      const m = /^(\d+) points.*within 1% ([\d.]+), within 2% ([\d.]+), reach ([\d.]+)/m.exec(out);
      const f = /^file: ([^,]+), (\d+) components, (\d+) self-intersections/m.exec(out);
      const s = /^skeleton: within 1% ([\d.]+), within 2% ([\d.]+); of the (\d+) points farther than 2% from the mesh, ([\d.]+)/m.exec(out);
      const w = /^wood: frustums \S+, inside the mesh ([\d.]+)/m.exec(out);
      const file = `${f[1] === "closed and manifold" ? "yes" : f[1]}, ${f[2]}, ${f[3]}`;
      console.log(`| ${process.argv[2]} | ${m[1]} | ${m[2]} | ${m[3]} | ${m[4]} | ${j.mesh.skeleton_coverage.toFixed(3)} | ${s[1]} / ${s[2]} | ${s[3] === "0" ? "-" : s[4]} | ${j.seconds.total.toFixed(2)} | ${file} | ${(j.mesh.volume / j.measurements.volume).toFixed(3)} | ${w[1]} |`);' \
      "$dir/r.json" "$name" "$dir/cov"
  else
    echo "| $name | | | | | | | | $(tr '\n|' '  ' <"$dir/err") | | | |"
  fi
done
