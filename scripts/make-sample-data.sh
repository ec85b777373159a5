#!/usr/bin/env bash
# Regenerates the bundled sample (data/sample/box-room/*.pcd): noise-free scans of a box
# room with a closed crate, poses in VIEWPOINT. Deterministic; the files are committed.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
"${FVX_BUILD_DIR:-build}/src/fvx_make_box_room" data/sample/box-room
