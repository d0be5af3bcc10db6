#!/usr/bin/env bash
# Quick start 2: installs what is missing, builds, and runs the whole test suite in parallel:
#   1. every test (unit, end-to-end, MeshLab under Xvfb, glTF validator, the --html pages in headless
#      Chromium, the Python package with pytest and a local Dask cluster) in build/;
#   2. the unit and end-to-end tests again in an AddressSanitizer + UndefinedBehaviorSanitizer build
#      (float-cast-overflow too; any report fails the test) in build-asan/;
#   3. each reader's fuzz target for a short time (scripts/fuzz.sh; TREESKEL_FUZZ_SECONDS, default 20).
# Usage: scripts/run-tests.sh [--quick] [ctest options...]
#        --quick   the library's unit tests alone (ctest -L unit), step 1 only
#        TREESKEL_SKIP_SANITIZE=1 / TREESKEL_SKIP_FUZZ=1   leave out step 2 / step 3
set -euo pipefail
trap 'echo "run-tests: failed (exit $?) at: $BASH_COMMAND" >&2' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TREESKEL_BUILD_DIR:-$here/build}
jobs=$(nproc 2>/dev/null || echo 2)
if [ "${1:-}" = --quick ]; then
  shift
  "$here/scripts/setup.sh"
  exec ctest --test-dir "$build" -j "$jobs" --output-on-failure -L unit "$@"
fi
failed=()
# 1. The suite, with the MeshLab plugin's tests in the real (headless) MeshLab and the Python package's.
TREESKEL_MESHLAB_PLUGIN=1 TREESKEL_PYTHON=1 TREESKEL_BROWSER=1 "$here/scripts/setup.sh"
echo "run-tests: the whole suite" >&2
ctest --test-dir "$build" -j "$jobs" --output-on-failure "$@" || failed+=("the suite (build/)")

# 2. The same unit and end-to-end tests under the sanitizers.
if [ "${TREESKEL_SKIP_SANITIZE:-0}" != 1 ]; then
  echo "run-tests: building the sanitizer build (build-asan/)" >&2
  TREESKEL_BUILD_DIR="$here/build-asan" \
  TREESKEL_CMAKE_ARGS="-DTREESKEL_SANITIZE=ON -DTREESKEL_BUILD_BENCH=OFF -DTREESKEL_BUILD_EXAMPLES=OFF" \
    TREESKEL_SKIP_INSTALL=1 "$here/scripts/setup.sh"
  echo "run-tests: unit and end-to-end tests under ASan + UBSan" >&2
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir "$here/build-asan" -j "$jobs" --output-on-failure -L 'unit|e2e' "$@" ||
    failed+=("the sanitizer build (build-asan/)")
fi

# 3. The readers' fuzz targets, briefly (a long run is recorded in docs/reliability.md).
if [ "${TREESKEL_SKIP_FUZZ:-0}" != 1 ]; then
  "$here/scripts/fuzz.sh" "${TREESKEL_FUZZ_SECONDS:-20}" || failed+=("fuzzing (build-fuzz/findings/)")
fi

if [ ${#failed[@]} -gt 0 ]; then
  for f in "${failed[@]}"; do echo "run-tests: FAILED: $f" >&2; done
  echo "run-tests: rerun one test with ctest --test-dir DIR -R NAME -V" >&2
  exit 1
fi
echo "run-tests: all passed" >&2
