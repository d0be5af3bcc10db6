#!/usr/bin/env bash
# Throughput of `treeskel batch` with 1 job and with as many jobs as cores, on 20 synthetic clouds of
# `treeskel synth` (trees 4-6, the larger ones: 8k-46k points each), models as GLB.
# Usage: bench/batch.sh [--seed S]   (TREESKEL_BUILD_DIR overrides build/)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}
seed=1
if [ "${1:-}" = "--seed" ]; then seed=${2:?--seed needs a number}; shift 2; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/cli/treeskel" synth "$work/all" --seed "$seed" -q
mkdir "$work/in"
for f in $(ls "$work"/all/tree[456]_*.xyz | sort | head -20); do mv "$f" "$work/in/"; done
cores=$(nproc)
time_of() {  # wall seconds of one batch run with $1 jobs
  local start end
  start=$(date +%s.%N)
  "$build/cli/treeskel" batch "$work/in" -o "$work/out$1" -j "$1" -q
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { print b - a }'
}
one=$(time_of 1)
many=$(time_of "$cores")
printf '| clouds | jobs | wall seconds | trees a minute |\n|---:|---:|---:|---:|\n'
printf '| 20 | 1 | %.2f | %.1f |\n' "$one" "$(awk -v t="$one" 'BEGIN { print 1200 / t }')"
printf '| 20 | %d | %.2f | %.1f |\n' "$cores" "$many" "$(awk -v t="$many" 'BEGIN { print 1200 / t }')"
printf '\n%d jobs give %.2fx the throughput of 1 on %s (%d cores)\n' "$cores" "$(awk -v a="$one" -v b="$many" 'BEGIN { print a / b }')" \
  "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')" "$cores"
