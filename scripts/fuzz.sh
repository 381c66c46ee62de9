#!/usr/bin/env bash
# Fuzzes one of rtsim's readers with libFuzzer for SECONDS (default 1800):
#   nff     the scene reader (tb/fuzz/fuzz_nff.cpp), seeded with the SPD
#           scenes up to 400 KB;
#   report  the report reader behind --rerun (tb/fuzz/fuzz_report.cpp),
#           seeded with reports of a few small runs;
#   config  the --config reader (tb/fuzz/fuzz_config.cpp), seeded with
#           configs/*.conf and the flags of those reports.
# The corpus grows in out/fuzz[-TARGET]/corpus and findings land beside it.
# Writes the figures (executions, coverage, findings) to out/fuzz[-TARGET]/
# fuzz.md; with --doc, to doc/results/fuzz[-TARGET].md and doc/robustness.md.
#   bash scripts/fuzz.sh [--target nff|report|config] [--doc] [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
target=nff
doc=
while [ $# -gt 0 ]; do
  case "$1" in
    --target) [ $# -ge 2 ] || { echo "fuzz.sh: --target: nff, report or config" >&2; exit 2; }
              target=$2; shift 2 ;;
    --doc) doc=doc; shift ;;
    -h|--help) sed -n '2,12s/^# \{0,1\}//p' "$0"; exit 0 ;;
    -*) echo "fuzz.sh: $1: unknown (--target, --doc, --help)" >&2; exit 2 ;;
    *) break ;;
  esac
done
case "$target" in nff|report|config) ;; *) echo "fuzz.sh: --target: nff, report or config, not '$target'" >&2; exit 2;; esac
seconds=${1:-1800}
case "$seconds" in
  ''|*[!0-9]*) echo "fuzz.sh: SECONDS: a whole number, not '$seconds'" >&2; exit 2 ;;
esac
[ $# -le 1 ] || { echo "fuzz.sh: one SECONDS at most, not '$*'" >&2; exit 2; }
"$root/scripts/setup.sh" fuzz
cmake -S "$root" -B "$root/build-fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRT_FUZZ=ON \
  -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build "$root/build-fuzz" -j "$(nproc)" --target "fuzz_$target"
suffix=$([ "$target" = nff ] && echo "" || echo "-$target")
out="$root/out/fuzz$suffix"
mkdir -p "$out/corpus"
max_len=65536
if [ "$target" = nff ]; then
  for f in "$root"/../shared/scenes/spd/*.nff; do
    [ "$(stat -c %s "$f")" -le 400000 ] && cp -n "$f" "$out/corpus/"
  done
else
  # Reports of small runs (plain, balanced, a sequence, per-node and
  # per-link flags), from the plain build (scripts/build.sh).
  "$root/scripts/build.sh" rtsim >/dev/null
  seeds=$(mktemp -d)
  i=0
  for flags in "" "--balance slide --mesh 3" "--frames 2 --balance resplit" \
               "--node-speed 0,0,0=2 --link-set 0,0,0,+x:latency=1us --light 1,2,3 --eye-step 0.1,0,0 --frames 2"; do
    i=$((i + 1))
    # shellcheck disable=SC2086
    "$root/build/rtsim" --spheres 100 --size 8x8 --mesh 2 --no-baseline -q --image '' $flags --report "$seeds/r$i.json"
    if [ "$target" = report ]; then
      cp "$seeds/r$i.json" "$out/corpus/"
    else
      /usr/bin/python3 -c "import json, sys; sys.stdout.write(json.load(open(sys.argv[1]))['rerun']['flags'])" \
        "$seeds/r$i.json" >"$out/corpus/flags$i.conf"
    fi
  done
  rm -rf "$seeds"
  [ "$target" = config ] && cp "$root"/configs/*.conf "$out/corpus/"
  [ "$target" = report ] && max_len=262144
fi
log="$out/fuzz.log"
set +e
(cd "$out" && "$root/build-fuzz/fuzz_$target" -max_total_time="$seconds" -max_len="$max_len" -timeout=10 \
  -rss_limit_mb=4096 -print_final_stats=1 corpus) >"$log" 2>&1
status=$?
set -e
/usr/bin/python3 "$root/scripts/fuzz_report.py" "$log" "$status" "$seconds" "$out" "$target" $doc
