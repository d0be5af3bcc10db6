#!/usr/bin/env bash
# Installs the Debian packages treeskel needs (only those missing) and builds it into build/.
# Usage: scripts/setup.sh            install what is missing, configure, build
#        TREESKEL_BUILD_DIR=dir      build somewhere else (default: build/)
#        TREESKEL_SKIP_INSTALL=1     do not touch packages (e.g. no root and no sudo)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}

packages=(build-essential cmake pkg-config
          libcgal-dev libeigen3-dev libopenmesh-dev libassimp-dev libboost-graph-dev libtbb-dev
          libcli11-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ] && [ "${TREESKEL_SKIP_INSTALL:-0}" != 1 ]; then
  if [ "$(id -u)" -eq 0 ]; then sudo=(); elif command -v sudo >/dev/null; then sudo=(sudo); else
    echo "setup: missing packages ${missing[*]}; run as root or install sudo" >&2; exit 1; fi
  echo "setup: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release ${TREESKEL_CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "$jobs"
