#!/usr/bin/env bash
# The MeshLab plugin in the real MeshLab (Debian's meshlabserver, under Xvfb), one case per ctest test.
# Usage: meshlab_test.sh CASE PREFIX CHECKER DATA_DIR SCRIPTS_DIR WORK_DIR
#   CASE: load | skeleton-ply | skeleton-xyz | mesh-ply | mesh-xyz | mesh-complete | mesh-wood
#         | far-from-origin | bad-input | gui-bad-input
#   PREFIX: the private MeshLab that plugins/meshlab/install.sh PREFIX made
set -euo pipefail
case_name=$1 prefix=$2 checker=$3 data=$4 scripts=$5 work=$6/$1
server=$prefix/bin/meshlabserver
[ -x "$server" ] || { echo "no meshlabserver in $prefix (run plugins/meshlab/install.sh PREFIX)" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work"

# meshlabserver under a private X server (with-xvfb.sh: the command's own exit status, a display the
# server picked itself); its output in server.log.
xvfb=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/plugins/meshlab/with-xvfb.sh
run() { "$xvfb" "$server" "$@" > server.log 2>&1; }

# Writes stdin's "x y z" rows as an ASCII PLY point cloud to $1.
to_ply() {
  local rows; rows=$(cat)
  { printf 'ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n' \
      "$(printf '%s' "$rows" | grep -c .)"
    [ -z "$rows" ] || printf '%s\n' "$rows"; } > "$1"
}
three_points() { printf '0 0 0\n1 0 0\n0 1 1\n' | to_ply three.ply; }

# arbor's georeferenced tree (UTM metres) as cloud.ply: "utm" at its coordinates, "near" moved near
# the origin (a point near it subtracted), as a user must before MeshLab reads it into floats.
near_origin() {
  local shift="0 0"; [ "$1" = utm ] || shift="269600 5168550"
  grep -v '^#' "$data/tree_arbor_leafy.xyz" | awk -v s="$shift" 'BEGIN {split(s, o, " ")} NF >= 3 {printf "%.4f %.4f %s\n", $1 - o[1], $2 - o[2], $3}' | to_ply cloud.ply
}

# The bundled rTwig cloud as an ASCII PLY (MeshLab's own reader), the AdTree cloud as it is (.xyz).
input_for() {
  case $1 in
    ply) awk 'NF >= 3 {print $1, $2, $3}' "$data/tree_rtwig.txt" | to_ply cloud.ply; echo cloud.ply ;;
    xyz) cp "$data/tree_adtree1.xyz" cloud.xyz; echo cloud.xyz ;;
  esac
}

expect_ok() {
  if ! run "$@"; then cat server.log >&2; echo "meshlabserver failed" >&2; exit 1; fi
}

case $case_name in
  load)
    expect_ok -d dump.txt
    for filter in "Tree Skeleton (CPC)" "Tree Mesh from Point Cloud"; do
      grep -qF "$filter" dump.txt || { echo "filter '$filter' is not listed" >&2; exit 1; }
    done
    # Parameters of each filter: the rows of its table in the dump.
    rows() { awk -v f="$1" 'index($0, f) {on = 1; next} on && /\\section/ {exit} on && /<TR>/ {n++} END {print n + 0}' dump.txt; }
    skeleton_rows=$(rows "Tree Skeleton (CPC)") mesh_rows=$(rows "Tree Mesh from Point Cloud")
    echo "Tree Skeleton (CPC): $skeleton_rows parameters; Tree Mesh from Point Cloud: $mesh_rows parameters"
    [ "$skeleton_rows" -eq 20 ] && [ "$mesh_rows" -eq 26 ] || { echo "unexpected parameter counts" >&2; exit 1; }
    grep -qF "Level set band width" dump.txt && grep -qF "Thinnest branch kept" dump.txt
    ;;
  skeleton-ply|skeleton-xyz)
    cloud=$(input_for "${case_name#skeleton-}")
    expect_ok -i "$cloud" -o skeleton.obj -o skeleton.ply -m vq sa -s "$scripts/tree_skeleton.mlx"
    grep -F "treeskel:" server.log | head -n 1
    "$checker" skeleton skeleton.obj skeleton.ply "$cloud"
    ;;
  mesh-ply|mesh-xyz)
    cloud=$(input_for "${case_name#mesh-}")
    out=tree.obj; [ "$case_name" = mesh-xyz ] && out=tree.ply
    expect_ok -i "$cloud" -o "$out" -s "$scripts/tree_mesh.mlx"
    grep -F "treeskel:" server.log | head -n 1
    "$checker" mesh "$out" "$cloud"
    ;;
  mesh-complete)
    # "Grow through missed points" set to branches, then to every group, in copies of the bundled
    # script: checked meshes of skeletons with more nodes than the default's (the grown branches), and
    # more again with the tufts and bushes, as `treeskel model --complete` and `--complete-all` give.
    cloud=$(input_for xyz)
    nodes() { grep -F "treeskel:" server.log | head -n 1 | sed -n 's/.* -> \([0-9]*\) nodes -> .*/\1/p'; }
    expect_ok -i "$cloud" -o plain.ply -s "$scripts/tree_mesh.mlx"
    plain=$(nodes)
    grown=()
    for choice in 1 2; do
      sed "s/name=\"complete\" value=\"0\"/name=\"complete\" value=\"$choice\"/" "$scripts/tree_mesh.mlx" > complete$choice.mlx
      grep -qF "name=\"complete\" value=\"$choice\"" complete$choice.mlx
      expect_ok -i "$cloud" -o tree$choice.ply -s complete$choice.mlx
      grep -F "treeskel:" server.log | head -n 1
      grown[$choice]=$(nodes)
      "$checker" mesh tree$choice.ply "$cloud"
    done
    # A script saved when the parameter was a checkbox (RichBool, true: "branches") still runs, as "branches".
    sed 's/<Param type="RichEnum" name="complete" value="0"[^>]*>/<Param type="RichBool" name="complete" value="true"\/>/' \
      "$scripts/tree_mesh.mlx" > checkbox.mlx
    grep -qF '<Param type="RichBool" name="complete" value="true"/>' checkbox.mlx
    expect_ok -i "$cloud" -o checkbox.ply -s checkbox.mlx
    checkbox=$(nodes)
    echo "nodes: $plain by default, ${grown[1]} grown through branches, ${grown[2]} through every group, $checkbox by a checkbox script"
    [ "$checkbox" = "${grown[1]}" ] || { echo "the checkbox script did not grow branches as \"branches\" does" >&2; exit 1; }
    [ -n "$plain" ] && [ -n "${grown[1]}" ] && [ "${grown[1]}" -gt "$plain" ] || { echo "no branch grown" >&2; exit 1; }
    [ -n "${grown[2]}" ] && [ "${grown[2]}" -gt "${grown[1]}" ] || { echo "no tuft or bush grown" >&2; exit 1; }
    ;;
  mesh-wood)
    # arbor's broadleaf in leaf (the bundled quarter, as a PLY moved near the origin, see
    # far-from-origin): by default the log says it looks leafy and names the "Wood only" option;
    # with it set in a copy of the bundled script, the mesh is made of the wood and the points set
    # aside are a layer of their own (layer 1, between the cloud and the mesh), as many as the log says.
    near_origin near
    expect_ok -i cloud.ply -o plain.ply -s "$scripts/tree_mesh.mlx"
    grep -F "looks leafy" server.log | grep -qF '"Wood only"' || { cat server.log >&2; echo "no leafy warning" >&2; exit 1; }
    sed 's/name="woodOnly" value="false"/name="woodOnly" value="true"/' "$scripts/tree_mesh.mlx" > wood.mlx
    grep -qF 'name="woodOnly" value="true"' wood.mlx
    expect_ok -i cloud.ply -o tree.ply -o leaves.ply -l 1 -m sa -s wood.mlx
    line=$(grep -F -m 1 "treeskel: wood only:" server.log) || { cat server.log >&2; echo "no wood line in the log" >&2; exit 1; }
    echo "$line"
    ! grep -qF "looks leafy" server.log || { echo "warned of leaves with Wood only" >&2; exit 1; }
    said=$(printf '%s' "$line" | sed -n 's/.*points look like wood; \([0-9]*\) .*/\1/p')
    written=$(sed -n 's/^element vertex //p' leaves.ply)
    echo "leaves: $said in the log, $written in the layer"
    [ -n "$said" ] && [ "$said" -gt 0 ] && [ "$said" = "$written" ] || { echo "the leaves layer is not what the log says" >&2; exit 1; }
    "$checker" mesh tree.ply cloud.ply
    ;;
  far-from-origin)
    # At its UTM coordinates MeshLab holds arbor's tree on a grid of floats 0.5 apart: both filters
    # fail with a message that says so and what to do, and write nothing.
    near_origin utm
    for script in tree_skeleton tree_mesh; do
      rc=0; run -i cloud.ply -o out.obj -s "$scripts/$script.mlx" || rc=$?
      [ "$rc" -eq 255 ] || { cat server.log >&2; echo "$script: exit $rc, expected 255" >&2; exit 1; }
      grep -F "32-bit floats are 0.5 apart" server.log | grep -F "near the origin" | head -n 1 ||
        { cat server.log >&2; echo "$script: no message about the coordinates" >&2; exit 1; }
      [ ! -e out.obj ] || { echo "$script wrote an output" >&2; exit 1; }
    done
    ;;
  bad-input)
    to_ply empty.ply < /dev/null
    three_points
    for script in tree_skeleton tree_mesh; do
      for cloud in empty three; do
        rc=0; run -i $cloud.ply -o out.obj -s "$scripts/$script.mlx" || rc=$?
        # A failed filter ends the script with MeshLab's own error status (255); a crash would be a
        # signal (128 + n) and an abort 134.
        [ "$rc" -eq 255 ] || { cat server.log >&2; echo "$script on $cloud: exit $rc, expected 255" >&2; exit 1; }
        grep -F "failed on layer '$cloud.ply'" server.log || { cat server.log >&2; echo "no error message" >&2; exit 1; }
        [ ! -e out.obj ] || { echo "$script on $cloud wrote an output" >&2; exit 1; }
      done
    done
    ;;
  gui-bad-input)
    # In the GUI: each filter on a 3-point layer shows MeshLab's "Filter Failure" message, and after
    # it is dismissed MeshLab is still running.
    command -v xdotool >/dev/null || { echo "xdotool is missing (Debian package xdotool)" >&2; exit 1; }
    three_points
    here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
    cat > session.sh <<SESSION
set -euo pipefail
"$prefix/bin/meshlab" "$work/three.ply" > "$work/meshlab.log" 2>&1 &
meshlab=\$!
for filter in "Tree Mesh from Point Cloud" "Tree Skeleton (CPC)"; do
  read -r apply_x apply_y close_x close_y < <("$here/plugins/meshlab/gui-open-filter.sh" "\$filter")
  xdotool mousemove \$apply_x \$apply_y click 1
  failure=""
  for i in \$(seq 40); do failure=\$(xdotool search --onlyvisible --name "^Filter Failure\$" 2>/dev/null | head -n 1) && [ -n "\$failure" ] && break; sleep 0.5; done
  [ -n "\$failure" ] || { echo "\$filter: no Filter Failure message" >&2; exit 1; }
  echo "\$filter: MeshLab showed 'Filter Failure'"
  # No window manager under Xvfb: the keyboard goes where the pointer is. Return presses OK.
  eval "\$(xdotool getwindowgeometry --shell "\$failure")"
  xdotool mousemove \$((X + WIDTH / 2)) \$((Y + HEIGHT / 2)) key Return
  for i in \$(seq 20); do xdotool search --onlyvisible --name "^Filter Failure\$" >/dev/null 2>&1 || break; sleep 0.5; done
  ! xdotool search --onlyvisible --name "^Filter Failure\$" >/dev/null 2>&1 || { echo "the message did not close" >&2; exit 1; }
  kill -0 \$meshlab || { echo "\$filter: MeshLab is no longer running" >&2; exit 1; }
  xdotool mousemove \$close_x \$close_y click 1; sleep 1
done
kill -0 \$meshlab && echo "MeshLab still running after both failures"
kill \$meshlab
SESSION
    "$xvfb" -s "-screen 0 1280x1024x24" bash session.sh
    ;;
  *) echo "unknown case $case_name" >&2; exit 2 ;;
esac
