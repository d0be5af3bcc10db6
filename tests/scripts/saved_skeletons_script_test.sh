#!/usr/bin/env bash
# bench/saved_skeletons.sh on the bundled rTwig tree: one row whose columns hold what they say. The
# saved skeleton's mesh is one closed, manifold piece free of self-intersection that holds the
# skeleton, and on this tree, whose level sets' radii agree with its fitted circles, its DBH and wood
# volume are those of the cloud's own model within a fifth (0.068 / 0.072 and 0.014 / 0.014).
set -uo pipefail
root=${1:?usage: saved_skeletons_script_test.sh SOURCE_DIR BUILD_DIR}
export TREESKEL_EXE=${2:?usage: saved_skeletons_script_test.sh SOURCE_DIR BUILD_DIR}/cli/treeskel
out=$(bash "$root/bench/saved_skeletons.sh" "$root/data/tree_rtwig.txt") || { echo "FAIL: saved_skeletons.sh exited with $?"; exit 1; }
echo "$out"
row=$(grep '^| tree_rtwig.txt |' <<<"$out")
[ -n "$row" ] || { echo "FAIL: no row for the cloud"; exit 1; }
node -e '
  const cells = process.argv[1].split("|").slice(1, -1).map((s) => s.trim());
  const fail = (why) => { console.log("FAIL: " + why + ": " + process.argv[1]); process.exit(1); };
  if (cells.length !== 9) fail(`${cells.length} columns, not 9`);
  const [name, triangles, closed, components, crossings, inside, dbh, volume, seconds] = cells;
  if (!(Number(triangles) > 1000)) fail("triangles");
  if (closed !== "yes" || components !== "1" || crossings !== "0") fail("not one closed, manifold piece free of self-intersection");
  if (!(Number(inside) >= 0.95)) fail("the mesh holds less than 0.95 of the skeleton");
  const pair = (s) => s.split("/").map((x) => Number(x.trim()));
  for (const [what, [cloud, saved]] of [["DBH", pair(dbh)], ["volume", pair(volume)]]) {
    if (!(cloud > 0 && saved > 0)) fail(`${what} not positive`);
    if (saved < 0.8 * cloud || saved > 1.25 * cloud) fail(`${what} from the saved skeleton differs from the cloud model by more than a fifth`);
  }
  if (!(Number(seconds) > 0)) fail("seconds");
' "$row"
