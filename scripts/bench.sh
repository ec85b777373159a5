#!/usr/bin/env bash
# Benchmarks, each with its baselines measured in the same run:
#  - integration: one 640x480 Kinect frame at 2.5 cm and 4 m through fvx and through
#    OctoMap's insertPointCloud (exact and discretised); the frame is a real Kinect capture
#    from FVX_REAL_DATA when available, else a synthetic one;
#  - rendering: a 640x480 frame of a 100k-triangle scene (Embree, CGAL), and the trees
#    against brute force on a small scene;
#  - frontiers and voids: incremental updates against recomputing from scratch after each
#    of 15 Kinect frames (Redwood living room, from FVX_REAL_DATA; skipped without it);
#  - next best view: the search on four synthetic scenes (two scans each, 2.5 cm) against the
#    exhaustive strategy on the same capability map (data/arms/fvx-arm.fcm), with the time
#    split, and field-of-view ray casting in cells/s against a plain dense 3-D DDA and
#    octree look-ups;
#  - one explore view on each paper replica at 2.5 cm (the fvx arm): median and max time per
#    stage (render, registration, integration, frontiers/voids, search) over the views of a
#    run, with and without pose noise (registration on);
#  - replay: the noise-free explore sessions of both replicas replayed from their files,
#    integration (octree, frontiers and voids) and search per view, median and max, beside
#    the paper's; the 211 Redwood frames at 2.5 cm (FVX_REAL_DATA): frames per second of the
#    replay step without the search against OctoMap's insertPointCloud in the same run, and
#    of the whole fvx replay command (files read, --search-every 0);
#  - next best view at scale: the whole fvx nbv on the real slambook and geb079 maps, sampled
#    against exact accumulation, seeds 1-4 (scripts/bench-nbv-scale.sh; FVX_REAL_DATA);
#  - maps larger than the machine: the whole fvx nbv on synthetic halls of 30, 60 and 200 m at
#    5 cm, searched whole and in a 4 m corner given as --bounds (scripts/bench-large-map.sh;
#    FVX_BASELINE=/path/to/fvx adds another binary in the same run);
#  - replay with a search after every view: the whole fvx replay on the 211 Redwood frames and
#    the five slambook frames at 2.5 cm (to 7 m and to the default 4 m), frames/s and peak
#    memory, and the same without any search (scripts/bench-replay.sh; FVX_BASELINE=/path/to/fvx
#    adds another binary in the same run; FVX_REAL_DATA);
#  - capability maps: the youBot map at 5 cm, the FK-seeded build against the exhaustive
#    IK loop on the same z-slab, lookups, file size (from FVX_REAL_DATA);
#  - batch: the youBot map at 2.5 cm as 2, 8 and 64 shards (slabs and samples) through GNU
#    parallel on this machine's cores against one process, and the projected time on 64
#    slots (scripts/bench-batch.sh; FVX_REAL_DATA);
#  - the suite's clairvoyant bound: per scene of builtin:suite/1-24, the views a greedy
#    planner that knows the ground truth needs to 95 % of the observable void volume
#    (bench_clairvoyant, fvx explore's defaults; about 5 min);
#  - the loop's regret: at each of the first 6 views of the frontier-void loop on every suite
#    scene, the true gain of the view it takes, of its best ranked view and of other rules'
#    first views, against the ground truth's best (bench_regret; about 18 min).
#  - ranking the candidates: at each of the first 4 views of the same loop, whether a feature
#    of a candidate's view on the map, or a ridge regression on all of them trained leave-one-
#    scene-out, picks candidates that reveal more than U's pick (bench_rank_features; about 6 min).
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
echo "== integration" && "$build/tests/bench/bench_integrate" "$frame"
echo "== rendering" && "$build/tests/bench/bench_render"
redwood="$data/redwood-livingroom1-micro"
if [ -d "$redwood" ]; then
  echo "== frontiers and voids" && "$build/tests/bench/bench_frontiers_voids" "$redwood/depth" \
    "$redwood/trajectory_open3d_estimated.log" 15
else
  echo "== frontiers and voids: skipped ($redwood not found; set FVX_REAL_DATA)"
fi
echo "== next best view" && "$build/tests/bench/bench_nbv" data/arms/fvx-arm.fcm 5
echo "== next best view at scale" && FVX_REAL_DATA="$data" scripts/bench-nbv-scale.sh
echo "== maps larger than the machine (whole and a corner as --bounds)" && scripts/bench-large-map.sh
echo "== replay with a search after every view" && FVX_REAL_DATA="$data" scripts/bench-replay.sh
echo "== explore: time per stage and view (paper replicas, 2.5 cm, fvx arm at (0.2, 0, 0))"
bench_out="$(mktemp -d)"
for scene in paper-setting-1 paper-setting-2; do
  for noise in "" "--pose-noise 0.02,2"; do
    "$build/src/fvx" explore "data/scenes/$scene.ply" --capmap data/arms/fvx-arm.fcm --base 0.2,0,0,0,0,0 \
      --arm data/arms/fvx-arm.urdf $noise --timing --format json -o "$bench_out/$scene${noise:+-noisy}" 2>/dev/null |
      jq -r --arg name "$scene${noise:+ (pose noise 0.02,2)}" '
        def med: sort | .[(length / 2 | floor)];
        [.results.rows[].timing_s] as $t
        | "\($name): \($t | length) views; median / max s: " +
          ([("render", "registration", "integration", "frontiers_voids", "search") as $k
            | "\($k) \([$t[][$k]] | med * 1000 | round / 1000) / \([$t[][$k]] | max * 1000 | round / 1000)"]
           | join(", "))'
  done
done
echo "== replay: the explore sessions above, from their files (the paper: integration 2.79-4.46 s, search 0.01-99.22 s per view)"
for scene in paper-setting-1 paper-setting-2; do
  "$build/src/fvx" replay "$bench_out/$scene" -o "$bench_out/$scene-replay" --timing --format json 2>/dev/null |
    jq -r --arg name "$scene" '
      def med: sort | .[(length / 2 | floor)];
      def r3: . * 1000 | round / 1000;
      [.results.rows[].timing_s] as $t
      | [$t[] | .integration + .frontiers_voids] as $i | [$t[].search] as $s
      | "\($name): \($t | length) views; integration median \($i | med | r3) s, max \($i | max | r3) s; search median \($s | med | r3) s, max \($s | max | r3) s"'
done
rm -rf "$bench_out"
if [ -d "$redwood" ]; then
  echo "== replay: 211 Redwood frames at 2.5 cm, 4 m"
  "$build/tests/bench/bench_replay" "$redwood/trajectory_open3d_estimated.log" "$redwood"/depth/*.png
  replay_out="$(mktemp -d)"
  start=$(date +%s.%N)
  "$build/src/fvx" replay --scans "$redwood/depth/*.png" --trajectory "$redwood/trajectory_open3d_estimated.log" \
    --no-capmap --no-register --search-every 0 -o "$replay_out/out" --format csv > "$replay_out/table.csv" 2>/dev/null
  end=$(date +%s.%N)
  frames=$(($(wc -l < "$replay_out/table.csv") - 1))
  awk -v n="$frames" -v a="$start" -v b="$end" 'BEGIN { printf "fvx replay command (files read, maps and reports written, no search): %d frames in %.1f s, %.2f frames/s\n", n, b - a, n / (b - a) }'
  rm -rf "$replay_out"
else
  echo "== replay of Redwood: skipped ($redwood not found; set FVX_REAL_DATA)"
fi
youbot="$data/arms/youbot_arm.urdf"
if [ -f "$youbot" ]; then
  echo "== capability maps" && "$build/tests/bench/bench_capmap" "$youbot"
  echo "== batch: capability-map shards through GNU parallel against one process" &&
    FVX_REAL_DATA="$data" scripts/bench-batch.sh "$youbot" base_link arm_link_5
else
  echo "== capability maps: skipped ($youbot not found; set FVX_REAL_DATA)"
fi
echo "== the suite's clairvoyant bound (views to 95 % of the observable void volume, ground truth known)"
"$build/tests/bench/bench_clairvoyant" data/arms/fvx-arm.fcm data/arms/fvx-arm.urdf 1 24
echo "== the loop's regret (true gain of the chosen view against the ground truth's best)"
"$build/tests/bench/bench_regret" data/arms/fvx-arm.fcm data/arms/fvx-arm.urdf 1 24 6
echo "== ranking the candidates (features of a view on the map against its true gain)"
"$build/tests/bench/bench_rank_features" data/arms/fvx-arm.fcm data/arms/fvx-arm.urdf 1 24 4
