#!/usr/bin/env bash
# The build: configures (once) and builds build/ (Release), every target,
# or only those named (scripts/run.sh builds rtsim alone). The build the
# benchmarks measure, profile-guided and link-time optimised, is
# scripts/build_fast.sh (build-fast/); both compute the same bits.
#   bash scripts/build.sh [TARGET...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in -h|--help) sed -n '2,6s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
# A unity build (the libraries' sources compiled a few to a file; the tests
# file by file, CMakeLists.txt): every target from scratch in 6 min 2 s on
# 2 cores where file by file took about 8; the same bits (same_outputs.py),
# and rtsim no slower.
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DRT_PGO= -DCMAKE_UNITY_BUILD=ON >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$root/build" -j "$(nproc)" "${targets[@]}"
