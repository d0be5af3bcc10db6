#!/usr/bin/env bash
# bench/coverage.sh on the bundled AdTree tree: one row whose columns hold what they say. The mesh is
# closed, manifold and one piece; the shares are shares and the skeleton's within 1% is no more than
# its within 2%; the points the mesh misses are counted and measured against the skeleton's axis; and
# the skeleton's axis, being thinner than the mesh, lies near fewer points than the mesh's surface;
# the mesh holds most of the wood volume the report gives, and most of the frustums' volume lies
# inside it.
# A mesh in another frame than the cloud's (a georeferenced tree's OBJ in world coordinates) is
# refused with the way out, not measured as covering nothing.
set -uo pipefail
root=${1:?usage: coverage_script_test.sh SOURCE_DIR BUILD_DIR}
export TREESKEL_BUILD_DIR=${2:?usage: coverage_script_test.sh SOURCE_DIR BUILD_DIR}
out=$(bash "$root/bench/coverage.sh" "$root/data/tree_adtree1.xyz") || { echo "FAIL: coverage.sh exited with $?"; exit 1; }
echo "$out"
row=$(grep '^| tree_adtree1.xyz |' <<<"$out")
[ -n "$row" ] || { echo "FAIL: no row for the cloud"; exit 1; }
node -e '
  const cells = process.argv[1].split("|").slice(1, -1).map((s) => s.trim());
  const fail = (why) => { console.log("FAIL: " + why + ": " + process.argv[1]); process.exit(1); };
  if (cells.length !== 12) fail(`${cells.length} columns, not 12`);
  const [name, points, near1, near2, reach, inside, axis, missedNear, seconds, file, wood, woodInside] = cells;
  if (Number(points) !== 11855) fail("points");
  const share = (s) => { const v = Number(s); if (!(v >= 0 && v <= 1)) fail(`${s} is not a share`); return v; };
  const m1 = share(near1), m2 = share(near2);
  if (m1 > m2) fail("within 1% above within 2%");
  const [a1, a2] = axis.split("/").map((s) => share(s.trim()));
  if (a1 > a2) fail("the axis within 1% above its within 2%");
  if (a2 > m2) fail("the bare axis is near more points than the mesh around it");
  if (a2 < 0.8 || m2 < 0.9) fail("far less of the tree than the coverage table says");
  // Issue 12 asks 0.95 within 2% of the height of every real cloud; this one has 0.996 (0.993 while
  // the model pruned as skeletonize does) and 0.902 within 1% (0.880).
  if (m2 < 0.95 || m1 < 0.89) fail("under what the model reaches on this tree (0.95 within 2%, 0.89 within 1%)");
  if (m2 < 1 && missedNear === "-") fail("points missed but none measured against the axis");
  if (missedNear !== "-") share(missedNear);
  if (!(Number(seconds) > 0)) fail("seconds");
  if (file !== "yes, 1, 0") fail("the file read back is not one closed, manifold piece free of self-intersection");
  if (!(Number(wood) >= 0.7 && Number(wood) <= 1.1)) fail("the mesh holds far more or less than the wood volume reported");
  if (share(woodInside) < 0.9) fail("less than 0.9 of the frustum volume inside the mesh");
' "$row" || exit 1

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
awk '{ printf "%.3f %.3f %s\n", $1 + 500000, $2 + 5000000, $3 }' "$root/data/tree_adtree1.xyz" > "$dir/utm.xyz"
"$TREESKEL_BUILD_DIR/cli/treeskel" model "$dir/utm.xyz" -q -o "$dir/world.obj" || { echo "FAIL: model of the shifted tree"; exit 1; }
if "$TREESKEL_BUILD_DIR/bench/bench_coverage" "$dir/utm.xyz" "$dir/world.obj" >"$dir/out" 2>"$dir/err"; then
  echo "FAIL: a mesh in world coordinates was measured against the local cloud: $(cat "$dir/out")"
  exit 1
fi
grep -q -- "--local" "$dir/err" || { echo "FAIL: no hint of --local: $(cat "$dir/err")"; exit 1; }
