#!/usr/bin/env bash
# Renders every SPD scene and the built-in procedural scene with the
# reference renderer: the pictures in doc/ and the README. Into
# out/images/; with --doc, into doc/images/ (the published ones).
#   bash scripts/render_gallery.sh [--doc]      (SIZE=WxH: the gallery's size, default 256x256)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dest="$root/out/images"
case "${1:-}" in
  -h|--help) sed -n '2,5s/^# \{0,1\}//p' "$0"; exit 0 ;;
  --doc) dest="$root/doc/images" ;;
  "") ;;
  *) echo "render_gallery.sh: $1: unknown (--doc or nothing)" >&2; exit 2 ;;
esac
spd="$root/../shared/scenes/spd"
size=${SIZE:-256x256}
mkdir -p "$dest"
# rtref writes each image through a temporary of its own, so a stopped run
# leaves the published picture as it was.
for f in "$spd"/*.nff; do
  n=$(basename "$f" .nff)
  "$root/build/rtref" "$f" --size "$size" --threads "$(nproc)" -o "$dest/$n.png" | head -1
done
"$root/build/rtref" "$spd/balls-4.nff" --size 512x512 --threads "$(nproc)" -o "$dest/balls-4-512.png" | head -1
"$root/build/rtref" --size "$size" -o "$dest/procedural.png" | head -1
"$root/build/rtref" --size "$size" --concentration 0.25 -o "$dest/procedural-f0.25.png" | head -1
