#!/usr/bin/env bash
# Fuzzes fvx's readers with libFuzzer (tests/fuzz/): builds the harnesses with clang, ASan and
# UBSan into build-sanitize/ (or $FVX_SANITIZE_BUILD_DIR), then runs each on its corpus and
# prints executions and findings per harness. Exit 1 when any harness found something.
#
#   scripts/fuzz.sh [SECONDS]            each harness SECONDS (default 60), $(nproc) at a time
#   scripts/fuzz.sh --runs N [HARNESS…]  each harness exactly N executions
#
# Findings (crash-*, leak-*, timeout-*, oom-*) go to <build>/fuzz/findings/<harness>/ and
# sanitizer reports to <build>/fuzz/reports/<harness>/; the growing corpus stays in
# <build>/fuzz/corpus/<harness>/. Seeds: tests/fuzz/corpus/ (found-* are past findings, kept
# as regression inputs), small files from data/, and from $FVX_REAL_DATA when set.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=60 runs=""
harnesses=()
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs="${2:?--runs needs a number}"; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    fuzz_*) harnesses+=("$1"); shift ;;
    *[!0-9]*|'') echo "fuzz.sh: '$1' is neither SECONDS, --runs N nor a harness name" >&2; exit 2 ;;
    *) seconds="$1"; shift ;;
  esac
done
all=(fuzz_pcd fuzz_ply fuzz_depth_image fuzz_octree fuzz_fcm fuzz_json fuzz_trajectory fuzz_urdf)  # fuzz_bag: by name (README)
[ ${#harnesses[@]} -gt 0 ] || harnesses=("${all[@]}")

build="${FVX_SANITIZE_BUILD_DIR:-build-sanitize}"
scripts/install-deps.sh
scripts/configure-sanitize.sh "$build"
cmake --build "$build" -j "$(nproc)" --target "${harnesses[@]}"

# The working corpus: the committed seeds, the project's small data files, and small real
# files when FVX_REAL_DATA is set (copies; libFuzzer adds what it finds beside them).
seed_corpus() {
  local c="$1" real="${FVX_REAL_DATA:-}"
  for h in "${all[@]}"; do mkdir -p "$c/$h"; cp -n tests/fuzz/corpus/"$h"/* "$c/$h"/; done
  cp -n data/scenes/*.ply "$c/fuzz_ply/"
  cp -n data/scenes/*.json "$c/fuzz_json/"
  { echo "base_link kinect_optical"; cat data/arms/fvx-arm.urdf; } > "$c/fuzz_urdf/fvx-arm.txt"
  [ -n "$real" ] && [ -d "$real" ] || return 0
  [ -f "$real/arms/youbot_arm.urdf" ] && { echo "base_link arm_link_5"; cat "$real/arms/youbot_arm.urdf"; } > "$c/fuzz_urdf/youbot.txt"
  [ -f "$real/arms/so101_arm.urdf" ] && { echo "base_link gripper_frame_link"; cat "$real/arms/so101_arm.urdf"; } > "$c/fuzz_urdf/so101.txt"
  find "$real" -size -64k \( -name '*.log' -o -name 'pose.txt' -o -name 'groundtruth.txt' \) \
    -exec cp -n {} "$c/fuzz_trajectory/" \; 2>/dev/null || true
}

out="$build/fuzz"
mkdir -p "$out"
seed_corpus "$out/corpus"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0}"

run_one() {  # harness → one line: name executions exec/s corpus findings
  local h="$1" log="$out/$1.log"
  mkdir -p "$out/findings/$h"
  local limit="-max_total_time=$seconds"
  [ -n "$runs" ] && limit="-runs=$runs"
  local dict=()
  [ -f "tests/fuzz/$h.dict" ] && dict=("-dict=tests/fuzz/$h.dict")
  # Sanitizer reports go to files: a reader may have stderr captured when one fires.
  mkdir -p "$out/reports/$h"
  local report="log_path=$out/reports/$h/report"
  set +e
  ASAN_OPTIONS="$ASAN_OPTIONS:$report" UBSAN_OPTIONS="$UBSAN_OPTIONS:$report" "$build/tests/fuzz/$h" "$limit" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=65536 \
    -print_final_stats=1 "${dict[@]}" -artifact_prefix="$out/findings/$h/" "$out/corpus/$h" > "$log" 2>&1
  local status=$?
  set -e
  local execs rate
  execs=$(awk -F: '/stat::number_of_executed_units/ { print $NF + 0 }' "$log" | tail -1)
  rate=$(awk -F: '/stat::average_exec_per_sec/ { print $NF + 0 }' "$log" | tail -1)
  local found
  found=$(find "$out/findings/$h" -type f | wc -l)
  printf '%-18s %12s %8s %8s %4s %s\n' "$h" "${execs:-?}" "${rate:-?}" \
    "$(find "$out/corpus/$h" -type f | wc -l)" "$found" "$([ $status -eq 0 ] || echo "exit $status, see $log and $out/reports/$h")"
}
export -f run_one
export build out seconds runs

printf '%-18s %12s %8s %8s %4s\n' harness executions exec/s corpus found
printf '%s\n' "${harnesses[@]}" | xargs -P "$(nproc)" -I{} bash -c 'run_one {}' | sort > "$out/summary.txt"
cat "$out/summary.txt"
! awk '$5 != 0 || NF > 5 { bad = 1 } END { exit !bad }' "$out/summary.txt"
