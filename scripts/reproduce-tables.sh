#!/usr/bin/env bash
# The paper's Tables I and II beside fvx's: fvx explore runs the closed loop on each paper
# replica (the fvx arm's capability map at the origin, 2.5 cm, seed 1, at most 15 views,
# --target-size the replica's victim's smallest extent) and
# records a session; fvx replay runs the recorded session again from its files. Each table
# shows, per view, the paper's integration time, search time, void cells and utility beside
# the replay's. The paper ran a real Kinect on a real arm (2.8–4.5 s integration per view);
# here the scenes are replicas and the sensor is simulated, so the void counts are not the
# paper's: what carries over is the shape (utility falling view by view to 0) and the times.
# Usage: scripts/reproduce-tables.sh [OUT_DIR]   (default: a temporary folder, removed)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
fvx="${FVX_BUILD_DIR:-build}/src/fvx"
if [ $# -ge 1 ]; then
  out="$1"
  mkdir -p "$out"
else
  out="$(mktemp -d)"
  trap 'rm -rf "$out"' EXIT
fi

# The paper's tables (Dornhege & Kleiner, SSRR 2011, §V-B): view, integration s, search s,
# void cells, utility dm³.
paper_1='[[1,3.07,22.91,1245,19.45],[2,3.21,30.27,988,15.44],[3,3.12,99.22,739,11.55],[4,3.51,66.85,306,4.78],[5,4.20,0.01,0,0.0]]'
paper_2='[[1,3.83,43.58,2292,35.81],[2,3.25,53.32,392,6.13],[3,2.99,53.28,167,2.61],[4,2.79,67.90,120,1.88],[5,3.87,68.53,1615,25.23],[6,4.46,14.49,103,1.61],[7,4.11,3.35,0,0.0]]'

for n in 1 2; do
  scene="paper-setting-$n"
  paper="paper_$n"
  echo "== Table $( [ $n = 1 ] && echo I || echo II ): $scene (paper | fvx replay of the fvx explore session)"
  target_size=$([ $n = 1 ] && echo 0.08 || echo 0.06)  # the replica's victim's smallest extent
  # --far-voids-only: void cells nearer than the Kinect's minimum depth never become known, so
  # with them U would not fall to 0 as the paper's tables do (README, "One U for every command").
  # --near-unknown ignore: the paper's U, which no near unknown cell cuts (the default, hidden,
  # learns from blank views, which the paper's loop did not; README, "Exploration over a scene suite").
  # --exterior unknown: the paper's viewpoints, each in a known free cell (the default, view, may
  # also stand in the unknown air outside the voids' hull; README, "--exterior").
  "$fvx" explore "data/scenes/$scene.ply" --capmap data/arms/fvx-arm.fcm --base 0,0,0,0,0,0 \
    --arm data/arms/fvx-arm.urdf --target-size "$target_size" --seed 1 --max-views 15 --far-voids-only \
    --near-unknown ignore --exterior unknown --format json -o "$out/$scene-session" \
    > "$out/$scene-explore.json" 2>/dev/null
  "$fvx" replay "$out/$scene-session" -o "$out/$scene-replay" --timing --format json > "$out/$scene-replay.json" 2>/dev/null
  jq -r --argjson paper "${!paper}" --slurpfile explore "$out/$scene-explore.json" '
    def f(d): if . == null then "" else (. * pow(10; d) | round / pow(10; d) | tostring) end;
    .results.rows as $r
    | "| view | integration s (paper / fvx) | search s (paper / fvx) | void cells (paper / fvx) | utility dm³ (paper / fvx) |",
      "|---|---|---|---|---|",
      (range(0; ([($paper | length), ($r | length)] | max)) as $i
       | ($paper[$i] // [null, null, null, null, null]) as $p
       | ($r[$i] // null) as $x
       | "| \($i + 1) | \($p[1] | f(2)) / \($x.timing_s.integration + $x.timing_s.frontiers_voids | f(3)) | \($p[2] | f(2)) / \($x.timing_s.search | f(3)) | \($p[3] | f(0)) / \($x.void_cells | f(0)) | \($p[4] | f(2)) / \($x.utility_dm3 | f(2)) |"),
      "",
      "fvx explore: \($explore[0].results.end) after \($explore[0].results.views) views; the replay reproduces its void cells: \(if ([$explore[0].results.rows[].void_cells] == [$r[].void_cells]) then "yes" else "NO" end)."' \
    "$out/$scene-replay.json"
  echo
done
