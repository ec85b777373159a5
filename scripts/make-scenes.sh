#!/usr/bin/env bash
# Regenerates data/scenes/: the built-in scenes as PLY meshes with JSON ground-truth sidecars
# (closed-box, room, crates, paper-setting-1, paper-setting-2). Deterministic; committed.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
"${FVX_BUILD_DIR:-build}/src/fvx_make_scenes" data/scenes
