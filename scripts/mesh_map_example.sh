#!/usr/bin/env bash
# The mesh picture in doc/machine.md and the README: a 4x4x4 run of the
# default scene balanced with the default policy, drawn by rtsim --map
# (scripts/mesh_map.py).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh" plots
"$root/scripts/build.sh" >/dev/null
"$root/build/rtsim" --mesh 4 --size 96x96 --balance default --no-baseline -q --image '' \
  --map "$root/doc/images/mesh-map.png"
echo "wrote doc/images/mesh-map.png"
