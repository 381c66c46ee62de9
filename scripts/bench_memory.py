#!/usr/bin/python3
"""Memory benchmark: what one load costs this machine as the memory it
reaches grows, on huge and on small pages, and what a fresh page costs to
touch. bench_misses.py counts a message's cache misses in a model of a
cache; these are what a miss costs here, and how much cache this machine
gives one process in fact (the last-level cache a VM's processor reports
is shared with whatever else runs on the host). bench_scaling.py's wall
per message at 32x32x32, where each message lands on state far from the
last, is these figures times the misses.

Runs build/memory_probe (tb/memory_probe.cpp: a chase through one random
cycle of a region's 64-byte lines, so that each load waits for the one
before), every run pinned to one CPU, huge and small pages alternated,
--runs runs of each; medians, and the spread. Prints the table; with --doc
writes doc/benchmarks/memory.md. Run with /usr/bin/python3."""
import argparse
import json
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from bench_rtref import add_cpu_option, machine, pin_to_cpu  # noqa: E402
from bench_scaling import build  # noqa: E402
from project import ROOT, version  # noqa: E402

PROBE = os.path.join(ROOT, "build", "memory_probe")
PAGES = ("huge", "small")
DOC = os.path.join(ROOT, "doc", "benchmarks", "memory.md")


def probe(mibs, pages, loads):
    """One run of the probe: {mib: (ns per load, ms per MiB to touch)}."""
    # (each size as Python writes it back exactly: the probe's JSON gives the
    # same double back, the key of its row)
    p = outputs.run_child([PROBE, "--mib", ",".join(repr(m) for m in mibs), "--pages", pages, "--loads", str(loads)])
    if p.returncode:
        raise outputs.ToolError(f"memory_probe --pages {pages}: exit {p.returncode}: "
                                f"{(p.stderr.strip().splitlines() or ['no message'])[-1]}", outputs.FAILED)
    got = {}
    for line in p.stdout.splitlines():
        r = json.loads(line)
        got[r["mib"]] = (r["ns_per_load"], r["touch_ms_per_mib"])
    return got


def spread(values, fmt):
    return f"{fmt.format(min(values))} .. {fmt.format(max(values))}"


def cache_ends(mibs, load):
    """Where the cache one process gets runs out: the two neighbouring
    sizes whose loads are furthest apart (the largest ratio), as (the
    last size inside, the first past it). The levels before the last one
    step up by less (a first-level load to a second-level one about 2
    times on this VM, the last level to memory 4 times)."""
    steps = [(load[b] / load[a], a, b) for a, b in zip(mibs, mibs[1:])]
    _, inside, past = max(steps)
    return inside, past


def table(mibs, runs, a, pinned):
    med = {(m, p): (statistics.median(r[m][0] for r in runs[p]), statistics.median(r[m][1] for r in runs[p]))
           for m in mibs for p in PAGES}
    lines = ["| region (MiB) | a load, huge pages (ns) | spread | a load, small pages (ns) | spread | "
             "first touch, huge pages (ms per MiB) | small pages | spread, huge |",
             "|---:|---:|---|---:|---|---:|---:|---|"]
    for m in mibs:
        h, s = [r[m] for r in runs["huge"]], [r[m] for r in runs["small"]]
        lines.append(f"| {m:g} | {med[(m, 'huge')][0]:.0f} | {spread([x[0] for x in h], '{:.0f}')} | "
                     f"{med[(m, 'small')][0]:.0f} | {spread([x[0] for x in s], '{:.0f}')} | "
                     f"{med[(m, 'huge')][1]:.2f} | {med[(m, 'small')][1]:.2f} | {spread([x[1] for x in h], '{:.2f}')} |")
    inside, past = cache_ends(mibs, {m: med[(m, "huge")][0] for m in mibs})
    where = (f"The cache one process gets here ends between {inside:g} and {past:g} MiB (the largest step "
             f"between two sizes, on huge pages): a load within {inside:g} MiB takes "
             f"{med[(inside, 'huge')][0]:.0f} ns, one spread over {past:g} MiB {med[(past, 'huge')][0]:.0f} ns, "
             f"and over {mibs[-1]:g} MiB {med[(mibs[-1], 'huge')][0]:.0f} ns on huge pages, "
             f"{med[(mibs[-1], 'small')][0]:.0f} ns on small ones.")
    lines += ["", where, "",
              f"{a.runs} runs of each, huge and small pages alternated; medians and min .. max; "
              f"{a.loads:,} loads timed per region after one pass through it; "
              f"{'every run pinned to CPU ' + str(pinned) if pinned is not None else 'not pinned'}; "
              f"{machine(os.path.join(ROOT, 'build'))}; {version()}."]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    outputs.one_line_errors(ap)
    ap.add_argument("--mib", default="0.25,0.5,1,2,4,8,16,32,64,256,1024", help="region sizes, MiB")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--loads", type=int, default=20_000_000, help="loads timed per region")
    add_cpu_option(ap)
    ap.add_argument("--doc", action="store_true", help="write doc/benchmarks/memory.md")
    a = ap.parse_args(argv)
    mibs = sorted(set(outputs.numbers(a.mib, "--mib", kind=float, least=0.0625, most=65536)))
    if len(mibs) < 2:
        raise outputs.ToolError(f"--mib {a.mib}: at least two sizes (where the cache ends lies between them)")
    if a.runs < 1:
        raise outputs.ToolError(f"--runs {a.runs}: at least 1")
    if a.loads < 1000:
        raise outputs.ToolError(f"--loads {a.loads}: at least 1000")
    if a.doc:
        outputs.check_output(DOC, "--doc", doc=True)
    pinned = pin_to_cpu(a.cpu, "bench_memory.py")
    build("build.sh", "memory_probe")
    runs = {p: [] for p in PAGES}
    for k in range(a.runs):
        for p in PAGES if k % 2 == 0 else reversed(PAGES):
            runs[p].append(probe(mibs, p, a.loads))
            print(f"run {k + 1}, {p} pages: done", file=sys.stderr)
    text = table(mibs, runs, a, pinned)
    print(text)
    if a.doc:
        outputs.write_text(DOC, "# What a load and a fresh page cost this machine\n\nWritten by "
                           "`scripts/bench_memory.py --doc`; do not edit by hand.\n\n" + text)


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_memory.py", main))
