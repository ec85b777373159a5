#!/usr/bin/env bash
# Regenerates data/scenes/: the built-in scenes as PLY meshes with JSON ground-truth sidecars
# (closed-box, room, crates, paper-setting-1, paper-setting-2). Deterministic; committed.
#   scripts/make-scenes.sh                 data/scenes/
#   scripts/make-scenes.sh suite [DIR]     the default scene suite (builtin:suite/1..24) into DIR
#                                          (default scenes-suite/): to open in a viewer or edit
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
if [ "${1:-}" = suite ]; then
  "${FVX_BUILD_DIR:-build}/src/fvx_make_scenes" "${2:-scenes-suite}" $(seq -f 'suite/%g' 1 24)
else
  "${FVX_BUILD_DIR:-build}/src/fvx_make_scenes" data/scenes
fi
