#!/usr/bin/env bash
# Installs what rtsim needs from Debian 12 packages, only what is missing, so
# a second run is quick. Needs root (or sudo) when something is missing.
set -euo pipefail

packages=(
  g++ make cmake pkg-config
  libsystemc-dev      # SystemC 2.3.4 (models/)
  libjemalloc-dev     # rtsim's allocator, on huge pages (tb/rtsim.cpp)
  libboost-dev        # small_vector: a message's rays inline (models/channel/message.h)
  libglm-dev          # vector maths (sw/)
  libcli11-dev        # command lines
  nlohmann-json3-dev  # reports and stats
  libpng-dev          # images
  libssl-dev          # SHA-256 of a report's scene file (tb/rerun.cpp)
  libgtest-dev        # tests
  gtkwave             # vcd2fst checks the VCD; gtkwave views it
  python3             # scripts (Debian's /usr/bin/python3)
  python3-distributed # the sweep driver's Dask submission (and its test)
  python3-matplotlib  # rtsim --map (scripts/mesh_map.py) and its test
  python3-hypothesis  # fuzzing the tools' readers (tb/tests/test_tool_readers.py)
  time                # GNU time: a run's own peak memory (scripts/bench_rtsim.py)
)

# `setup.sh plots`: also what the sweep and chart scripts need.
if [ "${1:-}" = "plots" ]; then packages+=(python3-numpy); fi
# `setup.sh bench`: also perf, which bench_scaling.py samples the runs with,
# and valgrind, under which bench_misses.py counts a run's cache misses.
if [ "${1:-}" = "bench" ]; then packages+=(linux-perf valgrind); fi
# `setup.sh fuzz`: clang and its libFuzzer, for scripts/fuzz.sh.
if [ "${1:-}" = "fuzz" ]; then packages+=(clang libclang-rt-14-dev); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root to install: ${missing[*]}" >&2; exit 1; }
  sudo=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
