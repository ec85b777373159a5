#!/usr/bin/env bash
# One command on a fresh machine: installs what is missing, builds fvx, and runs the main job
# on the bundled sample: a virtual Kinect scans a replica of the paper's second setting
# (data/scenes/paper-setting-2.ply) from four views, fvx integrates the scans into an
# OctoMap, the map is compared with the scene's voxel ground truth, and fvx nbv ranks the next
# best views for the project's arm (data/arms/fvx-arm.urdf, its committed capability map).
# Then fvx explore runs the whole loop of the paper on the same replica: the arm moves the
# virtual Kinect view by view until no reachable view sees a void, and prints the per-view
# table (the paper's columns plus ground truth).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh >/dev/null
fvx="${FVX_BUILD_DIR:-build}/src/fvx"
out="${FVX_DEMO_OUT:-demo-out}"
scene=data/scenes/paper-setting-2.ply
mkdir -p "$out"

# Four views from where the paper's arm could hold the sensor: eye point, then the point looked at.
views=("0.05,0.0,0.95,0.85,0.0,0.15" "0.3,0.75,0.85,0.9,0.1,0.1" "0.3,-0.75,0.85,0.9,-0.2,0.1" "0.45,0.0,1.2,0.8,0.1,0.0")
echo "== fvx simulate: ${#views[@]} Kinect views of $scene (noise sigma = 1.4 mm z^2)" >&2
mkdir -p "$out/scans"
for i in "${!views[@]}"; do
  "$fvx" simulate "$scene" --look-at "${views[$i]}" --noise kinect --seed "$i" -o "$out/scans/view$i.pcd" \
    | jq -r '.results.frames[0] | "  \(.file): \(.pixels.valid) pixels with depth"'
done
echo "== fvx integrate: the scans into $out/map.ot (poses are exact in simulation: --no-register)" >&2
"$fvx" integrate -o "$out/map.ot" --resolution 0.025 --no-register --progress "$out"/scans/*.pcd > "$out/integrate.json"
echo "== fvx simulate --ground-truth: the scene's cells at 2.5 cm" >&2
"$fvx" simulate "$scene" --ground-truth "$out/ground-truth.bt" -r 0.025 > "$out/ground-truth.json"

jq -r '.results.map | "map: \(.occupied_leaves) occupied and \(.free_leaves) free leaves, \(.free_volume_m3 * 1000 | floor) dm3 known free"' "$out/integrate.json"
jq -r '.results.ground_truth | "ground truth: \(.free_volume_m3 * 1000 | floor) dm3 free in the search space; hidden inside boxes: " + ([.containers[] | "\(.name) \(.free_volume_dm3 | floor) dm3"] | join(", "))' "$out/ground-truth.json"
echo "open the map with: octovis $out/map.ot   (ground truth: $out/ground-truth.bt)" >&2
echo "== fvx nbv: the next best view for the fvx arm standing at (0.2, 0, 0) (data/arms/fvx-arm.fcm)" >&2
"$fvx" nbv "$out/map.ot" --capmap data/arms/fvx-arm.fcm --base 0.2,0,0,0,0,0 --arm data/arms/fvx-arm.urdf \
  --bounds 0.35,-0.75,0.0,1.3,0.9,0.55 --top 3 --utility-cloud "$out/utility.ply" --picture "$out/utility.png" \
  -o "$out/views.json"
jq -r '.results | "\(.void_cells) void cells in \(.void_clusters) clusters, \(.frontier_voids_open) with a frontier; \(.utility_vectors) utility vectors; \(.poses_scored) poses scored"' "$out/views.json"
jq -r '.results.views[] | "view \(.rank): sensor at \(.position_m | map(. * 1000 | round / 1000)) looking \(.viewing_direction | map(. * 100 | round / 100)), sees \(.void_cells_seen) void cells (\(.utility_dm3) dm3)"' "$out/views.json"
jq -r 'if .results.views == [] then "no view: \(.results.reason)" else empty end' "$out/views.json"
echo "the utility field: $out/utility.ply (pcl_viewer, CloudCompare), $out/utility.png" >&2
echo "== fvx explore: the closed loop on $scene with the fvx arm at the origin, searching for a 6 cm victim, at most 15 views" >&2
rm -rf "$out/session"
"$fvx" explore "$scene" --capmap data/arms/fvx-arm.fcm --base 0,0,0,0,0,0 --arm data/arms/fvx-arm.urdf \
  --target-size 0.06 --max-views 15 --progress -o "$out/session"
echo "the session: $out/session (manifest.json, scans/*.pcd, maps/*.ot for octovis, reports/*.json, views.png: a picture per view)" >&2
