#!/usr/bin/env bash
# Integration benchmark: one 640x480 Kinect frame at 2.5 cm and 4 m through fvx and through
# OctoMap's insertPointCloud (exact and discretised), with ratios from the same run.
# Frame: a real Kinect capture from FVX_REAL_DATA when available, else a synthetic one.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh >/dev/null
build="${FVX_BUILD_DIR:-build}"
data="${FVX_REAL_DATA:-../shared/data}"
frame="$data/pcl-kinect-sequences/pairwise_tutorial/capture0001.pcd"
if [ ! -f "$frame" ]; then
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  "$build/src/fvx_make_box_room" "$tmp" 640 480 >/dev/null
  frame="$tmp/view0.pcd"
fi
"$build/tests/bench/bench_integrate" "$frame" "$@"
