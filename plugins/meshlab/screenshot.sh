#!/usr/bin/env bash
# Screenshots of the plugin in the real MeshLab GUI, under Xvfb, for the README: the dialog of
# "Tree Mesh from Point Cloud" on the bundled rTwig cloud, and MeshLab after applying it.
# Usage: plugins/meshlab/screenshot.sh PREFIX OUT_DIR
#   PREFIX: a private MeshLab made by plugins/meshlab/install.sh PREFIX
# Needs xvfb, xdotool and imagemagick (Debian packages). The dialog is opened by its name through
# MeshLab's filter search (gui-open-filter.sh), and its buttons found from its window's geometry.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
prefix=${1:?usage: screenshot.sh PREFIX OUT_DIR}
out=${2:?usage: screenshot.sh PREFIX OUT_DIR}
for tool in Xvfb xdotool import; do
  command -v $tool >/dev/null || { echo "screenshot.sh: $tool is missing (apt-get install xvfb xdotool imagemagick)" >&2; exit 1; }
done
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The bundled cloud as a PLY that MeshLab opens without asking for a format.
n=$(awk 'NF >= 3' "$here/data/tree_rtwig.txt" | wc -l)
{ printf 'ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n' "$n"
  awk 'NF >= 3 {print $1, $2, $3}' "$here/data/tree_rtwig.txt"; } > "$work/tree_rtwig.ply"

cat > "$work/session.sh" <<SESSION
set -euo pipefail
"$prefix/bin/meshlab" "$work/tree_rtwig.ply" > "$work/meshlab.log" 2>&1 &
meshlab=\$!
read -r apply_x apply_y close_x close_y < <("$here/plugins/meshlab/gui-open-filter.sh" "Tree Mesh from Point Cloud")
import -window root -crop 520x1024+0+0 "$out/meshlab_tree_mesh_dialog.png"
xdotool mousemove \$apply_x \$apply_y click 1; sleep 8
xdotool mousemove \$close_x \$close_y click 1; sleep 1
# Turn the view from the top to the side: drag the trackball down the middle of the viewer.
xdotool mousemove 217 470 mousedown 1 mousemove 217 400 mousemove 217 300 mousemove 217 200 mouseup 1; sleep 1
xdotool mousemove 471 114 click 1; sleep 2         # hide the cloud's layer
# The layer list and the viewer, not the log (it names the temporary files).
import -window root -crop 860x600+0+0 "$out/meshlab_tree_mesh_result.png"
kill \$meshlab
SESSION
"$here/plugins/meshlab/with-xvfb.sh" -s "-screen 0 1280x1024x24" bash "$work/session.sh"
echo "wrote $out/meshlab_tree_mesh_dialog.png and $out/meshlab_tree_mesh_result.png"
