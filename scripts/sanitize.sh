#!/usr/bin/env bash
# The whole test suite under AddressSanitizer (leaks included) and
# UndefinedBehaviorSanitizer, in build-sanitize/ (Debug, -O1). SystemC's
# QuickThreads switch stacks by hand, which AddressSanitizer's fake stacks
# do not follow: detect_stack_use_after_return=0. The tests of the Python
# tools and the docs (label `tools`) run in the plain build only.
#   bash scripts/sanitize.sh [CTEST ARGUMENTS, e.g. -R NAME]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in -h|--help) sed -n '2,6s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
"$root/scripts/setup.sh"
# A unity build (sources compiled a few to a file; the tests file by file
# since, CMakeLists.txt): on 2 cores 5 min 53 s against 8 min 47 s file by
# file (measured with the tests in it too), most of CI's time being its two builds.
cmake -S "$root" -B "$root/build-sanitize" -DCMAKE_BUILD_TYPE=Debug -DRT_SANITIZE=ON -DCMAKE_UNITY_BUILD=ON >/dev/null
cmake --build "$root/build-sanitize" -j "$(nproc)"
cd "$root/build-sanitize"
export ASAN_OPTIONS=detect_stack_use_after_return=0:detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --output-on-failure -j "$(nproc)" --timeout 600 -LE tools "$@"
