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
#   -o DIR      default evaluation/; runs already there are kept (a killed evaluation resumes)
#
# Writes DIR/runs/*.json (each run's fvx explore --format json, written atomically),
# DIR/runs.csv (one line per run), DIR/coverage.csv (void_known_fraction per run and view),
# DIR/summary.md and DIR/summary.csv (per planner), DIR/coverage.png (per planner the median
# share of the observable void volume known after each view, the band from the first to the
# third quartile across runs). The headline is void_known_fraction (man fvx-explore). A run
# that ended before max-views keeps its last coverage for the views after it.
# Needs jq and gnuplot (installed when missing, as scripts/install-deps.sh does).
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
    -h|--help) sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "evaluate-planners: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$max_views" =~ ^[1-9][0-9]*$ ]] || { echo "evaluate-planners: --max-views must be a positive integer" >&2; exit 2; }
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "evaluate-planners: --jobs must be a positive integer" >&2; exit 2; }
command -v gnuplot >/dev/null && command -v jq >/dev/null || scripts/install-deps.sh
[ -x "$fvx" ] || { scripts/install-deps.sh && scripts/build.sh >/dev/null; }

# "1-3,paper-setting-1 7" -> one item per line; numbers become builtin:suite/N.
expand() {
  local item
  for item in ${1//,/ }; do
    if [[ "$item" =~ ^([0-9]+)-([0-9]+)$ ]]; then seq "${BASH_REMATCH[1]}" "${BASH_REMATCH[2]}"
    else echo "$item"; fi
  done
}
scene_arg() { [[ "$1" =~ ^[0-9]+$ ]] && echo "builtin:suite/$1" || echo "$1"; }
slug() { echo "$1" | sed 's|^builtin:||; s|[/ _]|-|g; s|.*/||'; }

mkdir -p "$out/runs"
threads=$(( $(nproc) / jobs )); [ "$threads" -ge 1 ] || threads=1
tasks="$out/tasks.txt"
: > "$tasks"
for s in $(expand "$scenes"); do
  scene="$(scene_arg "$s")"
  for item in $planners; do
    planner="${item%%=*}"
    spec="${item#*=}"              # STRATEGY[,FLAG...]; the label itself when there is no "="
    strategy="${spec%%,*}"
    flags=""
    [ "$spec" != "$strategy" ] && flags="${spec#*,}" && flags="${flags//,/ }"
    [[ "$planner" =~ ^[A-Za-z0-9.+-]+$ ]] || { echo "evaluate-planners: planner label '$planner': letters, digits, . + - only" >&2; exit 2; }
    for seed in $(expand "$seeds"); do
      id="$(slug "$scene")_${planner}_$seed"
      [ -s "$out/runs/$id.json" ] && continue  # done in an earlier, interrupted evaluation
      # A failed run leaves its log, not a partial JSON, and names itself with the log's last line.
      printf '%q explore %q --capmap data/arms/fvx-arm.fcm --arm data/arms/fvx-arm.urdf --strategy %q %s --seed %q --max-views %q --threads %q --timing --format json -o %q > %q 2> %q && mv %q %q || { rm -f %q; echo "evaluate-planners: %s failed: $(tail -1 %q)" >&2; exit 1; }\n' \
        "$fvx" "$scene" "$strategy" "$flags" "$seed" "$max_views" "$threads" "$out/runs/$id.session" \
        "$out/runs/$id.json.tmp" "$out/runs/$id.log" "$out/runs/$id.json.tmp" "$out/runs/$id.json" \
        "$out/runs/$id.json.tmp" "$id" "$out/runs/$id.log" >> "$tasks"
      rm -rf "${out:?}/runs/$id.session"
    done
  done
done
labels=""
for item in $planners; do labels="$labels ${item%%=*}"; done
total=$(wc -l < "$tasks")
echo "evaluate-planners: $total runs to do, $jobs at a time, in $out/" >&2
failed=0
tr '\n' '\0' < "$tasks" | xargs -0 -P "$jobs" -I{} bash -c '{}' || failed=1
compgen -G "$out/runs/*.json" >/dev/null || { echo "evaluate-planners: no run finished; see $out/runs/*.log" >&2; exit 1; }

# Per run: the coverage after each view (carried to max-views) and the summary fields.
runs_csv="$out/runs.csv"
echo "scene,planner,seed,views,end,utility_exhausted,observable_void_cells,target_observable,target_seen_at,views_to_95,void_known_final,known_final,auc,search_s_median" > "$runs_csv"
echo "scene,planner,seed,view,void_known_fraction" > "$out/coverage.csv"
for f in "$out"/runs/*.json; do
  [ -e "$f" ] || continue
  id="$(basename "$f" .json)"
  IFS=_ read -r scene planner seed <<< "$id"
  jq -r --arg scene "$scene" --arg planner "$planner" --arg seed "$seed" --argjson max "$max_views" '
    def med: sort | if length == 0 then null else .[(length / 2 | floor)] end;
    .results as $r
    | [$r.rows[].void_known_fraction] as $c
    | [range(0; $max) | if . < ($c | length) then $c[.] else $c[-1] end] as $carried
    | ([$r.rows[] | select(.target_seen) | .view] | first // "") as $seen
    | ([$r.rows[] | select(.void_known_fraction >= 0.95) | .view] | first // "") as $v95
    | (if $r.observable_target_cells == null then "" elif $r.observable_target_cells >= 5 then "yes" else "no" end) as $obs
    | [$scene, $planner, $seed, $r.views, ($r.end | gsub(","; ";")), $r.utility_exhausted, $r.observable_void_cells,
       $obs, $seen, $v95, $c[-1], $r.rows[-1].known_fraction, ($carried | add / $max),
       ([$r.rows[].timing_s.search] | med)] | @csv' "$f" | tr -d '"' >> "$runs_csv"
  jq -r --arg scene "$scene" --arg planner "$planner" --arg seed "$seed" --argjson max "$max_views" '
    [.results.rows[].void_known_fraction] as $c
    | range(0; $max) | [$scene, $planner, $seed, . + 1, (if . < ($c | length) then $c[.] else $c[-1] end)] | @csv' "$f" |
    tr -d '"' >> "$out/coverage.csv"
done

# Per planner. Views to 95 %: the median over runs, a run that never got there counting as
# max-views + 1. AUC: the mean coverage over the views; the first planner's AUC is compared
# with each other's on the same scene and seed: in how many it is higher.
awk -F, -v max="$max_views" -v md="$out/summary.md" -v csv="$out/summary.csv" -v order="$labels" '
  function median(list, n,    a, i, j, t) {
    split(list, a, " "); n = length(a)
    for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
    return n ? a[int((n + 1) / 2)] : "-"
  }
  NR == 1 { next }
  {
    p = $2; key = $1 "_" $3; planners[p] = 1; runs[p]++
    v95 = $10 == "" ? max + 1 : $10; views95[p] = views95[p] " " v95; reached[p] += $10 != ""
    ended[p] += $6 == "true"; auc[p] += $13; auc_of[p, key] = $13; keys[key] = 1
    search[p] = search[p] " " $14
    if ($8 == "yes") { observable[p]++; seen[p] += $9 != "" }
  }
  END {
    n_order = split(order, ordered, " ")
    ref = ordered[1]
    print "| planner | runs | views to 95 % of the void (median) | reached 95 % | ended with utility 0 | target seen where observable | mean AUC | " ref " AUC higher | search s (median) |" > md
    print "|---|---|---|---|---|---|---|---|---|" > md
    print "planner,runs,views_to_95_median,reached_95,ended_utility_0,target_observable,target_seen,auc_mean,first_auc_higher,runs_compared,search_s_median" > csv
    for (i = 1; i <= n_order; i++) {
      p = ordered[i]
      if (!(p in planners)) continue
      higher = 0; compared = 0
      for (k in keys) if ((p, k) in auc_of && (ref, k) in auc_of) { compared++; higher += auc_of[ref, k] > auc_of[p, k] }
      m = median(views95[p]); m = m > max ? ">" max : m
      printf "| %s | %d | %s | %d/%d | %d/%d | %d/%d | %.3f | %s | %.3f |\n", p, runs[p], m, reached[p], runs[p], ended[p], runs[p],
        seen[p], observable[p], auc[p] / runs[p], p == ref ? "-" : higher "/" compared, median(search[p]) > md
      printf "%s,%d,%s,%d,%d,%d,%d,%.4f,%d,%d,%.4f\n", p, runs[p], m, reached[p], ended[p], observable[p], seen[p], auc[p] / runs[p],
        higher, compared, median(search[p]) > csv
    }
  }' "$runs_csv"

# Median and quartiles per planner and view, then the plot.
awk -F, -v order="$labels" 'NR > 1 { v[$2, $4] = v[$2, $4] " " $5; planners[$2] = 1; if ($4 > n) n = $4 }
  function q(list, f,    a, k, i, j, t) {
    k = split(list, a, " ")
    for (i = 2; i <= k; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
    return a[int(f * (k - 1)) + 1]
  }
  END { m = split(order, ordered, " "); for (o = 1; o <= m; o++) { p = ordered[o]; if (!(p in planners)) continue; print "# " p; for (i = 1; i <= n; i++) print i, 100 * q(v[p, i], 0.5), 100 * q(v[p, i], 0.25), 100 * q(v[p, i], 0.75); print ""; print "" } }' \
  "$out/coverage.csv" > "$out/coverage.dat"
blocks=$(grep -c '^# ' "$out/coverage.dat" || true)
plot=""
for i in $(seq 0 $((blocks - 1))); do
  name=$(grep '^# ' "$out/coverage.dat" | sed -n "$((i + 1))p" | cut -c3-)
  plot="$plot '$out/coverage.dat' index $i using 1:3:4 with filledcurves lc $((i + 1)) fs transparent solid 0.2 notitle, '' index $i using 1:2 with linespoints lc $((i + 1)) lw 2 title '$name',"
done
gnuplot <<EOF
set terminal pngcairo size 900,560 font ",11"
set output "$out/coverage.png.tmp"
set title "Observable void volume known after each view (median; band: quartiles across runs)"
set xlabel "view"; set ylabel "void known, %"; set yrange [0:100]; set xrange [1:$max_views]
set key bottom right; set grid; set xtics 1
plot ${plot%,}
EOF
mv "$out/coverage.png.tmp" "$out/coverage.png"
cat "$out/summary.md"
echo "evaluate-planners: $(($(wc -l < "$runs_csv") - 1)) runs; $out/summary.md, summary.csv, runs.csv, coverage.png" >&2
exit "$failed"
