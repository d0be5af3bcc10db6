#!/usr/bin/env bash
# bench/skeleton_reach.sh on the bundled AdTree tree: one row with both ways' branch points and
# shares. The defaults (spurs judged with the host's points) keep no more forks than the rule on the
# nodes' radii alone (tree1: 229 against 239) and still come within 2% of the height of most points
# (0.973 against 0.975 when set); a cloud that cannot be read gives a row that says so and exit code 1.
set -uo pipefail
root=${1:?usage: skeleton_reach_script_test.sh SOURCE_DIR BUILD_DIR}
export TREESKEL_BUILD_DIR=${2:?usage: skeleton_reach_script_test.sh SOURCE_DIR BUILD_DIR}
out=$(bash "$root/bench/skeleton_reach.sh" "$root/data/tree_adtree1.xyz") ||
  { echo "FAIL: skeleton_reach.sh exited with $?"; exit 1; }
echo "$out"
row=$(grep "^| tree_adtree1.xyz |" <<<"$out")
[ -n "$row" ] || { echo "FAIL: no row"; exit 1; }
IFS='|' read -r _ name forks shares other_forks other_shares rest <<<"$row"
[ -z "${rest// /}" ] || { echo "FAIL: more than 5 columns: $row"; exit 1; }
read -r near1 _ near2 <<<"$shares"
read -r other1 _ other2 <<<"$other_shares"
awk -v f="$forks" -v of="$other_forks" -v a="$near1" -v b="$near2" -v c="$other1" -v d="$other2" 'BEGIN {
  if (!(f > 50 && of >= f)) { print "FAIL: branch points " f " against " of; exit 1 }
  if (!(a > 0 && a <= b && b <= 1 && c > 0 && c <= d && d <= 1)) { print "FAIL: shares " a " / " b ", " c " / " d; exit 1 }
  if (!(b >= 0.95 && d >= b - 0.001)) { print "FAIL: within 2% " b " (other " d ")"; exit 1 }
}' || exit 1
echo "not a cloud" >"${TMPDIR:-/tmp}/skeleton_reach_bad.xyz"
bad=$(bash "$root/bench/skeleton_reach.sh" "${TMPDIR:-/tmp}/skeleton_reach_bad.xyz")
code=$?
rm -f "${TMPDIR:-/tmp}/skeleton_reach_bad.xyz"
[ "$code" -eq 1 ] || { echo "FAIL: exit code $code for an unreadable cloud"; exit 1; }
grep -q "failed:" <<<"$bad" || { echo "FAIL: no failed row: $bad"; exit 1; }
echo "ok"
