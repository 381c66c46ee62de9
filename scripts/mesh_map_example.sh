#!/usr/bin/env bash
# The mesh picture in doc/machine.md and the README: a 4x4x4 run of the
# default scene balanced with the recommended policy, drawn by rtsim --map
# (scripts/mesh_map.py). To out/images/mesh-map.png; with --doc, to
# doc/images/mesh-map.png (the published one).
#   bash scripts/mesh_map_example.sh [--doc]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dest="$root/out/images"
case "${1:-}" in
  -h|--help) sed -n '2,6s/^# \{0,1\}//p' "$0"; exit 0 ;;
  --doc) dest="$root/doc/images" ;;
  "") ;;
  *) echo "mesh_map_example.sh: $1: unknown (--doc or nothing)" >&2; exit 2 ;;
esac
"$root/scripts/setup.sh" plots
"$root/scripts/build.sh" >/dev/null
mkdir -p "$dest"
"$root/build/rtsim" --mesh 4 --size 96x96 --balance recommended --no-baseline -q --image '' \
  --map "$dest/mesh-map.png"
echo "wrote ${dest#$root/}/mesh-map.png"
