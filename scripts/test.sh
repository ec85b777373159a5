#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test with ctest.
# Real-data tests read FVX_REAL_DATA (default: ../shared/data beside the project, if present).
set -euo pipefail
# A relative FVX_REAL_DATA is relative to where the script was called from; the tests run in
# the build folder, so make it absolute first.
if [ -n "${FVX_REAL_DATA:-}" ] && [ -d "$FVX_REAL_DATA" ]; then
  FVX_REAL_DATA="$(cd "$FVX_REAL_DATA" && pwd)"
fi
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
if [ -z "${FVX_REAL_DATA:-}" ] && [ -d ../shared/data ]; then
  FVX_REAL_DATA="$(cd ../shared/data && pwd)"
fi
export FVX_REAL_DATA="${FVX_REAL_DATA:-}"
[ -n "$FVX_REAL_DATA" ] || echo "test.sh: FVX_REAL_DATA is not set; real-data tests will be skipped" >&2
cd "${FVX_BUILD_DIR:-build}"
ctest --output-on-failure -j "$(nproc)"
