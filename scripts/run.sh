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
# The build's progress on stderr (cmake's [ NN%] lines): the first build
# takes minutes, and a silent one looks hung. stdout stays the summary's.
if [[ -x "$root/build/rtsim" ]]; then
    echo "run.sh: bringing build/rtsim up to date" >&2
else
    echo "run.sh: building rtsim in build/ (the first time: about 2.5 minutes on 2 cores; its progress follows)" >&2
fi
"$root/scripts/build.sh" rtsim >&2
mkdir -p "$root/out"
"$root/build/rtsim" --image "$root/out/rtsim.png" --report "$root/out/rtsim.json" --vcd "$root/out/rtsim.vcd" "$@"
