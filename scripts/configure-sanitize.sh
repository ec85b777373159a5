#!/usr/bin/env bash
# Configures the ASan + UBSan build (clang, with the libFuzzer harnesses) into $1, default
# build-sanitize/; scripts/sanitize.sh and scripts/fuzz.sh build in it. -O1 keeps stacks
# readable and the tests fast enough; no benchmarks.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-sanitize}"
. scripts/generator.sh
fvx_choose_generator "$build"
CC=clang CXX=clang++ cmake -S . -B "$build" -DFVX_FUZZ=ON -DFVX_BUILD_BENCH=OFF \
  -DFVX_WERROR="${FVX_WERROR:-OFF}" -DCMAKE_BUILD_TYPE=None "-DCMAKE_CXX_FLAGS=-O1 -gline-tables-only" \
  > /dev/null 2> >(grep -v "^\*\* WARNING \*\* io features" >&2)
