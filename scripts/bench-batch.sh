#!/usr/bin/env bash
# Batch work (issue 22): a capability map built as N shards by GNU parallel on this machine's
# cores against one process on all of them, in the same run. The one-process build is the
# default (fk-witness: rounds of witnesses until the recall estimate reaches 0.995). Shards:
#  - slab (the default split): each shard keeps one z-slab, and draws every witness;
#  - samples with the budget one process drew (its report's fk_samples), and with twice it:
#    each shard draws its share of the budget, the merge applies the stop rule.
# Per plan: the batch's wall time (plan, `parallel -j CORES` of one-thread tasks, merge), its
# ratio to one process, whether the merged map is the one-process map byte for byte, the
# shards' run times from the job log and, for 64 shards, the time 64 slots would take (the
# longest shard plus the merge, as measured here), and the floor that no split goes under (GNU
# parallel running N empty tasks on the same slots, plus the merge). Then fk-seeded-ik, whose slab shards split
# the IK work, at FVX_BATCH_IK_VOXEL (default 0.05; 0 skips it).
#   scripts/bench-batch.sh [URDF BASE TIP]   default: FVX_REAL_DATA's youBot arm
# FVX_BATCH_VOXEL (default 0.025), FVX_BATCH_SHARDS (default "2 8 64"), FVX_BATCH_SLAB_SHARDS
# (default: the same; slab shards draw every witness each, so 64 of them take 64 builds).
set -euo pipefail
cd "$(dirname "$0")/.."
build="${FVX_BUILD_DIR:-build}"
data="${FVX_REAL_DATA:-../shared/data}"
urdf="${1:-$data/arms/youbot_arm.urdf}" base="${2:-base_link}" tip="${3:-arm_link_5}"
fvx="$(pwd)/$build/src/fvx"
[ -x "$fvx" ] || { scripts/install-deps.sh && scripts/build.sh >/dev/null; }
command -v parallel >/dev/null && command -v jq >/dev/null && [ -x /usr/bin/time ] || scripts/install-deps.sh
[ -f "$urdf" ] || { echo "bench-batch: $urdf not found; set FVX_REAL_DATA or give a URDF" >&2; exit 1; }
slots="$(nproc)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# plan LABEL SHARDS OPTIONS...: one row of the table, against the one-process build of the
# same options run just before it (this machine's speed drifts by tens of percent).
plan() {
  local label="$1" n="$2"; shift 2
  local dir="$tmp/plan-$label-$n" start merge_start end one_s
  /usr/bin/time -f '%e' -o "$tmp/one.time" "$fvx" capmap build "$urdf" "${one_opts[@]}" -o "$tmp/one.fcm" > /dev/null
  one_s="$(cat "$tmp/one.time")"
  start=$(date +%s.%N)
  "$fvx" batch capmap "$urdf" "$@" --threads 1 --shards "$n" -o "$dir" > /dev/null
  parallel -j "$slots" --joblog "$dir/joblog" < "$dir/tasks.txt"
  merge_start=$(date +%s.%N)
  sh "$dir/merge.sh" > /dev/null
  end=$(date +%s.%N)
  local same=no
  cmp -s "$tmp/one.fcm" "$dir/map.fcm" && same=yes
  awk -F'\t' 'NR > 1 { print $4 }' "$dir/joblog" | sort -g > "$tmp/runtimes"
  local samples empty_start empty_end
  samples=$(cat "$dir"/parts/*.json | jq -s 'map(.results.fk_samples) | add')
  # The floor no split can go under: GNU parallel running N empty tasks on the same slots,
  # plus this plan's merge. Over a tenth of one process, N shards cannot be within 10 %.
  empty_start=$(date +%s.%N)
  seq "$n" | parallel -j "$slots" true
  empty_end=$(date +%s.%N)
  awk -v label="$label" -v n="$n" -v one="$one_s" -v s="$start" -v m="$merge_start" -v e="$end" -v same="$same" \
      -v samples="$samples" -v es="$empty_start" -v ee="$empty_end" '{ t[NR] = $1 } END {
    floor = (ee - es) + (e - m)
    printf "| %s | %d | %d | %.2f | %.2f | %.2f | %s | %.2f / %.2f / %.2f | %.2f (%.0f %%) | %s |\n", label, n, samples, one, e - s, (e - s) / one, same,
      t[1], t[int((NR + 1) / 2)], t[NR], floor, 100 * floor / one, (n >= 64 ? sprintf("%.2f", t[NR] + (e - m)) : "-") }' "$tmp/runtimes"
}

header() {
  printf '| shards | N | configurations drawn | one process s (%s threads, just before) | batch s (plan, %s slots, merge) | batch / one | same bytes | shard s min / median / max | floor s: N empty tasks through parallel + merge (of one process) | 64 slots s (projected) |\n' "$slots" "$slots"
  printf '|---|---|---|---|---|---|---|---|---|---|\n'
}

voxel="${FVX_BATCH_VOXEL:-0.025}"
one_opts=(--base "$base" --tip "$tip" --voxel "$voxel" --directions 200)
"$fvx" capmap build "$urdf" "${one_opts[@]}" -o "$tmp/one.fcm" > "$tmp/one.json"
budget="$(jq '.results.fk_samples' "$tmp/one.json")"  # what one process draws: the samples shards' budget
echo "fk-witness at $voxel m: one process draws $budget configurations"
header
for n in ${FVX_BATCH_SLAB_SHARDS:-${FVX_BATCH_SHARDS:-2 8 64}}; do plan slab "$n" "${one_opts[@]}"; done
for n in ${FVX_BATCH_SHARDS:-2 8 64}; do plan samples "$n" "${one_opts[@]}" --shard-split samples --fk-samples "$budget"; done
plan samples-2x 8 "${one_opts[@]}" --shard-split samples --fk-samples "$((2 * budget))"

ik_voxel="${FVX_BATCH_IK_VOXEL:-0.05}"
if [ "$ik_voxel" != 0 ]; then
  one_opts=(--base "$base" --tip "$tip" --voxel "$ik_voxel" --directions 200 --method fk-seeded-ik)
  echo
  echo "fk-seeded-ik at $ik_voxel m"
  header
  for n in 2 8; do plan ik-slab "$n" "${one_opts[@]}"; done
fi
