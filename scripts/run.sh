#!/usr/bin/env bash
# The main job on its built-in default: installs what is missing, builds
# rtsim, and runs it with no scene arguments: the paper's
# concentrated-spheres scene on a 4 x 4 x 4 mesh. Writes out/rtsim.png,
# out/rtsim.json and out/rtsim.vcd (+ out/rtsim.gtkw) and prints a summary.
# Extra arguments go to rtsim (e.g. --scene ../shared/scenes/spd/balls-4.nff
# --size 512x512).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh"
"$root/scripts/build.sh" rtsim >/dev/null
mkdir -p "$root/out"
"$root/build/rtsim" --image "$root/out/rtsim.png" --report "$root/out/rtsim.json" --vcd "$root/out/rtsim.vcd" "$@"
