#!/usr/bin/env bash
# Sets up, builds and runs every test of Pliant:
#   1. Release build of everything (engine, CLI, plugins, editor) and all its
#      tests: unit, integration, plugins, render (EGL), editor (headless UI).
#   2. clang build of the engine with AddressSanitizer + UBSan: the unit tests
#      again (except long optimisation runs labelled no_asan, which the Release
#      pass covers), and the libFuzzer targets for a bounded number of executions.
# Usage: scripts/test.sh [--no-sanitize]
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-$(nproc)}

bash scripts/setup.sh

# Ninja schedules the two cores better than make; an existing build folder keeps
# the generator it was configured with.
generator() {
  local cache="$1/CMakeCache.txt"
  if [ -f "$cache" ]; then sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$cache"
  elif command -v ninja >/dev/null; then echo Ninja
  else echo "Unix Makefiles"; fi
}

echo "== Release build"
cmake -S . -B build -G "$(generator build)" -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$JOBS"
echo "== Tests (Release)"
# Under a virtual X server when one can be started, so the GLFW-window render
# test runs too (the EGL tests need no display).
XVFB=()
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then XVFB=(xvfb-run -a -s "-screen 0 1920x1080x24"); fi
(cd build && "${XVFB[@]}" ctest --output-on-failure -j"$JOBS" --timeout 600)

if [ "${1:-}" != "--no-sanitize" ]; then
  echo "== Sanitizer + fuzz build (clang, ASan + UBSan)"
  # Line tables only: sanitizer reports keep file:line, the build skips full
  # debug info (a third of this pass's compile and link time). No editor, bench
  # or end-to-end tests: this pass runs the unit and fuzz tests. -O1, not -O2: clang
  # with ASan spends far less in the optimiser (articulated dynamics.cpp 54 -> 30 CPU s).
  CC=clang CXX=clang++ cmake -S . -B build-asan -G "$(generator build-asan)" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DPLIANT_EDITOR=OFF -DPLIANT_BENCH=OFF -DPLIANT_SANITIZE=ON -DPLIANT_FUZZ=ON -DPLIANT_INTEGRATION_TESTS=OFF
  cmake --build build-asan -j"$JOBS" --target unit_and_fuzz_tests
  echo "== Unit and fuzz tests under ASan + UBSan"
  (cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
     ctest --output-on-failure -j"$JOBS" -L 'unit|fuzz' -LE no_asan --timeout 600)
fi
echo "== All tests passed"
