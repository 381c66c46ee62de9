#!/usr/bin/python3
"""Where rtsim's time goes against rtref's (issue 64: the exact mode at
most 1.5 x rtref): both programs on the same job (default balls-4 at
512x512, N = 4), each under perf, alternated; their samples split into the
tracing both do and the rest; and the cut the target needs in rtsim's
rest. Prints the table; with --doc writes it into doc/exploration.md
("time against rtref"). Run with /usr/bin/python3."""
import argparse
import json
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
import bench_scaling  # noqa: E402
from bench_rtref import machine  # noqa: E402
from project import BUILD, ROOT, RTREF, RTSIM, spd_scene, update_doc_section, version  # noqa: E402

# Issue 64's: the exact mode at most this many times rtref's wall time.
TARGET_EXACT = 1.5


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=spd_scene("balls-4"))
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--mesh", type=int, default=4)
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--doc", action="store_true", help="write the table into doc/exploration.md")
    a = ap.parse_args()
    outputs.image_size(a.size)
    outputs.check_input(a.scene, "--scene")
    if a.runs < 1 or a.mesh < 1:
        raise outputs.ToolError(f"--runs {a.runs}, --mesh {a.mesh}: at least 1 each")
    if a.doc:
        outputs.check_output(os.path.join(ROOT, "doc", "exploration.md"), "--doc", doc=True)
    bench_scaling.build("setup.sh", "bench")  # perf
    bench_scaling.build("build.sh", "rtsim", "rtref")
    a.version = version()
    with tempfile.TemporaryDirectory() as tmp:
        split_against_rtref(a, tmp)


def split_against_rtref(a, tmp):
    """Where rtsim's time goes against rtref's, on the benchmark's job in
    the exact mode: each program run --runs times under `perf record`,
    alternated, in the plain Release build (whose profile keeps the
    region's trace a function of its own), its samples split as
    bench_scaling.py splits them: the tracing (the grid walk, intersection
    tests, shading: work both programs do) and the rest (for rtsim the
    messages, links, frame buffer, the nodes' loops and the kernel; for
    rtref the scene's parse and the PNG). From the medians, what issue 64's
    target (rtsim at most 1.5 x rtref) leaves the rest of rtsim, and the
    cut that needs. Into doc/exploration.md's "time against rtref"
    section with --doc."""
    report = os.path.join(tmp, "r.json")
    sim_cmd = [RTSIM, "--scene", a.scene, "--size", a.size, "--mesh", str(a.mesh), "--no-baseline", "-q",
               "--image", "", "--report", report]
    ref_stats = os.path.join(tmp, "split.json")
    ref_cmd = [RTREF, a.scene, "--size", a.size, "-o", os.path.join(tmp, "split.png"), "--stats", ref_stats]
    sim, ref = [], []
    for i in range(a.runs):
        for name, cmd, into in (("rtref", ref_cmd, ref), ("rtsim", sim_cmd, sim)) if i % 2 else \
                (("rtsim", sim_cmd, sim), ("rtref", ref_cmd, ref)):
            into.append(bench_scaling.profiled(cmd, tmp))
            print(f"split, {name}, run {i + 1}: tracing {into[-1][0]:.2f} s, the rest {into[-1][1]:.2f} s",
                  file=sys.stderr)
    with open(report) as f:
        r = json.load(f)
    with open(ref_stats) as f:
        st = json.load(f)
    _, tests, messages = bench_scaling.events(r)
    counts = {"messages": messages, "tests": tests, "ref_tests": st["intersection_tests"], "ref_grid": st["accelerator"]}
    text = split_text(a, [statistics.median(x) for x in zip(*sim)], [statistics.median(x) for x in zip(*ref)],
                      counts, bench_scaling.PERF_HZ)
    print(text)
    if a.doc:
        update_doc_section(os.path.join(ROOT, "doc", "exploration.md"), "time against rtref", text)


def split_text(a, sim, ref, counts, hz, target=TARGET_EXACT):
    """The split's table and what the target leaves the rest of rtsim:
    `sim` and `ref` are (tracing, rest) in seconds of samples; `counts`
    rtsim's messages and intersection tests, rtref's tests and grid."""
    messages = counts["messages"]
    job = f"{os.path.splitext(os.path.basename(a.scene))[0]} at {a.size}, N = {a.mesh}"
    allowed = target * sum(ref) - sim[0]  # what rtsim's rest may take at the target
    rows = ["| program | tracing | the rest | whole run | against rtref's whole run |", "|---|---:|---:|---:|---:|",
            f"| rtref | {ref[0]:.2f} s | {ref[1]:.2f} s | {sum(ref):.2f} s | 1.00 |",
            f"| rtsim, exact | {sim[0]:.2f} s | {sim[1]:.2f} s | {sum(sim):.2f} s | {sum(sim) / sum(ref):.2f} |",
            "",
            f"{job}; medians of {a.runs} runs of each under `perf record` ({hz} samples a second, "
            f"alternated), the plain Release build; {machine(BUILD)}; {a.version}. rtsim's tracing takes "
            f"{sim[0] / ref[0]:.2f} of rtref's: its boxes' grids are finer than rtref's one grid "
            f"({counts['ref_grid']}), and it makes {counts['tests'] / 1e6:.1f} M intersection tests where rtref "
            f"makes {counts['ref_tests'] / 1e6:.1f} M. The rest is {messages:,} messages' handling, {1e9 * sim[1] / messages:.0f} ns a "
            f"message. At the target, {target} x rtref's whole run, rtsim's rest could take at most "
            f"{max(allowed, 0):.2f} s: " +
            (f"{1 - allowed / sim[1]:.0%} less than now." if 0 < allowed < sim[1] else
             "as now or more (met)." if allowed >= sim[1] else "nothing: its tracing alone is over the target.")]
    return "\n".join(rows)


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_split.py", main))
