#!/usr/bin/env bash
# Runs a 2x2x2 machine on the procedural scene, writes its waveform and save
# file to waveforms/example-2x2x2.{vcd,gtkw}, opens them in GTKWave on a
# virtual display (Xvfb) and saves a screenshot to doc/images/gtkwave-2x2x2.png;
# then the same with links of 20 MB/s, node 1,0,0 and its links traced:
# its +y link saturated (waveforms/saturated-link.*,
# doc/images/gtkwave-saturated-link.png); then the bottleneck of
# doc/machine.md, "Finding a bottleneck": balls-4 at 256x256 on 6x6x6 with
# 200 MB/s links, the busiest nodes and links traced
# (doc/images/gtkwave-bottleneck.png; its VCD, about 40 MB, is not kept).
# Those are the places with --doc (the published files); without it, the
# waveforms go to out/waveforms/ and the screenshots to out/images/.
#   bash scripts/gtkwave_screenshot.sh [--doc]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
waves="$root/out/waveforms" images="$root/out/images"
case "${1:-}" in
  -h|--help) sed -n '2,13s/^# \{0,1\}//p' "$0"; exit 0 ;;
  --doc) waves="$root/waveforms" images="$root/doc/images" ;;
  "") ;;
  *) echo "gtkwave_screenshot.sh: $1: unknown (--doc or nothing)" >&2; exit 2 ;;
esac
need=()
for p in gtkwave xvfb x11-apps imagemagick; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
"$root/scripts/build.sh" >/dev/null
mkdir -p "$waves" "$images"
cd "$waves"
"$root/build/rtsim" --mesh 2 --size 96x96 --concentration 0.5 --no-baseline -q --image '' \
  --vcd example-2x2x2.vcd
"$root/build/rtsim" --mesh 2 --size 96x96 --concentration 0.5 --link-bandwidth 20MB/s --no-baseline -q --image '' \
  --trace-nodes 1,0,0 --trace-window 0,2ms --vcd saturated-link.vcd
tmp=$(mktemp -d)
"$root/build/rtsim" --scene "$root/../shared/scenes/spd/balls-4.nff" --size 256x256 --mesh 6 \
  --link-bandwidth 200MB/s --no-baseline -q --image '' --trace-nodes busiest:3 --vcd "$tmp/bottleneck.vcd"
display=:97
Xvfb $display -screen 0 1400x900x24 >/dev/null 2>&1 &
xvfb=$!
gw=
trap 'kill $gw $xvfb 2>/dev/null || true; rm -rf "$tmp"' EXIT
sleep 1
shot() {  # shot NAME.gtkw OUT.png [SECONDS to load]
  DISPLAY=$display gtkwave -a "$1" >/dev/null 2>&1 &
  gw=$!
  sleep "${3:-6}"
  # through a temporary beside it: a stopped run leaves the old picture whole
  DISPLAY=$display xwd -root -silent | convert xwd:- "png:$2.incomplete"
  mv "$2.incomplete" "$2"
  kill $gw 2>/dev/null || true
  wait $gw 2>/dev/null || true
  echo "wrote ${2#$root/}"
}
shot example-2x2x2.gtkw "$images/gtkwave-2x2x2.png"
shot saturated-link.gtkw "$images/gtkwave-saturated-link.png"
cd "$tmp"  # (the .gtkw names its VCD relative to itself)
shot bottleneck.gtkw "$images/gtkwave-bottleneck.png" 30
