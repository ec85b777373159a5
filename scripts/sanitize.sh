#!/usr/bin/env bash
# The sanitizer job (.ci/run runs it after scripts/test.sh): the unit and CLI tests built with
# clang, AddressSanitizer and UndefinedBehaviorSanitizer into build-sanitize/ (or
# $FVX_SANITIZE_BUILD_DIR) and run there, then every fuzz harness for $FVX_FUZZ_SECONDS
# (default 30) on its corpus. Any sanitizer report fails the job.
#
#   scripts/sanitize.sh           the job
#   scripts/sanitize.sh --proof   runs only the tests labelled 'proof' (a heap overflow and a
#                                 signed overflow planted in tests/fuzz/sanitizer_proof.cpp):
#                                 it must fail, which shows the job fails when it should
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -gt 1 ] || { [ $# -eq 1 ] && [ "$1" != "--proof" ]; }; then
  echo "sanitize.sh: unknown argument '$*'; usage: scripts/sanitize.sh [--proof]" >&2
  exit 2
fi
if [ -n "${FVX_REAL_DATA:-}" ] && [ -d "$FVX_REAL_DATA" ]; then
  FVX_REAL_DATA="$(cd "$FVX_REAL_DATA" && pwd)"
fi
export FVX_REAL_DATA="${FVX_REAL_DATA:-}"
build="${FVX_SANITIZE_BUILD_DIR:-build-sanitize}"
scripts/install-deps.sh
scripts/configure-sanitize.sh "$build"
cmake --build "$build" -j "$(nproc)"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0:max_allocation_size_mb=4000}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0}"
if [ "${1:-}" = "--proof" ]; then
  (cd "$build" && ctest --output-on-failure -L proof)
  exit $?
fi
# The tests that take more than 10 s in the release build or under ASan (tests/sanitize-skip.txt):
# end-to-end loops and planner sweeps whose readers and steps the other tests already cover.
# Under ASan they would take the job past CI's 30 minutes; they run in scripts/test.sh.
skip=$(grep -v -e '^#' -e '^$' tests/sanitize-skip.txt)
# A name that matches no test (one renamed since) would quietly put its test back in the job.
missing=$(grep -vxFf <(cd "$build" && ctest -N | awk '/Test +#/ {print $3}') <<< "$skip" || true)
if [ -n "$missing" ]; then
  echo "sanitize.sh: tests/sanitize-skip.txt names no test called: ${missing//$'\n'/ }" >&2
  exit 1
fi
slow="^($(paste -sd'|' <<< "$skip"))\$"
(cd "$build" && ctest --output-on-failure -j "$(nproc)" -LE proof -E "$slow")
scripts/fuzz.sh "${FVX_FUZZ_SECONDS:-30}"
