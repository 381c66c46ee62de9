#!/usr/bin/python3
"""Benchmark of the reference renderer: rtref on an SPD scene (default
balls-4 at 512x512), single thread, N runs, each pinned to one CPU (--cpu); prints the median wall time and
rays per second with the ray counts, and with --doc writes them as a table
into doc/benchmarks/rtref.md together with a description of the machine
(without --doc it writes nothing: the table goes to stdout).

Uses only the Python standard library; run with /usr/bin/python3."""
import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import FAST_BUILD, ROOT, spd_scene  # noqa: E402


def build_fast():
    """Makes build-fast/ (scripts/build_fast.sh: only what changed), the
    profile-guided build every benchmark measures."""
    if subprocess.run(["bash", os.path.join(ROOT, "scripts", "build_fast.sh")], stdout=subprocess.DEVNULL).returncode:
        raise outputs.ToolError("scripts/build_fast.sh failed (its messages above)", outputs.FAILED)


def build_kind(build=FAST_BUILD):
    """How a build was made, from its CMake cache: profile-guided and
    link-time optimised when scripts/build_fast.sh made it (RT_PGO=use)."""
    try:
        with open(os.path.join(build, "CMakeCache.txt")) as f:
            pgo = any(line.strip() == "RT_PGO:STRING=use" for line in f)
    except OSError:
        pgo = False
    return "Release build (-O3, profile-guided and link-time optimised)" if pgo else "Release build (-O3)"


def machine(build=FAST_BUILD):
    """The host, the compiler and how `build` (the build whose programs the benchmark runs) was made."""
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    mem = ""
    try:
        with open("/proc/meminfo") as f:
            kb = int(f.readline().split()[1])
            mem = f", {kb / 2**20:.0f} GiB RAM"
    except (OSError, ValueError, IndexError):
        pass
    gxx = subprocess.run(["g++", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    return f"{cpu}, {os.cpu_count()} cores{mem}; {platform.system()} {platform.release()}; {gxx}; {build_kind(build)}"


def add_cpu_option(ap):
    ap.add_argument("--cpu", type=int, default=None,
                    help="CPU to pin every run to (default: the last this script may use; -1: no pinning)")


def pin_to_cpu(cpu, prog):
    """Pins this script, and so every run it starts, to one CPU (--cpu): this
    VM's two CPUs ran at different speeds for minutes at a time (the same
    run took 1.5 s on one and 2.3 s on the other at the same moment), so an
    unpinned run took either time or a mix. Returns the CPU, or None when
    not pinned (-1)."""
    allowed = sorted(os.sched_getaffinity(0))
    pin = allowed[-1] if cpu is None else None if cpu == -1 else cpu
    if pin is not None:
        if pin not in allowed:
            raise outputs.ToolError(f"--cpu {cpu}: not -1 nor one of the CPUs this process may use ({allowed})")
        os.sched_setaffinity(0, {pin})
    return pin


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=spd_scene("balls-4"))
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--rtref", help="the rtref to measure (default: the one in build-fast/, built first)")
    ap.add_argument("--doc", action="store_true", help="write doc/benchmarks/rtref.md")
    add_cpu_option(ap)
    a = ap.parse_args()
    if a.runs < 1:
        raise outputs.ToolError(f"--runs {a.runs}: at least 1")
    outputs.check_input(a.scene, "--scene")
    outputs.image_size(a.size)
    if a.rtref:
        outputs.check_input(a.rtref, "--rtref")
    page = outputs.check_output(os.path.join(ROOT, "doc", "benchmarks", "rtref.md"), "--doc", doc=True) if a.doc else None
    if not a.rtref:
        build_fast()
        a.rtref = os.path.join(FAST_BUILD, "rtref")
    pin = pin_to_cpu(a.cpu, "bench_rtref")
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(a.runs):
            stats = os.path.join(tmp, "s.json")
            p = outputs.run_child([a.rtref, a.scene, "--size", a.size, "--threads", "1", "-o",
                                   os.path.join(tmp, "i.png"), "--stats", stats])
            if p.returncode != 0:
                raise outputs.ToolError(f"rtref exit {p.returncode}: {p.stderr.strip()}", outputs.FAILED)
            with open(stats) as f:
                runs.append(json.load(f))
            print(f"run {i + 1}: {runs[-1]['wall_s']:.3f} s", file=sys.stderr)
    walls = [r["wall_s"] for r in runs]
    s = runs[0]
    rays = s["primary_rays"] + s["shadow_rays"] + s["secondary_rays"]
    med = statistics.median(walls)
    name = os.path.splitext(os.path.basename(a.scene))[0]
    rows = [
        ("scene", f"{name} at {a.size}, max depth {s['max_depth']}, 1 thread, {s['accelerator']}"),
        ("wall time, median of %d" % a.runs, f"{med:.3f} s (min {min(walls):.3f}, max {max(walls):.3f})"),
        ("rays per second (median run)", f"{rays / med:,.0f}"),
        ("primary rays / hits", f"{s['primary_rays']:,} / {s['primary_hits']:,}"),
        ("shadow rays / blocked", f"{s['shadow_rays']:,} / {s['shadow_hits']:,}"),
        ("secondary rays / hits", f"{s['secondary_rays']:,} / {s['secondary_hits']:,}"),
        ("intersection tests", f"{s['intersection_tests']:,}"),
        ("voxel steps", f"{s['voxel_steps']:,}"),
        ("machine", machine() + (f"; every run pinned to CPU {pin}" if pin is not None else "; runs not pinned")),
    ]
    table = "| quantity | value |\n|---|---|\n" + "".join(f"| {k} | {v} |\n" for k, v in rows)
    print(table, end="")
    if page:
        outputs.write_text(page, "# rtref benchmark\n\nWritten by `scripts/bench_rtref.py --doc`; do not edit by hand.\n\n"
                           + table)


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_rtref.py", main))
