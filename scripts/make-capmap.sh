#!/usr/bin/env bash
# Regenerates data/arms/fvx-arm.fcm: the capability map of the project's own arm
# (data/arms/fvx-arm.urdf) at 10 cm, 200 directions, seed 1 — small enough to commit (150 KB)
# for the tests and the demo. Deterministic on any thread count; about 20 s on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
"${FVX_BUILD_DIR:-build}/src/fvx" capmap build data/arms/fvx-arm.urdf --base base_link --tip kinect_optical \
  --voxel 0.1 --directions 200 --seed 1 -o data/arms/fvx-arm.fcm >/dev/null
echo "wrote data/arms/fvx-arm.fcm"
