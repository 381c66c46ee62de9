#!/usr/bin/env bash
# The main job on its built-in default: installs what is missing, builds,
# and renders the built-in procedural scene with the reference renderer,
# writing out/default.png and out/default.json and printing a summary.
# Extra arguments go to rtref (e.g. a scene file, --size 512x512).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh"
"$root/scripts/build.sh" >/dev/null
mkdir -p "$root/out"
"$root/build/rtref" -o "$root/out/default.png" --stats "$root/out/default.json" "$@"
