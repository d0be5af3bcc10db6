#!/usr/bin/env bash
# The pages and previews in a real headless browser (Debian's chromium, driven by playwright-core from
# npm; tools/check_page.js): `model --html --preview` and `skeletonize --html` of the bundled trees
# load from disk with no console error and no network request, draw the tree where its cloud is, and
# their toggles change what is drawn; the preview PNG is made without a display and is not blank;
# `batch --html --preview` links every tree's page and picture from index.html.
# Usage: tests/view/browser_test.sh TREESKEL_EXE
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
exe=$1
check="$here/tools/check_page.js"
[ -f "$here/tools/node_modules/playwright-core/package.json" ] || {
  echo "playwright-core is not installed: run scripts/setup.sh" >&2; exit 1; }
[ -x "${TREESKEL_CHROMIUM:-/usr/bin/chromium}" ] || {
  echo "chromium is not installed: TREESKEL_BROWSER=1 scripts/setup.sh installs it" >&2; exit 1; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
unset DISPLAY  # nothing may need a display

# A verdict on check_page.js's JSON, by Debian's python3: each failed expectation is printed.
verdict() {
  /usr/bin/python3 - "$@" <<'PY'
import json, sys
kind, path = sys.argv[1], sys.argv[2]
d = json.load(open(path))
bad = []
def need(ok, what):
    if not ok:
        bad.append(what)
if kind == "page":
    need(d["ready"], "the page did not finish drawing")
    need(not d["errors"], "console errors: %s" % d["errors"])
    need(not d["requests"], "network requests: %s" % d["requests"])
    drawn = d["drawn"]
    need(0.01 < drawn["all"]["share"] < 0.6, "share of the view drawn: %.3f" % drawn["all"]["share"])
    layers = [k for k in ("cloud", "skeleton", "mesh") if k in drawn and drawn[k]["share"] > 0]
    need(len({drawn[k]["checksum"] for k in layers}) == len(layers), "the layers' toggles do not change the picture")
    need(drawn["status"]["checksum"] != drawn["height"]["checksum"], "the cloud's colouring does not change the picture")
    # The tree is drawn where its cloud is: the boxes of the cloud alone and of the model alone agree.
    cloud = drawn["cloud"]["box"]
    for k in ("skeleton", "mesh"):
        if k in drawn and drawn[k]["box"]:
            b = drawn[k]["box"]
            ix = max(0, min(cloud[2], b[2]) - max(cloud[0], b[0])) * max(0, min(cloud[3], b[3]) - max(cloud[1], b[1]))
            union = (cloud[2] - cloud[0]) * (cloud[3] - cloud[1]) + (b[2] - b[0]) * (b[3] - b[1]) - ix
            need(ix / union > 0.8, "the %s is not where the cloud is (box overlap %.2f)" % (k, ix / union))
    # The tree fills the view's height, not a corner of it.
    need(cloud[3] - cloud[1] > 0.5, "the cloud fills %.2f of the view's height" % (cloud[3] - cloud[1]))
elif kind == "image":
    need(d["width"] == 1600 and d["height"] == 800, "size %dx%d" % (d["width"], d["height"]))
    need(0.01 < d["share"] < 0.6, "share of the preview drawn: %.3f" % d["share"])
    need(d["box"] and d["box"][0] < 0.4 and d["box"][2] > 0.6, "the preview does not show both views")
for b in bad:
    print("FAIL %s: %s" % (path, b))
sys.exit(1 if bad else 0)
PY
}

failed=0
# model: one tree by itself; the other through batch below.
"$exe" model "$here/data/tree_adtree1.xyz" -q -o "$dir/a.glb" --html "$dir/a.html" --preview "$dir/a.png"
node "$check" "$dir/a.html" "$dir/a-shots" --toggles > "$dir/a.json"
verdict page "$dir/a.json" || failed=1
node "$check" --image "$dir/a.png" > "$dir/a-png.json"
verdict image "$dir/a-png.json" || failed=1

# skeletonize (the cloud and the skeleton, no mesh), at georeferenced coordinates: the page's floats
# are centred, so it shows the tree as well.
awk '{ printf "%.3f %.3f %.3f\n", $1 + 652000.5, $2 + 5762000.25, $3 + 35.0 }' "$here/data/tree_rtwig.txt" > "$dir/utm.xyz"
"$exe" skeletonize "$dir/utm.xyz" -q -o "$dir/utm.ply" --html "$dir/utm.html"
node "$check" "$dir/utm.html" "$dir/utm-shots" --toggles > "$dir/utm.json"
verdict page "$dir/utm.json" || failed=1

# batch: a page and a picture per tree, and the index linking them.
"$exe" batch "$here/data" -o "$dir/batch" -q --html --preview
for name in tree_adtree1 tree_rtwig; do
  for f in "$name.html" "$name.png"; do
    [ -s "$dir/batch/$f" ] || { echo "FAIL batch: $f is missing"; failed=1; }
    grep -q "href=\"$name.html\"" "$dir/batch/index.html" || { echo "FAIL batch: index.html does not link $name.html"; failed=1; }
    grep -q "src=\"$name.png\"" "$dir/batch/index.html" || { echo "FAIL batch: index.html does not show $name.png"; failed=1; }
  done
done
node "$check" "$dir/batch/tree_rtwig.html" "$dir/r-shots" --toggles > "$dir/r.json"
verdict page "$dir/r.json" || failed=1
node "$check" --image "$dir/batch/tree_rtwig.png" > "$dir/r-png.json"
verdict image "$dir/r-png.json" || failed=1
# A preview that cannot be made is a usage error before any work, and writes nothing.
if TREESKEL_CHROMIUM=/nonexistent/chromium "$exe" model "$here/data/tree_rtwig.txt" -q -o "$dir/no.glb" --preview "$dir/no.png" 2> "$dir/no.err"; then
  echo "FAIL: a preview with no Chromium did not fail"; failed=1
fi
[ ! -e "$dir/no.glb" ] || { echo "FAIL: a failed preview left the model behind"; failed=1; }
grep -q "needs Chromium" "$dir/no.err" || { echo "FAIL: no Chromium: $(cat "$dir/no.err")"; failed=1; }
exit $failed
