#!/usr/bin/env bash
# Runs a 2x2x2 machine on the procedural scene, writes its waveform and save
# file to waveforms/example-2x2x2.{vcd,gtkw}, opens them in GTKWave on a
# virtual display (Xvfb) and saves a screenshot to doc/images/gtkwave-2x2x2.png.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
need=()
for p in gtkwave xvfb x11-apps imagemagick; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
"$root/scripts/build.sh" >/dev/null
cd "$root/waveforms"
"$root/build/rtsim" --mesh 2 --size 96x96 --concentration 0.5 --no-baseline -q --image '' \
  --vcd example-2x2x2.vcd
display=:97
Xvfb $display -screen 0 1400x900x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $gw $xvfb 2>/dev/null || true' EXIT
sleep 1
DISPLAY=$display gtkwave -a example-2x2x2.gtkw >/dev/null 2>&1 &
gw=$!
sleep 6
DISPLAY=$display xwd -root -silent | convert xwd:- "$root/doc/images/gtkwave-2x2x2.png"
echo "wrote doc/images/gtkwave-2x2x2.png"
