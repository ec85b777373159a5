#!/usr/bin/env bash
# Configures and builds fvx into build/ (or $FVX_BUILD_DIR). Extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${FVX_BUILD_DIR:-build}"
# A full build writes about 0.5 GB into the build folder and up to 0.3 GB of compiler temporaries;
# say so plainly before the compiler fails with "No space left on device" half-way through.
free_mb=$(df -Pm "$(dirname "$(realpath -m "$build")")" "${TMPDIR:-/tmp}" 2>/dev/null \
  | awk 'NR > 1 { if (min == "" || $4 < min) min = $4 } END { if (min != "") print min }')
if [ -n "$free_mb" ] && [ "$free_mb" -lt 2048 ]; then
  echo "build.sh: warning: only ${free_mb} MB free for $build or ${TMPDIR:-/tmp}; a full build needs about 1 GB" >&2
fi
# A new build folder uses Ninja where it is installed (scripts/generator.sh).
. scripts/generator.sh
fvx_choose_generator "$build"
# PCL's config prints two "** WARNING ** io features ..." lines about optional codecs; hide only those.
cmake -S . -B "$build" -DFVX_WERROR="${FVX_WERROR:-OFF}" "$@" > /dev/null 2> >(grep -v "^\*\* WARNING \*\* io features" >&2)
cmake --build "$build" -j "$(nproc)"
