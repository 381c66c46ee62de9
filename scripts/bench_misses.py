#!/usr/bin/python3
"""Cache-miss benchmark: what a message costs rtsim in instructions and
cache misses as the mesh grows, counted, not timed. Each point runs rtsim
once under valgrind's callgrind with a simulated cache (the same sizes on
any host: 32 KiB instruction and 48 KiB data first level, --ll MiB last
level) and counts only the simulation's evaluation phases (SystemC's
crunch: every process's work, the links, the kernel's evaluation; not the
start-up, the report or the timed-event heap's pops between phases). The
frame's start and end inside those phases (each node finding its links,
each process ended) cost per node, not per message: at 32x32x32 and
128x128 they were 40 % of the last-level misses. So each N also runs an
idle mesh (one sphere at 8x8, whose links carry nothing), and its counts
are taken off. Per message (all work included: the tracing too) it
reports instructions, first-level data misses and last-level misses, and
each against N = 4's.

Why: this VM's wall times swing by up to 60 % between identical runs (a
32x32x32 frame took 11.2 s and 19.7 s minutes apart), so a change to the
message path worth 5 % cannot be told from noise by timing. The counts
repeat (two runs of one build at 32x32x32 differed by 0.03 % in
instructions, 0.2 % in first-level and 0.7 % in last-level misses: the
host's clock reads, such as the watchdog's, and where the system maps
memory), so --against BINARY compares two builds to within that. They
are a model of a cache, not this CPU's: they say where misses come from
and whether a change removes some, not what a miss costs (bench_memory.py
times one; bench_scaling.py times whole runs).

Prints the table; with --doc writes doc/benchmarks/misses.md (without it,
nothing is written). Run with /usr/bin/python3."""
import argparse
import concurrent.futures
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from bench_scaling import build, paper_scene  # noqa: E402
from project import ROOT, RTSIM, spd_scene, version  # noqa: E402

EVENTS = ("Ir", "D1mr", "D1mw", "ILmr", "DLmr", "DLmw")
# Only inside the kernel's evaluation phases (sc_simcontext::crunch).
COLLECT = "sc_core::sc_simcontext::crunch(bool)"


def callgrind_totals(text):
    """The totals of a callgrind output file: {event: count} for the
    events line's names, from its `totals:` line (or `summary:`)."""
    names, values = None, None
    for line in text.splitlines():
        if line.startswith("events:"):
            names = line.split()[1:]
        elif line.startswith(("totals:", "summary:")) and values is None:
            values = [int(v) for v in line.split()[1:]]
    if not names or values is None:
        raise outputs.ToolError("callgrind's output has no events or totals line", outputs.FAILED)
    counts = dict(zip(names, values + [0] * (len(names) - len(values))))
    missing = [e for e in EVENTS if e not in counts]
    if missing:
        raise outputs.ToolError(f"callgrind's output lacks {', '.join(missing)} (no cache simulation?)", outputs.FAILED)
    return counts


def per_message(counts, messages):
    """Instructions, first-level data misses and last-level misses per message."""
    return (counts["Ir"] / messages, (counts["D1mr"] + counts["D1mw"]) / messages,
            (counts["ILmr"] + counts["DLmr"] + counts["DLmw"]) / messages)


def scene_flags(scene, size):
    return paper_scene(size) if scene == "paper" else ["--scene", spd_scene(scene), "--size", size]


IDLE = ["--spheres", "1", "--size", "8x8"]  # the built-in scene: a mesh that starts and ends a frame, and no more


def less_idle(run, idle):
    """A run's counts less an idle mesh's (the per-node start and end)."""
    return {e: run[e] - idle.get(e, 0) for e in run}


def counted(binary, flags, n, ll_mib, tmp, tag):
    """One run under callgrind: (counts, messages, the build's version)."""
    out, report = os.path.join(tmp, f"cg.{tag}"), os.path.join(tmp, f"r.{tag}.json")
    cmd = ["valgrind", "--tool=callgrind", "--cache-sim=yes", "--I1=32768,8,64", "--D1=49152,12,64",
           f"--LL={ll_mib * 1024 * 1024},16,64", f"--toggle-collect={COLLECT}", f"--callgrind-out-file={out}",
           binary] + flags + ["--mesh", str(n), "--no-baseline", "-q", "--image", "", "--report", report]
    p = outputs.run_child(cmd)
    if p.returncode != 0:
        raise outputs.ToolError(f"{os.path.basename(binary)} at N = {n} under callgrind: exit {p.returncode}: "
                                f"{p.stderr.strip()[-300:]}", outputs.FAILED)
    with open(out) as f:
        counts = callgrind_totals(f.read())
    with open(report) as f:
        r = json.load(f)
    return counts, sum(r["totals"]["messages"].values()), r["rerun"]["version"]


def table(builds, ns, got, versions, a, ver):
    """got: (build, N) -> (counts less the idle mesh's, messages, the idle mesh's counts)."""
    lines = ["| build | N | messages | instructions per message | L1 data misses per message | "
             "last-level misses per message | last-level misses / N = 4's | the idle mesh's last-level misses |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for name, _ in builds:
        base = per_message(*got[(name, 4)][:2]) if (name, 4) in got else None
        for n in ns:
            counts, msgs, idle = got[(name, n)]
            ir, d1, ll = per_message(counts, msgs)
            rel = f"{ll / base[2]:.2f}" if base and base[2] > 0 else "-"
            lines.append(f"| {name} ({versions[name]}) | {n} | {msgs:,} | {ir:,.0f} | {d1:.1f} | {ll:.2f} | "
                         f"{rel} | {idle['ILmr'] + idle['DLmr'] + idle['DLmw']:,} |")
    lines += ["", f"{a.scene} at {a.size}, exact mode, `--no-baseline`; callgrind's cache model: 32 KiB 8-way "
              f"instructions, 48 KiB 12-way data, {a.ll} MiB 16-way last level, 64-byte lines; counted inside "
              f"`{COLLECT}` only, less an idle mesh's of the same N (`{' '.join(IDLE)}`, whose count is the last "
              f"column); one run per point (the counts repeat); {ver}."]
    return "\n".join(lines) + "\n"


def check_arguments(a):
    outputs.image_size(a.size)
    ns = outputs.numbers(a.n, "--n", least=1, most=64)
    if a.ll < 1:
        raise outputs.ToolError(f"--ll {a.ll}: at least 1 (MiB)")
    if a.jobs < 1:
        raise outputs.ToolError(f"--jobs {a.jobs}: at least 1")
    if a.scene != "paper":
        outputs.check_input(spd_scene(outputs.check_name(a.scene, "--scene")), "--scene")
    for flag, path in (("--rtsim", a.rtsim), ("--against", a.against)):
        if path:
            outputs.check_input(path, flag)
    if a.doc:
        outputs.check_output(os.path.join(ROOT, "doc", "benchmarks", "misses.md"), "--doc", doc=True)
    return ns


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    outputs.one_line_errors(ap)
    ap.add_argument("--n", default="4,8,16,24,32", help="mesh sizes N (N x N x N)")
    ap.add_argument("--size", default="128x128")
    ap.add_argument("--scene", default="balls-5", help="an SPD scene's name, or 'paper'")
    # 4 MiB: the cache one process gets on this VM ends between 4 and 8
    # (bench_memory.py, doc/benchmarks/memory.md), not at the 32 MiB its
    # processor reports, shared with the host's other guests: with 32 a
    # message at N = 32 counted a tenth of the misses it has here
    # (doc/history.md, "At 32x32x32").
    ap.add_argument("--ll", type=int, default=4, help="the simulated last-level cache, MiB")
    ap.add_argument("--rtsim", default=RTSIM, help="the build to count (default: scripts/build.sh's)")
    ap.add_argument("--against", default="", help="another rtsim binary (the build before), counted alike; "
                    "the table names each build's version, as its report gives it")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once (counts do not depend on it)")
    ap.add_argument("--doc", action="store_true", help="write doc/benchmarks/misses.md")
    a = ap.parse_args(argv)
    ns = check_arguments(a)
    build("setup.sh", "bench")  # valgrind
    if a.rtsim == RTSIM:
        build("build.sh", "rtsim")
    builds = [("this", os.path.abspath(a.rtsim))] + ([("against", os.path.abspath(a.against))] if a.against else [])
    flags = scene_flags(a.scene, a.size)
    raw = {}
    with tempfile.TemporaryDirectory() as tmp, concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        jobs = {pool.submit(counted, binary, scene, n, a.ll, tmp, f"{name}.{n}.{kind}"): (name, n, kind)
                for n in reversed(ns) for name, binary in builds for kind, scene in (("run", flags), ("idle", IDLE))}
        for job in concurrent.futures.as_completed(jobs):
            raw[jobs[job]] = job.result()
            print(f"{' '.join(map(str, jobs[job]))}: counted", file=sys.stderr)
    got, versions = {}, {}
    for name, _ in builds:
        for n in ns:
            (run, msgs, versions[name]), idle = raw[(name, n, "run")], raw[(name, n, "idle")][0]
            got[(name, n)] = (less_idle(run, idle), msgs, idle)
            ir, d1, ll = per_message(got[(name, n)][0], msgs)
            print(f"{name}, N = {n}: {ir:,.0f} instructions, {d1:.1f} L1 and {ll:.2f} last-level misses a message",
                  file=sys.stderr)
    text = table(builds, ns, got, versions, a, version())
    print(text)
    if a.doc:
        outputs.write_text(os.path.join(ROOT, "doc", "benchmarks", "misses.md"),
                           "# What a message costs in instructions and cache misses\n\nWritten by "
                           "`scripts/bench_misses.py --doc`; do not edit by hand.\n\n" + text)


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_misses.py", main))
