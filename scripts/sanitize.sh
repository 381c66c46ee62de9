#!/usr/bin/env bash
# The whole test suite under AddressSanitizer (leaks included) and
# UndefinedBehaviorSanitizer, in build-sanitize/ (Debug, -O1). SystemC's
# QuickThreads switch stacks by hand, which AddressSanitizer's fake stacks
# do not follow: detect_stack_use_after_return=0. The tests of the Python
# tools and the docs (label `tools`) and the end-to-end runs of
# --max-error run in the plain build only.
#   bash scripts/sanitize.sh [CTEST ARGUMENTS, e.g. -R NAME]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in -h|--help) sed -n '2,8s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
"$root/scripts/setup.sh"
# A unity build (sources compiled a few to a file; the tests file by file
# since, CMakeLists.txt): on 2 cores 5 min 53 s against 8 min 47 s file by
# file (measured with the tests in it too), most of CI's time being its two builds.
cmake -S "$root" -B "$root/build-sanitize" -DCMAKE_BUILD_TYPE=Debug -DRT_SANITIZE=ON -DCMAKE_UNITY_BUILD=ON >/dev/null
cmake --build "$root/build-sanitize" -j "$(nproc)"
cd "$root/build-sanitize"
export ASAN_OPTIONS=detect_stack_use_after_return=0:detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Rtsim.MaxError*: rtsim end to end at 256x256 on 16x16x16, two or three
# runs each, 64 to 115 s apiece sanitized (most of its tests' time); the
# calibration they run (frames of one machine with express switched and
# every k-th pixel) is sanitized at 6x6x6 by FramesInOneMachine.*.
ctest --output-on-failure -j "$(nproc)" --timeout 600 -LE tools -E '^Rtsim\.MaxError' "$@"
