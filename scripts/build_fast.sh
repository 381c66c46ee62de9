#!/usr/bin/env bash
# The fast build, for benchmarks: rtsim and rtref profile-guided and
# link-time optimised, alike (CMakeLists.txt, RT_PGO), in build-fast/.
# build-pgo/ holds an instrumented pair, which renders a training job
# whenever it has changed; each profile that changed goes beside its object
# in build-fast/, whose object is then made again with it. About four
# minutes from a clean clone on 2 cores; later builds make again only what
# changed (doc/exploration.md, "The build"). Profiles change only the code's
# layout and inlining, never a result.
#   bash scripts/build_fast.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in
  -h|--help) sed -n '2,10s/^# \{0,1\}//p' "$0"; exit 0 ;;
  "") ;;
  *) echo "build_fast.sh: $1: takes no arguments" >&2; exit 2 ;;
esac
gen="$root/build-pgo" use="$root/build-fast"
cmake -S "$root" -B "$gen" -DCMAKE_BUILD_TYPE=Release -DRT_PGO=generate >/dev/null
cmake --build "$gen" -j "$(nproc)" --target rtsim rtref
if [ ! -e "$gen/trained" ] || [ "$gen/rtsim" -nt "$gen/trained" ] || [ "$gen/rtref" -nt "$gen/trained" ]; then
  # The training job: the built-in procedural scene, not a benchmark's. The
  # default job as scripts/run.sh runs it (exact mode, the one-node
  # baseline, a balancing policy, a VCD: code a profile never saw is laid
  # out as cold) and a denser scene at 512x512 with a 100 us quantum;
  # rtref on that scene.
  find "$gen" -name '*.gcda' -delete
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
  # Without address randomisation: value profiles record addresses, and
  # the same job then leaves the same profiles (no object is made again).
  norand=(setarch "$(uname -m)" -R)
  "${norand[@]}" "$gen/rtsim" -q --image "$out/a.png" --report "$out/a.json" --vcd "$out/a.vcd"
  "${norand[@]}" "$gen/rtsim" -q --spheres 10000 --size 512x512 --quantum 100us --no-baseline --image "$out/b.png" --report "$out/b.json"
  "${norand[@]}" "$gen/rtref" --spheres 10000 --size 512x512 -o "$out/c.png" >/dev/null
  touch "$gen/trained"
fi
(cd "$gen" && find CMakeFiles -name '*.gcda') | while read -r f; do
  if ! cmp -s "$gen/$f" "$use/$f"; then
    mkdir -p "$(dirname "$use/$f")"
    cp "$gen/$f" "$use/$f"
    rm -f "$use/${f%.gcda}.o"  # (make does not know an object depends on its profile)
  fi
done
cmake -S "$root" -B "$use" -DCMAKE_BUILD_TYPE=Release -DRT_PGO=use >/dev/null
cmake --build "$use" -j "$(nproc)" --target rtsim rtref
