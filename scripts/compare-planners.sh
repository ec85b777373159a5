#!/usr/bin/env bash
# The four planners of fvx explore in the same loop and seed on both paper replicas (the fvx
# arm's capability map at the origin, as the issue's command line has it, 2.5 cm, at most 15
# views; --target-size is each replica's victim's smallest extent, 8 and 6 cm): views until
# the target was seen, views until 95 % of the observable volume was known, the final share,
# the last view's utility, how it ended.
# Usage: scripts/compare-planners.sh [MAX_VIEWS] [SEED]
set -euo pipefail
cd "$(dirname "$0")/.."
fvx="${FVX_BUILD_DIR:-build}/src/fvx"
max_views="${1:-15}"
seed="${2:-1}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
echo "| scene | planner | views | target seen at view | 95 % known at view | known at the end | last utility (void cells) | search s (median) | end |"
echo "|---|---|---|---|---|---|---|---|---|"
for scene in paper-setting-1 paper-setting-2; do
  target_size=$([ "$scene" = paper-setting-1 ] && echo 0.08 || echo 0.06)
  for planner in frontier-void frontier random exhaustive; do
    "$fvx" explore "data/scenes/$scene.ply" --capmap data/arms/fvx-arm.fcm --base 0,0,0,0,0,0 \
      --arm data/arms/fvx-arm.urdf --target-size "$target_size" --strategy "$planner" --max-views "$max_views" --seed "$seed" --timing \
      --format json -o "$out/$scene-$planner" 2>/dev/null |
      jq -r --arg scene "$scene" --arg planner "$planner" '
        def med: sort | .[(length / 2 | floor)];
        .results as $r
        | ([$r.rows[] | select(.target_seen) | .view] | first // "no") as $target
        | ([$r.rows[] | select(.known_fraction >= 0.95) | .view] | first // "no") as $known
        | "| \($scene) | \($planner) | \($r.views) | \($target) | \($known) | \($r.rows[-1].known_fraction * 1000 | round / 10) % | \($r.rows[-1].void_cells) | \([$r.rows[].timing_s.search] | med * 1000 | round / 1000) | \($r.end) |"'
  done
done
