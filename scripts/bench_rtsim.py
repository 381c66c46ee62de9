#!/usr/bin/python3
"""Benchmark of the machine model: rtsim's wall time against rtref's on the
same scene (default balls-4 at 512x512, N = 4), runs alternated so both see
the same machine state; messages per wall second; peak memory; and how wall
time grows with the mesh size N = 1..8. Prints a table; with --doc writes it
to doc/benchmarks/rtsim.md. Standard library only; run with /usr/bin/python3."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from bench_rtref import machine  # noqa: E402


def timed(cmd):
    """Runs cmd; returns (wall seconds, peak resident set in MiB)."""
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - t0
    err = p.stderr.read().decode()
    p.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"bench_rtsim: {' '.join(cmd)} failed: {err.strip()}")
    return wall, usage.ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=os.path.join(ROOT, "..", "shared", "scenes", "spd", "balls-4.nff"))
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--mesh", type=int, default=4)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--growth", default="1,2,3,4,5,6,7,8", help="mesh sizes for the growth table ('' to skip)")
    ap.add_argument("--growth-runs", type=int, default=3)
    ap.add_argument("--doc", action="store_true")
    a = ap.parse_args()
    build = os.path.join(ROOT, "build")
    tmp = tempfile.mkdtemp()
    report = os.path.join(tmp, "r.json")

    def rtsim(n):
        return [os.path.join(build, "rtsim"), "--scene", a.scene, "--size", a.size, "--mesh", str(n), "--no-baseline",
                "-q", "--image", os.path.join(tmp, "s.png"), "--report", report]

    rtref = [os.path.join(build, "rtref"), a.scene, "--size", a.size, "-o", os.path.join(tmp, "r.png")]
    sim, ref, ratios, mem = [], [], [], []
    for i in range(a.runs):
        ws, ms = timed(rtsim(a.mesh))
        wr, _ = timed(rtref)
        sim.append(ws)
        ref.append(wr)
        ratios.append(ws / wr)
        mem.append(ms)
        print(f"run {i + 1}: rtsim {ws:.3f} s, rtref {wr:.3f} s, ratio {ws / wr:.2f}", file=sys.stderr)
    with open(report) as f:
        r = json.load(f)
    msgs = sum(r["totals"]["messages"].values())
    same = open(os.path.join(tmp, "s.png"), "rb").read() == open(os.path.join(tmp, "r.png"), "rb").read()
    name = os.path.splitext(os.path.basename(a.scene))[0]
    rows = [
        ("scene", f"{name} at {a.size}, N = {a.mesh} ({a.mesh ** 3} nodes), default costs and links"),
        (f"rtsim wall, median of {a.runs}", f"{statistics.median(sim):.3f} s"),
        (f"rtref wall, median of {a.runs}", f"{statistics.median(ref):.3f} s"),
        ("rtsim / rtref, median of per-run ratios", f"{statistics.median(ratios):.2f}"),
        ("messages (ray / contributions / credit)",
         " / ".join(f"{r['totals']['messages'][k]:,}" for k in ("ray", "contributions", "credit"))),
        ("messages per wall second (median run)", f"{msgs / statistics.median(sim):,.0f}"),
        ("rtsim peak memory (max over runs)", f"{max(mem):.0f} MiB"),
        ("simulated render time", f"{r['render_time_ns'] / 1e6:.3f} ms"),
        ("image identical to rtref's", "yes" if same else "NO"),
        ("machine", machine()),
    ]
    table = "| quantity | value |\n|---|---|\n" + "".join(f"| {k} | {v} |\n" for k, v in rows)
    growth = ""
    if a.growth:
        growth = ("\n| N | nodes | rtsim wall (median of %d) | peak memory | ray messages | render time |\n"
                  "|---:|---:|---:|---:|---:|---:|\n" % a.growth_runs)
        for n in [int(x) for x in a.growth.split(",")]:
            walls, mems = [], []
            for _ in range(a.growth_runs):
                w, m = timed(rtsim(n))
                walls.append(w)
                mems.append(m)
            with open(report) as f:
                g = json.load(f)
            growth += (f"| {n} | {n ** 3} | {statistics.median(walls):.3f} s | {max(mems):.0f} MiB | "
                       f"{g['totals']['messages']['ray']:,} | {g['render_time_ns'] / 1e6:.3f} ms |\n")
            print(f"N={n}: {statistics.median(walls):.3f} s", file=sys.stderr)
    print(table + growth, end="")
    if a.doc:
        os.makedirs(os.path.join(ROOT, "doc", "benchmarks"), exist_ok=True)
        with open(os.path.join(ROOT, "doc", "benchmarks", "rtsim.md"), "w") as f:
            f.write("# rtsim benchmark\n\nWritten by `scripts/bench_rtsim.py --doc`; do not edit by hand.\n\n"
                    + table + "\nWall time against mesh size (same scene and costs):\n" + growth)


if __name__ == "__main__":
    main()
