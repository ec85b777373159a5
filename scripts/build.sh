#!/usr/bin/env bash
# Configures and builds fvx into build/ (or $FVX_BUILD_DIR). Extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${FVX_BUILD_DIR:-build}"
# PCL's config prints two "** WARNING ** io features ..." lines about optional codecs; hide only those.
cmake -S . -B "$build" -DFVX_WERROR="${FVX_WERROR:-OFF}" "$@" > /dev/null 2> >(grep -v "^\*\* WARNING \*\* io features" >&2)
cmake --build "$build" -j "$(nproc)"
