#!/usr/bin/env bash
# Fuzzes each reader (ply, las, xyz, skeleton_ply, skeleton_json) with libFuzzer for SECONDS seconds,
# under AddressSanitizer and UndefinedBehaviorSanitizer, starting from seed corpora made of the bundled
# files. Stops at the first crash, hang (a single input over 10 s), sanitizer report or memory blow-up
# (2 GB), and leaves the input that caused it in build-fuzz/findings/. Installs clang's fuzzer runtime
# if it is missing (as setup.sh installs packages).
# Usage: scripts/fuzz.sh [SECONDS=60] [READER...]
#        TREESKEL_FUZZ_DIR=dir     build somewhere else (default: build-fuzz/)
set -euo pipefail
trap 'echo "fuzz: failed (exit $?) at: $BASH_COMMAND" >&2' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-60}
shift || true
readers=("$@")
[ ${#readers[@]} -gt 0 ] || readers=(ply las xyz skeleton_ply skeleton_json)
build=${TREESKEL_FUZZ_DIR:-$here/build-fuzz}

TREESKEL_EXTRA_PACKAGES="clang libclang-rt-14-dev" TREESKEL_INSTALL_ONLY=1 "$here/scripts/setup.sh"
generator=()
[ -f "$build/CMakeCache.txt" ] || ! command -v ninja >/dev/null || generator=(-G Ninja)
CXX=clang++ cmake -S "$here" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTREESKEL_FUZZ=ON \
  -DTREESKEL_BUILD_TESTS=OFF -DTREESKEL_BUILD_BENCH=OFF -DTREESKEL_BUILD_EXAMPLES=OFF >/dev/null
targets=()
for r in "${readers[@]}"; do targets+=("fuzz_$r"); done
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" --target "${targets[@]}"

# Seed corpora: the bundled clouds and skeletons, cut to at most 64 KB (libFuzzer's longest input),
# plus small files of each kind written by treeskel itself.
seeds=$build/seeds
rm -rf "$seeds"; mkdir -p "$seeds"/{ply,las,xyz,skeleton_ply,skeleton_json} "$build/findings"
for f in "$here"/data/*.{xyz,txt}; do [ -f "$f" ] && head -c 65536 "$f" > "$seeds/xyz/$(basename "$f")"; done
for f in "$here"/tests/fuzz/seeds/*.ply; do cp "$f" "$seeds/ply/"; cp "$f" "$seeds/skeleton_ply/"; done
for f in "$here"/tests/fuzz/seeds/*.las; do cp "$f" "$seeds/las/"; done
for f in "$here"/tests/fuzz/seeds/*.json; do cp "$f" "$seeds/skeleton_json/"; done

status=0
for r in "${readers[@]}"; do
  corpus=$build/corpus/$r
  mkdir -p "$corpus"
  echo "fuzz: $r for ${seconds} s" >&2
  log=$build/fuzz_$r.log
  if ! "$build/fuzz/fuzz_$r" "$corpus" "$seeds/$r" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/findings/$r-" >"$log" 2>&1; then
    echo "fuzz: $r FOUND A PROBLEM (input in $build/findings/, log $log):" >&2
    grep -E "ERROR|SUMMARY|runtime error|Test unit written" "$log" | head -n 10 >&2
    status=1
    continue
  fi
  runs=$(awk '/stat::number_of_executed_units/ {print $2}' "$log")
  echo "fuzz: $r: $runs inputs, no crash, no hang, no sanitizer report" >&2
done
exit $status
