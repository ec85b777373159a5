#!/usr/bin/env bash
# The whole `fvx replay` command with a search after every view (the default --search-every 1),
# as a user runs it on recorded Kinect data, free-flying (--no-capmap), registration on (the
# default for --scans): wall time, frames per second, seconds per view and peak memory (RSS).
#   - the 211 Redwood living-room frames at 2.5 cm (redwood-livingroom1-micro);
#   - the five slambook frames at 2.5 cm, depth < 7 m (slambook-joinmap-5kf; slambook's own
#     joinMap cut-off);
#   - the same frames at the sensor's default range, depth < 4 m (Kinect v1, what a user who
#     gives only the intrinsics gets).
# A last row per sequence replays it without any search (--search-every 0): the floor that the
# steps before the search (registration, integration, frontiers and voids, writing) set.
# Data from FVX_REAL_DATA (default ../shared/data). FVX_BASELINE=/path/to/another/fvx runs that
# binary on the same inputs first, in the same run (ratios need both from one run: the machines
# are noisy), and checks that both wrote the same per-view maps.
#   scripts/bench-replay.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build="${FVX_BUILD_DIR:-build}"
data="${FVX_REAL_DATA:-../shared/data}"
fvx="$build/src/fvx"
[ -x "$fvx" ] || { scripts/install-deps.sh && scripts/build.sh >/dev/null; }
command -v /usr/bin/time >/dev/null || { echo "bench-replay: needs /usr/bin/time (Debian package time)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

redwood="$data/redwood-livingroom1-micro"
slambook="$data/slambook-joinmap-5kf"
declare -A args
args[redwood]="--scans $redwood/depth/*.png --trajectory $redwood/trajectory_open3d_estimated.log --fx 525 --fy 525 --cx 319.5 --cy 239.5"
slambook_args="--scans $slambook/depth/*.pgm --trajectory $slambook/pose.txt --fx 518 --fy 519 --cx 325.5 --cy 253.5 --depth-scale 1000"
args[slambook]="$slambook_args --depth-max 7"
args[slambook-4m]="$slambook_args"
binaries=("$fvx")
[ -n "${FVX_BASELINE:-}" ] && binaries=("$FVX_BASELINE" "$fvx")

printf '| sequence | binary | search | frames | wall s | frames/s | s per view | peak MiB | same maps as the first |\n'
printf '|---|---|---|---|---|---|---|---|---|\n'
for name in redwood slambook slambook-4m; do
  dir="$redwood"
  [ "$name" != redwood ] && dir="$slambook"
  [ -d "$dir" ] || { echo "bench-replay: $dir not found; set FVX_REAL_DATA" >&2; continue; }
  n=0
  for run in "${binaries[@]}" "$fvx none"; do
    n=$((n + 1))
    bin="${run% none}" search="every view" every=1
    [ "$bin" != "$run" ] && search="none" every=0
    out="$tmp/$name-$n"
    set -f  # the globs in args go to fvx as they are
    # shellcheck disable=SC2086
    /usr/bin/time -f '%e %M' -o "$tmp/time" "$bin" replay ${args[$name]} -r 0.025 --no-capmap -o "$out" \
      --search-every "$every" --format csv > "$tmp/table.csv" 2> "$tmp/err" ||
      { echo "bench-replay: $bin failed: $(tail -1 "$tmp/err")" >&2; exit 1; }
    set +f
    read -r wall kb < "$tmp/time"
    frames=$(($(wc -l < "$tmp/table.csv") - 1))
    same="-"
    [ "$n" -gt 1 ] && same="$(cd "$out/maps" && sha256sum ./* | (cd "$tmp/$name-1/maps" && sha256sum --quiet -c - >/dev/null 2>&1) && echo yes || echo NO)"
    awk -v s="$name" -v b="$bin" -v x="$search" -v f="$frames" -v w="$wall" -v m="$((kb / 1024))" -v same="$same" \
      'BEGIN { printf "| %s | %s | %s | %d | %.1f | %.2f | %.3f | %d | %s |\n", s, b, x, f, w, f / w, w / f, m, same }'
  done
done
