#!/usr/bin/env bash
# Installs what treeskel needs (only what is missing) and builds it into build/.
# Usage: scripts/setup.sh              install what is missing, configure, build
#        TREESKEL_BUILD_DIR=dir        build somewhere else (default: build/)
#        TREESKEL_SKIP_INSTALL=1       do not touch packages (e.g. no root and no sudo)
#        TREESKEL_MESHLAB_PLUGIN=1     also the MeshLab plugin and its tests: Debian's MeshLab, Qt, GLEW,
#                                      Xvfb, and MeshLab's headers from its source package
#        TREESKEL_PYTHON=1             also the Python package and its tests: pybind11, Debian's python3
#                                      with numpy, pytest and dask.distributed
#        TREESKEL_BROWSER=1            also Debian's Chromium: --preview's PNG pictures, and the tests that
#                                      open the --html pages in a real (headless) browser
#        TREESKEL_BUILD_TARGET=name    build this target only
#        TREESKEL_EXTRA_PACKAGES="a b" also these Debian packages (e.g. clang for scripts/fuzz.sh)
#        TREESKEL_INSTALL_ONLY=1       install what is missing and stop (no build)
set -euo pipefail
trap 'echo "setup: failed (exit $?) at: $BASH_COMMAND" >&2' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}

# Installs Debian packages as root, or through sudo.
apt_install() {
  [ "${TREESKEL_SKIP_INSTALL:-0}" = 1 ] && return 0
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null; then sudo=(sudo); else
      echo "setup: missing packages $*; run as root or install sudo" >&2; exit 1; fi
  fi
  echo "setup: installing $*" >&2
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

packages=(build-essential cmake ninja-build pkg-config
          libcgal-dev libeigen3-dev libopenmesh-dev libassimp-dev libboost-graph-dev libtbb-dev
          libcli11-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev zlib1g-dev)
meshlab=${TREESKEL_MESHLAB_PLUGIN:-0}
if [ "$meshlab" = 1 ]; then
  packages+=(meshlab qtbase5-dev libqt5opengl5-dev libglew-dev dpkg-dev xvfb xauth xdotool)
fi
python=${TREESKEL_PYTHON:-0}
if [ "$python" = 1 ]; then
  packages+=(pybind11-dev python3-dev python3-numpy python3-pytest python3-distributed)
fi
[ "${TREESKEL_BROWSER:-0}" = 1 ] && packages+=(chromium fonts-dejavu-core)
read -r -a extra <<< "${TREESKEL_EXTRA_PACKAGES:-}"
packages+=("${extra[@]}")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] || apt_install "${missing[@]}"
[ "${TREESKEL_INSTALL_ONLY:-0}" = 1 ] && exit 0

# Node tools from npm (tools/package.json): laz-perf, the LAZ decoder the readers run for .laz files
# (Debian has no LAZ library); three.js and esbuild, which the build bundles into the --html pages'
# script; the Khronos glTF validator and playwright-core, which the tests check exported glTF and the
# pages with (not needed when building the MeshLab plugin alone).
if [ "${TREESKEL_BUILD_TARGET:-}" != filter_treeskel ]; then
  if ! command -v node >/dev/null || ! command -v npm >/dev/null; then apt_install nodejs npm; fi
  missing_npm=0
  for m in gltf-validator laz-perf three esbuild playwright-core; do
    [ -f "$here/tools/node_modules/$m/package.json" ] || missing_npm=1
  done
  if command -v npm >/dev/null && [ "$missing_npm" = 1 ]; then
    echo "setup: installing laz-perf, three.js, esbuild, the glTF validator and playwright-core (npm) into tools/" >&2
    (cd "$here/tools" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  fi
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake_args=(-DCMAKE_BUILD_TYPE=Release)
if [ "$meshlab" = 1 ]; then
  # MeshLab's headers, from the Debian source package of the installed MeshLab (kept in the build dir).
  "$here/plugins/meshlab/fetch-meshlab-source.sh" "$build/meshlab-source"
  cmake_args+=(-DTREESKEL_MESHLAB_PLUGIN=ON "-DMESHLAB_SOURCE_DIR=$build/meshlab-source")
fi
[ "$python" = 1 ] && cmake_args+=(-DTREESKEL_PYTHON=ON)
# Ninja for a new build folder: it compiles a target's own sources while the libraries it links are
# still being built, where make's generator waits for them and leaves a core idle; a folder made
# before keeps the generator it was made with.
[ -f "$build/CMakeCache.txt" ] || ! command -v ninja >/dev/null || cmake_args+=(-G Ninja)
cmake -S "$here" -B "$build" "${cmake_args[@]}" ${TREESKEL_CMAKE_ARGS:-} >/dev/null
target=()
[ -z "${TREESKEL_BUILD_TARGET:-}" ] || target=(--target "$TREESKEL_BUILD_TARGET")
cmake --build "$build" -j "$jobs" "${target[@]}"
