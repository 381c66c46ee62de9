#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs every test.
#   bash scripts/test.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in
  -h|--help) sed -n '2,3s/^# \{0,1\}//p' "$0"; exit 0 ;;
  "") ;;
  *) echo "test.sh: $1: takes no arguments (ctest's own: cd build && ctest -R NAME)" >&2; exit 2 ;;
esac
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
cd "$root/build"
ctest --output-on-failure -j "$(nproc)" --timeout 300
