#!/usr/bin/env bash
# Renders every SPD scene and the built-in procedural scene into doc/images/
# with the reference renderer (the pictures in doc/ and the README).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
spd="$root/../shared/scenes/spd"
size=${SIZE:-256x256}
mkdir -p "$root/doc/images"
for f in "$spd"/*.nff; do
  n=$(basename "$f" .nff)
  "$root/build/rtref" "$f" --size "$size" --threads "$(nproc)" -o "$root/doc/images/$n.png" | head -1
done
"$root/build/rtref" "$spd/balls-4.nff" --size 512x512 --threads "$(nproc)" -o "$root/doc/images/balls-4-512.png" | head -1
"$root/build/rtref" --size "$size" -o "$root/doc/images/procedural.png" | head -1
"$root/build/rtref" --size "$size" --concentration 0.25 -o "$root/doc/images/procedural-f0.25.png" | head -1
