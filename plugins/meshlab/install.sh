#!/usr/bin/env bash
# Builds treeskel's MeshLab filter plugin and installs it.
#
# Usage: plugins/meshlab/install.sh [--plugin FILE] [PREFIX]
#   (no PREFIX)    into the system MeshLab's plugin folder (as root, or through sudo)
#   PREFIX         into a private MeshLab under PREFIX: PREFIX/bin/meshlab and PREFIX/bin/meshlabserver
#                  load Debian's plugins and this one, and the system is left untouched
#   --plugin FILE  install this already built libfilter_treeskel.so instead of building one
#
# Building installs what is missing (Debian's meshlab, Qt and GLEW development packages, dpkg-dev, and
# treeskel's own dependencies), fetches MeshLab's headers from its Debian source package and builds
# the plugin into build/ (TREESKEL_BUILD_DIR elsewhere) with scripts/setup.sh.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)

plugin=""
prefix=""
while [ $# -gt 0 ]; do
  case "$1" in
    --plugin) plugin=${2:?--plugin needs a file}; shift 2 ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "install.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) [ -z "$prefix" ] || { echo "install.sh: one PREFIX only" >&2; exit 2; }; prefix=$1; shift ;;
  esac
done

if [ -z "$plugin" ]; then
  build=${TREESKEL_BUILD_DIR:-$here/build}
  TREESKEL_MESHLAB_PLUGIN=1 TREESKEL_BUILD_TARGET=filter_treeskel "$here/scripts/setup.sh"
  plugin=$build/plugins/meshlab/libfilter_treeskel.so
fi
[ -f "$plugin" ] || { echo "install.sh: no plugin at $plugin" >&2; exit 1; }

# Where Debian's MeshLab keeps libmeshlab-common.so and its plugins.
common=$(dpkg -L meshlab 2>/dev/null | grep '/libmeshlab-common\.so$' | head -n 1 || true)
[ -n "$common" ] || { echo "install.sh: Debian's meshlab package is not installed" >&2; exit 1; }
libdir=$(dirname "$common")                    # /usr/lib/<multiarch>/meshlab
multiarch=$(basename "$(dirname "$libdir")")   # <multiarch>

if [ -z "$prefix" ]; then
  sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "install.sh: run as root or install sudo (or give a PREFIX)" >&2; exit 1; }
    sudo=(sudo)
  fi
  "${sudo[@]}" install -m 644 "$plugin" "$libdir/plugins/libfilter_treeskel.so"
  echo "installed $libdir/plugins/libfilter_treeskel.so: restart MeshLab and look under Filters > Point Set"
  exit 0
fi

# A private MeshLab: the executables find libmeshlab-common.so and the plugins through their RUNPATH
# ($ORIGIN/../lib/<multiarch>/meshlab), so copies of them (not links, whose $ORIGIN is the system's)
# load whatever sits in PREFIX/lib/<multiarch>/meshlab/plugins.
mkdir -p "$prefix"
prefix=$(cd "$prefix" && pwd)
target=$prefix/lib/$multiarch/meshlab
mkdir -p "$prefix/bin" "$target/plugins"
for exe in meshlab meshlabserver; do
  install -m 755 "/usr/bin/$exe" "$prefix/bin/$exe"
done
ln -sf "$common" "$target/libmeshlab-common.so"
for p in "$libdir"/plugins/*.so; do
  [ "$(basename "$p")" = libfilter_treeskel.so ] && continue
  ln -sf "$p" "$target/plugins/$(basename "$p")"
done
install -m 644 "$plugin" "$target/plugins/libfilter_treeskel.so.partial"
mv -f "$target/plugins/libfilter_treeskel.so.partial" "$target/plugins/libfilter_treeskel.so"
echo "installed a private MeshLab with the treeskel filters: $prefix/bin/meshlab, $prefix/bin/meshlabserver"
