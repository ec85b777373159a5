#!/usr/bin/env bash
# Next best view at the scale of real maps: the whole `fvx nbv` command (read the map, find
# frontiers and voids, search) on the fast path (the defaults: sampled accumulation, poses
# screened by a coarse ray fan) and the exact path (the paper's Algorithm 1, every pose
# scored with the full fan: --accumulation exact --coarse-rays off), in the same run, on each
# map, free-flying (--no-capmap), for each seed. Prints wall time, peak memory (RSS), utility
# vectors and the best view's void cells, and the ratio of the fast best view's void cells to
# the exact one's with the same seed (both scored by the same full field-of-view ray cast).
#   scripts/bench-nbv-scale.sh [SEEDS]     SEEDS default "1 2 3 4"
# FVX_NBV_VARIANTS="FLAGS|FLAGS|..." runs the fast path once per flag set (e.g.
# "--utility-vectors 262144 --coarse-rays 20x15|--coarse-rays off") against the same exact
# run; "" is the defaults. FVX_NBV_BUDGETS="262144 524288 ..." adds one variant per budget.
# Maps: octomap-maps/slambook_ch13/octomap.bt and octomap-share-data/geb079.bt from
# FVX_REAL_DATA (default ../shared/data), and any in FVX_NBV_MAPS (space-separated paths).
# The exact path takes 15-45 s per real map and seed. Then the two paper replicas (two
# simulated scans each, 2.5 cm) on the fvx arm at (0.2, 0, 0): each variant, the exact path
# and the exhaustive strategy, the median wall time of each variant's run over three.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${FVX_BUILD_DIR:-build}"
data="${FVX_REAL_DATA:-../shared/data}"
seeds="${1:-1 2 3 4}"
variants=()
IFS='|' read -r -a variants <<< "${FVX_NBV_VARIANTS:-}"
for b in ${FVX_NBV_BUDGETS:-}; do variants+=("--utility-vectors $b"); done
[ "${#variants[@]}" -gt 0 ] || variants=("")  # "": the defaults
exact_flags=(--accumulation exact --coarse-rays off)
fvx="$build/src/fvx"
[ -x "$fvx" ] || { scripts/install-deps.sh && scripts/build.sh >/dev/null; }
command -v /usr/bin/time >/dev/null || { echo "bench-nbv-scale: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
maps=("$data/octomap-maps/slambook_ch13/octomap.bt" "$data/octomap-maps/octomap-share-data/geb079.bt")
# shellcheck disable=SC2206
[ -n "${FVX_NBV_MAPS:-}" ] && maps+=(${FVX_NBV_MAPS})
printf '| map | seed | mode | wall s | search s | accumulation s | peak MiB | vectors | best U | fast/exact U |\n'
printf '|---|---|---|---|---|---|---|---|---|---|\n'
for map in "${maps[@]}"; do
  [ -f "$map" ] || { echo "bench-nbv-scale: $map not found; set FVX_REAL_DATA" >&2; continue; }
  for seed in $seeds; do
    exact=""
    for mode in exact "${variants[@]}"; do
      flags=("${exact_flags[@]}")
      # shellcheck disable=SC2206  # a variant is a list of flags
      [ "$mode" = exact ] || flags=($mode)
      /usr/bin/time -f '%e %M' -o "$tmp/time" "$fvx" nbv "$map" --no-capmap --timing --seed "$seed" \
        "${flags[@]}" -o "$tmp/run.json"
      read -r wall kb < "$tmp/time"
      best="$(jq '.results.best_void_cells_seen' "$tmp/run.json")"
      [ "$mode" = exact ] && exact="$best"
      printf '| %s | %s | %s | %s | %.3f | %.3f | %d | %s | %s | %s |\n' "$(basename "$(dirname "$map")")/$(basename "$map")" \
        "$seed" "${mode:-defaults}" "$wall" "$(jq '.results.timing_s.total' "$tmp/run.json")" \
        "$(jq '.results.timing_s.accumulation' "$tmp/run.json")" "$((kb / 1024))" \
        "$(jq '.results.utility_vectors' "$tmp/run.json")" "$best" \
        "$(awk -v s="$best" -v e="$exact" 'BEGIN{printf "%.3f", e ? s/e : 0}')"
    done
  done
done

# The paper replicas: two first views (from above the base, from one side), 2.5 cm.
arm=(--capmap data/arms/fvx-arm.fcm --base 0.2,0,0,0,0,0)
printf '\n| replica | seed | variant | fast wall s (median of 3) | fast U | exact U | exhaustive U | exhaustive wall s | fast/exact | fast/exhaustive |\n'
printf '|---|---|---|---|---|---|---|---|---|---|\n'
for scene in paper-setting-1 paper-setting-2; do
  for view in "0.05,0,0.95" "0.3,0.75,0.85"; do
    "$fvx" simulate "data/scenes/$scene.ply" --look-at "$view,0.6,0,0.3" -o "$tmp/$scene-$view.pcd" >/dev/null 2>&1
  done
  "$fvx" integrate "$tmp/$scene-"*.pcd -r 0.025 --no-register -o "$tmp/$scene.ot" >/dev/null
  for seed in $seeds; do
    "$fvx" nbv "$tmp/$scene.ot" "${arm[@]}" --seed "$seed" "${exact_flags[@]}" -o "$tmp/e.json"
    /usr/bin/time -f '%e' -o "$tmp/xtime" "$fvx" nbv "$tmp/$scene.ot" "${arm[@]}" --seed "$seed" \
      --strategy exhaustive -o "$tmp/x.json"
    e="$(jq '.results.best_void_cells_seen' "$tmp/e.json")" x="$(jq '.results.best_void_cells_seen' "$tmp/x.json")"
    for variant in "${variants[@]}"; do
      walls=()
      for _ in 1 2 3; do
        # shellcheck disable=SC2086  # a variant is a list of flags
        /usr/bin/time -f '%e' -o "$tmp/time" "$fvx" nbv "$tmp/$scene.ot" "${arm[@]}" --seed "$seed" \
          $variant -o "$tmp/s.json"
        walls+=("$(cat "$tmp/time")")
      done
      median="$(printf '%s\n' "${walls[@]}" | sort -n | sed -n 2p)"
      s="$(jq '.results.best_void_cells_seen' "$tmp/s.json")"
      printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$scene" "$seed" "${variant:-defaults}" "$median" \
        "$s" "$e" "$x" "$(cat "$tmp/xtime")" "$(awk -v a="$s" -v b="$e" 'BEGIN{printf "%.3f", b ? a/b : 0}')" \
        "$(awk -v a="$s" -v b="$x" 'BEGIN{printf "%.3f", b ? a/b : 0}')"
    done
  done
done
