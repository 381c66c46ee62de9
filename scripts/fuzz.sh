#!/usr/bin/env bash
# Fuzzes the scene reader (tb/fuzz/fuzz_nff.cpp) with libFuzzer for SECONDS
# (default 1800), seeded with the SPD scenes up to 400 KB; the corpus grows
# in out/fuzz/corpus and crashes land in out/fuzz/. Writes the figures
# (executions, coverage, findings) to doc/results/fuzz.md and doc/robustness.md.
#   bash scripts/fuzz.sh [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-1800}
"$root/scripts/setup.sh" fuzz
cmake -S "$root" -B "$root/build-fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRT_FUZZ=ON \
  -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build "$root/build-fuzz" -j "$(nproc)" --target fuzz_nff
out="$root/out/fuzz"
mkdir -p "$out/corpus"
for f in "$root"/../shared/scenes/spd/*.nff; do
  [ "$(stat -c %s "$f")" -le 400000 ] && cp -n "$f" "$out/corpus/"
done
log="$out/fuzz.log"
set +e
(cd "$out" && "$root/build-fuzz/fuzz_nff" -max_total_time="$seconds" -max_len=65536 -timeout=10 \
  -rss_limit_mb=4096 -print_final_stats=1 corpus) >"$log" 2>&1
status=$?
set -e
/usr/bin/python3 "$root/scripts/fuzz_report.py" "$log" "$status" "$seconds" "$out"
