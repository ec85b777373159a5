#!/usr/bin/env bash
# Maps larger than the machine: the whole `fvx nbv` (free-flying, defaults) on halls as large
# as a building's (tests/bench/make_large_map: one scan to two walls 2 m high, 5 cm cells),
# searched whole and in a 4 m corner given as --bounds. Prints wall time, peak memory (RSS),
# the exit status (1: refused, with its message) and the report's void cells and best view.
# FVX_BASELINE=/path/to/fvx runs another binary on the same maps in the same run.
#   scripts/bench-large-map.sh [HALVES]      HALVES default "15 30 100" (half the hall's side, m)
# The 100 m hall is searched only in its corner: whole, it holds 656 M cells (about 30 GiB).
set -euo pipefail
cd "$(dirname "$0")/.."
build="${FVX_BUILD_DIR:-build}"
halves="${1:-15 30 100}"
for half in $halves; do
  [[ "$half" =~ ^[1-9][0-9]*$ ]] || { echo "bench-large-map: HALVES are whole metres, e.g. \"15 30 100\"; got '$half'" >&2; exit 2; }
done
if [ ! -x "$build/src/fvx" ] || [ ! -x "$build/tests/bench/make_large_map" ]; then
  scripts/install-deps.sh && scripts/build.sh >/dev/null
fi
command -v /usr/bin/time >/dev/null || { echo "bench-large-map: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
binaries=("$build/src/fvx")
[ -n "${FVX_BASELINE:-}" ] && binaries=("$FVX_BASELINE" "${binaries[@]}")
printf '| hall | search space | binary | exit | wall s | peak MiB | void cells | best U |\n'
printf '|---|---|---|---|---|---|---|---|\n'
for half in $halves; do
  "$build/tests/bench/make_large_map" 0.05 "$half" "$tmp/hall.bt" 2>/dev/null
  corner="$((half - 4)),$((half - 4)),0,$half,$half,2"
  for space in whole corner; do
    [ "$space" = whole ] && [ "$half" -gt 60 ] && continue
    bounds=()
    [ "$space" = corner ] && bounds=(--bounds "$corner")
    for fvx in "${binaries[@]}"; do
      status=0
      /usr/bin/time -f '%e %M' -o "$tmp/time" "$fvx" nbv "$tmp/hall.bt" --no-capmap "${bounds[@]}" \
        -o "$tmp/run.json" 2> "$tmp/err" || status=$?
      read -r wall kb < <(tail -1 "$tmp/time")
      voids=-; best=-
      if [ "$status" = 0 ]; then
        voids="$(jq '.results.void_cells' "$tmp/run.json")"
        best="$(jq '.results.best_void_cells_seen' "$tmp/run.json")"
      fi
      printf '| %s m | %s | %s | %s | %s | %d | %s | %s |\n' "$((2 * half))" "${bounds[1]:-whole}" "$fvx" "$status" \
        "$wall" "$((kb / 1024))" "$voids" "$best"
      [ "$status" = 0 ] || echo "  ($(head -c 300 "$tmp/err"))"
      rm -f "$tmp/run.json"
    done
  done
done
