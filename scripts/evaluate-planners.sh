#!/usr/bin/env bash
# Planners measured over many scenes: `fvx explore` for every scene x planner x seed, with the
# fvx arm at each scene's base, then per run the coverage after each view and a summary.
#
#   scripts/evaluate-planners.sh [-o DIR] [--scenes LIST] [--planners LIST] [--seeds LIST]
#                                [--max-views N] [--jobs N]
#
#   --scenes    numbers and ranges of the scene family builtin:suite/N ("1-24", the default
#               suite), or any scene fvx explore takes (builtin:NAME, a mesh); comma or space
#               separated
#   --planners  default "frontier-void frontier random exhaustive"; an item LABEL=STRATEGY,FLAG...
#               runs a variant under its own label, e.g. "fv-far=frontier-void,--far-voids-only"
#               (labels without "_"): before and after a change, in the same run
#   --seeds     default "1"; ranges allowed ("1-3")
#   --max-views default 15
#   --jobs      runs at the same time (default: the number of cores); each search gets
#               cores/jobs threads
#   -o DIR      default evaluation/; runs already there are kept (a killed evaluation resumes
#               when called again with the same options)
#
# The evaluation is a batch plan (`fvx batch sweep`, man fvx-batch): DIR/tasks.txt holds one
# fvx explore per run, run here --jobs at a time, and `fvx batch merge DIR` (DIR/merge.sh)
# writes the tables. The same plan runs on GNU parallel or Slurm and merges into the same
# bytes. Writes DIR/parts/*.json (each run's fvx explore --format json, written atomically;
# its log beside it), DIR/runs.csv (one line per run), DIR/coverage.csv (void_known_fraction
# per run and view), DIR/summary.md and DIR/summary.csv (per planner), DIR/coverage.png (per
# planner the median share of the observable void volume known after each view, the band from
# the first to the third quartile across runs), DIR/timing.csv (each run's search seconds).
# The headline is void_known_fraction (man fvx-explore). A run that ended before max-views
# keeps its last coverage for the views after it.
# Needs gnuplot (installed when missing, as scripts/install-deps.sh does).
set -euo pipefail
cd "$(dirname "$0")/.."
fvx="${FVX_BUILD_DIR:-build}/src/fvx"
out=evaluation
scenes="1-24"
planners="frontier-void frontier random exhaustive"
seeds="1"
max_views=15
jobs="$(nproc)"
while [ $# -gt 0 ]; do
  case "$1" in
    -o) out="$2"; shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    --planners) planners="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --max-views) max_views="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "evaluate-planners: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$max_views" =~ ^[1-9][0-9]*$ ]] || { echo "evaluate-planners: --max-views must be a positive integer" >&2; exit 2; }
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "evaluate-planners: --jobs must be a positive integer" >&2; exit 2; }
command -v gnuplot >/dev/null || scripts/install-deps.sh
[ -x "$fvx" ] || { scripts/install-deps.sh && scripts/build.sh >/dev/null; }

threads=$(( $(nproc) / jobs )); [ "$threads" -ge 1 ] || threads=1
"$fvx" batch sweep --scenes "$scenes" --planners "$planners" --seeds "$seeds" --max-views "$max_views" -o "$out" \
  -- --capmap data/arms/fvx-arm.fcm --arm data/arms/fvx-arm.urdf --threads "$threads" > /dev/null
remaining="$("$fvx" batch status "$out" 2> /dev/null | sed -n 's/.*"remaining": *\([0-9]*\).*/\1/p' | head -1)"
echo "evaluate-planners: ${remaining:-?} runs to do of $(wc -l < "$out/tasks.txt"), $jobs at a time, in $out/" >&2
failed=0
tr '\n' '\0' < "$out/tasks.txt" | xargs -0 -P "$jobs" -n 1 sh -c || failed=1
"$fvx" batch merge "$out" > /dev/null
cat "$out/summary.md"
for p in $(tail -n +2 "$out/timing.csv" | cut -d, -f2 | awk '!seen[$0]++'); do
  m="$(awk -F, -v p="$p" '$2 == p && $4 != "" { print $4 }' "$out/timing.csv" | sort -g | awk '{ a[NR] = $1 } END { if (NR) print a[int((NR + 1) / 2)] }')"
  echo "evaluate-planners: $p: search ${m:-?} s per view (median of the runs)" >&2
done
echo "evaluate-planners: $(($(wc -l < "$out/runs.csv") - 1)) runs; $out/summary.md, summary.csv, runs.csv, coverage.png, timing.csv" >&2
exit "$failed"
