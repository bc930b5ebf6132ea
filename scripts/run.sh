#!/usr/bin/env bash
# Sets up, builds and runs Pliant's main job.
#  - With a display ($DISPLAY or $WAYLAND_DISPLAY): opens the editor on the
#    default scene (assets/scenes/plume_2d.json).
#  - Without one: runs the default job headless through the editor's job runner,
#    renders every frame with the editor's renderer (EGL), and writes PNGs to
#    out/default/frames/ (the take itself goes to out/default/take/).
# Usage: scripts/run.sh [SCENE]
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-$(nproc)}
SCENE=${1:-assets/scenes/plume_2d.json}

bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$JOBS"

if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  exec build/bin/pliant-editor "$SCENE"
fi

OUT=out/default
rm -rf "$OUT"
mkdir -p "$OUT"
echo "No display: running $SCENE headless"
build/bin/pliant-editor --headless "$SCENE" --run --take "$OUT/take" --render-frames "$OUT/frames"
n=$(ls "$OUT/frames" | wc -l)
echo "Wrote $n rendered frames to $(pwd)/$OUT/frames/ (take: $(pwd)/$OUT/take)"
