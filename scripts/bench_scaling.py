#!/usr/bin/python3
"""Scaling benchmark: how rtsim's cost grows with the mesh, N x N x N for
N = 2, 4, 8, 16, 24, 32, on balls-5 at 1024x1024 and on the paper's scene
(1,000 spheres crowded into a quarter of x) at 1024x1024, exact mode, no
balancing, no baseline runs. Per N: wall time and peak memory (medians of
--runs runs, the N alternated ascending and descending, every run pinned
to one CPU), the start-up (the process's wall time to the first simulated
event, the report's wall_startup_s) and the wall time per modelled event.
The modelled events are the nodes' ray steps (a ray traced through a box,
or passed on through it untraced), their intersection tests and every
message (rays, contributions, credit). At the largest N the image is
compared with rtref's. Memory per node: the run's peak over its nodes,
and an idle mesh's (one sphere at 8x8, one run per N: what a node costs
for existing, its module, links and ports), each less the peak of the
idle 1x1x1 mesh (the process itself).

Where the time per event goes: at every N, one more run of each scene
under `perf record` (sampled, not timed; in the plain
Release build of scripts/build.sh, whose profile keeps the region's trace
apart from the node's step, which the profile-guided build inlines it
into) splits the simulation's time into the tracing (the grid walk,
intersection tests and shading: TRACING below) and the rest (messages,
links, the nodes' loops, the SystemC kernel), each over its own events:
tracing per ray step or test, the rest per message, each against
N = 4's (issue 64's per-kind targets, per N; charted). From them, the wall
time per event that the largest mesh would have if every kind of event
cost what it does at N = 4: the ratio the mix of events alone sets,
against which issue 45's 1.3 is to be read; and issue 64's targets (per
message and per step or test at most 1.5 x N = 4's; balls-5 at N = 32 in
at most 60 s and 1.5 GiB). Prints tables; with --doc writes
doc/benchmarks/scaling.md and scaling.png (without it, nothing is written).
Run with /usr/bin/python3."""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from bench_rtref import add_cpu_option, build_fast, machine, pin_to_cpu  # noqa: E402
from bench_rtsim import timed  # noqa: E402
from project import FAST_BUILD, PAPER_SCENE, ROOT, RTSIM, spd_scene, version  # noqa: E402

# Issue 45's targets, checked in the table's last lines.
TARGET_WALL_S, TARGET_MEM_MIB = 150.0, 3 * 1024
TARGET_PER_EVENT, TARGET_STARTUP = 1.3, 0.10
# Issue 64's, after the split table: each kind of event at N = 32 against
# N = 4, and balls-5's wall and peak memory at N = 32.
TARGET_PER_KIND, TARGET64_WALL_S, TARGET64_MEM_MIB = 1.5, 60.0, 1.5 * 1024

# The tracing's functions in a profile (perf's symbols): the per-sample work
# that rtref does too. Everything else in the process is the machine's.
TRACING = re.compile(r"UniformGrid::closestHit|Lattice::locate|Region::trace|Shader::|"
                     r"(Sphere|Polygon|Cone|Shape|BruteForce)::(intersect|closestHit)")
PERF_HZ = 999


def paper_scene(size):
    """The paper's scene (project.PAPER_SCENE) at f = 1/4, at `size`."""
    flags = list(PAPER_SCENE)
    flags[flags.index("--size") + 1] = size
    return flags + ["--concentration", "0.25"]


def events(r):
    """The report's modelled events: (ray steps, intersection tests, messages)."""
    steps = sum(n["rays_traced"] + n["rays_passed"] for n in r["nodes"])
    tests = sum(n["counters"]["intersection_tests"] for n in r["nodes"])
    return steps, tests, sum(r["totals"]["messages"].values())


def split_samples(lines):
    """Samples per symbol from `perf report --stdio -n --sort symbol` lines:
    (tracing, the rest), as counts."""
    tracing = rest = 0
    for line in lines:
        m = re.match(r"\s*[\d.]+%\s+(\d+)\s+\[[.k]\]\s+(.*)", line)
        if not m:
            continue
        if TRACING.search(m.group(2)):
            tracing += int(m.group(1))
        else:
            rest += int(m.group(1))
    return tracing, rest


def kind_costs(tracing_s, rest_s, startup_s, events):
    """Seconds per event of each kind: tracing per ray step or test, the
    rest (start-up aside) per message."""
    steps, tests, msgs = events
    return tracing_s / (steps + tests), (rest_s - startup_s) / msgs


def per_event_at(costs, events):
    """Seconds per event with these costs of each kind (kind_costs)."""
    steps, tests, msgs = events
    return (costs[0] * (steps + tests) + costs[1] * msgs) / sum(events)


def mix_ratio(costs4, events4, events_n):
    """The wall time per event at events_n, over N = 4's, if each kind of
    event cost what it does at N = 4 (costs4: kind_costs), start-up aside."""
    return per_event_at(costs4, events_n) / per_event_at(costs4, events4)


def profiled(cmd, tmp):
    """Runs cmd under perf record; returns (tracing, rest) in seconds of samples."""
    data = os.path.join(tmp, "perf.data")
    checked(["perf", "record", "-q", "-F", str(PERF_HZ), "-o", data, "--"] + cmd)
    out = checked(["perf", "report", "-i", data, "--no-children", "--sort", "symbol", "--stdio", "-n"]).stdout
    tracing, rest = split_samples(out.splitlines())
    return tracing / PERF_HZ, rest / PERF_HZ


def checked(cmd):
    """Runs cmd (ended by a stop of this script); its result, or one line
    and exit 1 if it failed."""
    p = outputs.run_child(cmd)
    if p.returncode != 0:
        raise outputs.ToolError(f"{' '.join(cmd[:3])} ... exit {p.returncode}: {p.stderr.strip()[-300:]}",
                                outputs.FAILED)
    return p


def check_arguments(a):
    """The mesh sizes, the scenes and the doc pages, before any work; the N."""
    outputs.image_size(a.size)
    try:
        ns = [int(x) for x in a.n.split(",")]
    except ValueError:
        raise outputs.ToolError(f"--n {a.n}: not a list of whole numbers")
    if a.runs < 1 or min(ns) < 1:
        raise outputs.ToolError(f"--runs {a.runs}, --n {a.n}: at least 1 each")
    for scene in a.scenes.split(","):
        if scene != "paper":
            outputs.check_input(spd_scene(outputs.check_name(scene, "--scenes")), "--scenes")
    if a.doc:
        for name in ("scaling.md", "scaling.png"):
            outputs.check_output(os.path.join(ROOT, "doc", "benchmarks", name), "--doc", doc=True)
    return ns


def build(script, *args):
    if subprocess.run(["bash", os.path.join(ROOT, "scripts", script), *args], stdout=subprocess.DEVNULL).returncode:
        raise outputs.ToolError(f"{script} failed (its messages above)", outputs.FAILED)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="2,4,8,16,24,32", help="mesh sizes N (N x N x N)")
    ap.add_argument("--size", default="1024x1024")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--scenes", default="balls-5,paper", help="SPD scene names, or 'paper'")
    add_cpu_option(ap)
    ap.add_argument("--doc", action="store_true",
                    help="write doc/benchmarks/scaling.md and scaling.png (without it: the tables to stdout only)")
    a = ap.parse_args()
    ns = check_arguments(a)
    build_fast()
    build("setup.sh", "bench")  # perf
    # The split's runs: the plain build, whose profile keeps the region's
    # trace a function of its own (the profile-guided build inlines it into
    # the node's step, with the message handling).
    build("build.sh", "rtsim")
    pin = pin_to_cpu(a.cpu, "bench_scaling")
    ver = version()
    with tempfile.TemporaryDirectory() as tmp:
        measure(a, ns, pin, ver, tmp)


def measure(a, ns, pin, ver, tmp):
    """The runs, the tables and, with --doc, the page and its chart; in the
    temporary folder `tmp`."""
    report = os.path.join(tmp, "r.json")
    rtsim = os.path.join(FAST_BUILD, "rtsim")

    def command(scene, n, image="", binary=rtsim):
        flags = paper_scene(a.size) if scene == "paper" else ["--scene", spd_scene(scene), "--size", a.size]
        return [binary] + flags + ["--mesh", str(n), "--no-baseline", "-q", "--image", image, "--report", report]

    rows = {}  # (scene, n) -> dict
    for scene in a.scenes.split(","):
        for run in range(a.runs):
            for n in (ns if run % 2 == 0 else list(reversed(ns))):
                wall, mem = timed(command(scene, n))
                with open(report) as f:
                    r = json.load(f)
                row = rows.setdefault((scene, n), {"wall": [], "mem": [], "startup": [], "report": None})
                row["wall"].append(wall)
                row["mem"].append(mem)
                row["startup"].append(r["wall_startup_s"])
                row["report"] = {"events": events(r), "render_ns": r["render_time_ns"]}
                print(f"{scene}, N = {n}, run {run + 1}: {wall:.2f} s, {mem:.0f} MiB, start-up "
                      f"{r['wall_startup_s']:.2f} s", file=sys.stderr)
    idle = {}  # n -> peak MiB of an idle mesh (a node's cost for existing; 1: the process itself)
    for n in [1] + ns:
        _, idle[n] = timed([rtsim, "--spheres", "1", "--size", "8x8", "--mesh", str(n), "--no-baseline", "-q",
                            "--image", ""])
        print(f"idle mesh, N = {n}: {idle[n]:.0f} MiB", file=sys.stderr)
    split = {}  # (scene, n) -> (tracing s, rest s, start-up s, events), from one run under perf
    for scene in a.scenes.split(","):
        for n in ns if 4 in ns else []:
            tracing, rest = profiled(command(scene, n, binary=RTSIM), tmp)
            with open(report) as f:
                r = json.load(f)
            split[(scene, n)] = (tracing, rest, r["wall_startup_s"], events(r))
            print(f"{scene}, N = {n}, under perf: tracing {tracing:.2f} s, the rest {rest:.2f} s", file=sys.stderr)
    same = {}
    for scene in a.scenes.split(","):  # the largest mesh's image against rtref's
        ours, ref = os.path.join(tmp, "ours.png"), os.path.join(tmp, "ref.png")
        checked(command(scene, ns[-1], ours))
        flags = paper_scene(a.size) if scene == "paper" else [spd_scene(scene), "--size", a.size]
        checked([os.path.join(FAST_BUILD, "rtref")] + flags + ["-o", ref])
        with open(ours, "rb") as f, open(ref, "rb") as g:
            same[scene] = f.read() == g.read()
    text = table(a, ns, rows, idle, same, pin, ver) + split_table(a, ns, rows, split)
    print(text)
    if a.doc:
        out = os.path.join(ROOT, "doc", "benchmarks")
        outputs.write_text(os.path.join(out, "scaling.md"),
                           "# How rtsim scales with the mesh\n\nWritten by `scripts/bench_scaling.py --doc`; do not "
                           "edit by hand.\n\n" + image_link("scaling.png") + "\n\n" + text)
        chart(a, ns, rows, idle, split, os.path.join(out, "scaling.png"))


def image_link(name):
    """The chart's markdown link, beside the page in doc/benchmarks/."""
    return "![wall time per event and memory against N](" + name + ")"


def per_event(row):
    return statistics.median(row["wall"]) / sum(row["report"]["events"]) * 1e9


def per_message(row):
    """The wall time per message, all work included (start-up, tracing,
    report): issue 64's first target reads it against N = 4's."""
    return statistics.median(row["wall"]) / row["report"]["events"][2] * 1e9


def kib_per_node(mib, n, idle):
    """Peak memory per node, the process's own (the idle 1x1x1 mesh's) taken
    out; 0 where the peak is below that (an idle 2x2x2 mesh's peak, one run,
    came out 0.15 MiB under it: the pages' noise, not memory a node gives back)."""
    return max(0.0, (mib - idle[1]) * 1024 / n ** 3)


def table(a, ns, rows, idle, same, pin, ver):
    lines = ["| scene | N | nodes | wall (median) | start-up (median) | start-up share | peak memory (max) | "
             "per node: this run / idle mesh (less the process's own) | ray steps | intersection tests | messages | wall per event | "
             "per event / N = 4's | wall per message | per message / N = 4's |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for scene in a.scenes.split(","):
        base = rows.get((scene, 4))
        for n in ns:
            row = rows[(scene, n)]
            w, s = statistics.median(row["wall"]), statistics.median(row["startup"])
            steps, tests, msgs = row["report"]["events"]
            rel = f"{per_event(row) / per_event(base):.2f}" if base else "-"
            rel_msg = f"{per_message(row) / per_message(base):.2f}" if base else "-"
            lines.append(f"| {scene} | {n} | {n ** 3:,} | {w:.2f} s | {s:.2f} s | {s / w * 100:.1f} % | "
                         f"{max(row['mem']):.0f} MiB | {kib_per_node(max(row['mem']), n, idle):.1f} / "
                         f"{kib_per_node(idle[n], n, idle):.1f} KiB | {steps:,} | {tests:,} | {msgs:,} | {per_event(row):.0f} ns | "
                         f"{rel} | {per_message(row):.0f} ns | {rel_msg} |")
    top = ns[-1]
    lines += ["", f"Against issue 45's targets (N = {top}):", "",
              "| target | measured | met |", "|---|---|---|"]
    for scene in a.scenes.split(","):
        row, base = rows[(scene, top)], rows.get((scene, 4))
        w, m = statistics.median(row["wall"]), max(row["mem"])
        share = statistics.median(row["startup"]) / w
        if scene == "balls-5":
            lines.append(f"| {scene}: wall at most {TARGET_WALL_S:.0f} s | {w:.1f} s | {'yes' if w <= TARGET_WALL_S else 'NO'} |")
            lines.append(f"| {scene}: peak memory at most 3 GiB | {m:.0f} MiB | {'yes' if m <= TARGET_MEM_MIB else 'NO'} |")
        if base:
            rel = per_event(row) / per_event(base)
            lines.append(f"| {scene}: wall per event at most {TARGET_PER_EVENT} x N = 4's | {rel:.2f} x | "
                         f"{'yes' if rel <= TARGET_PER_EVENT else 'NO'} |")
        lines.append(f"| {scene}: start-up at most {TARGET_STARTUP * 100:.0f} % of the run | {share * 100:.1f} % | "
                     f"{'yes' if share <= TARGET_STARTUP else 'NO'} |")
        lines.append(f"| {scene}: image at N = {top} identical to rtref's | {'identical' if same[scene] else 'DIFFERENT'} | "
                     f"{'yes' if same[scene] else 'NO'} |")
    lines += ["", f"{a.size}, exact mode (the default), `--no-baseline`; {a.runs} runs per point, the N alternated "
              f"ascending and descending; {machine()}"
              + (f"; every run pinned to CPU {pin}" if pin is not None else "") + f"; {ver}."]
    return "\n".join(lines) + "\n"


def split_table(a, ns, rows, split):
    """Where the time per event goes, at every N profiled: each kind's cost
    and its ratio to N = 4's, and the ratio the mix of events alone sets
    (mix_ratio) at the largest N."""
    top = ns[-1]
    lines = ["", f"Where the time goes (one more run of each point under `perf record`, {PERF_HZ} samples a second, "
             "in the plain Release build, where the region's trace is a function of its own; start-up aside): the "
             "tracing (the grid walk, intersection tests, shading) per ray step or test, and the rest (messages, "
             "links, the nodes' loops, the SystemC kernel) per message, each against N = 4's:", "",
             "| scene | N | tracing | per ray step or test | / N = 4's | the rest | per message | / N = 4's | "
             "per event | per event / N = 4's |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    mixes = []
    for scene in a.scenes.split(","):
        if (scene, 4) not in split:
            continue
        t4 = split[(scene, 4)]
        c4 = kind_costs(*t4)
        base = per_event_at(c4, t4[3])
        for n, step_ratio, message_ratio in kind_ratios(scene, ns, split):
            tracing, rest, startup, ev = split[(scene, n)]
            c = kind_costs(tracing, rest, startup, ev)
            pe = per_event_at(c, ev)
            lines.append(f"| {scene} | {n} | {tracing:.2f} s | {c[0] * 1e9:.0f} ns | {step_ratio:.2f} | "
                         f"{rest - startup:.2f} s | {c[1] * 1e9:.0f} ns | {message_ratio:.2f} | {pe * 1e9:.0f} ns | "
                         f"{pe / base:.2f} |")
        mixes.append((scene, mix_ratio(c4, t4[3], split[(scene, top)][3])))
    if mixes:
        lines += ["", f"If every kind of event cost at N = {top} what it does at N = 4, the wall time per event "
                  f"would be, against N = 4's: " + "; ".join(f"{s} {m:.2f} x" for s, m in mixes)
                  + f" (the target: {TARGET_PER_EVENT} x). Messages cost more than steps and tests, and their share "
                  "of the events grows with N, so this much of the ratio comes from the mix of events alone."]
    lines += ["", f"Against issue 64's targets (N = {top}; per kind from the split above):", "",
              "| target | measured | met |", "|---|---|---|"]
    for scene in a.scenes.split(","):
        if (scene, 4) in rows and (scene, top) in rows:
            r = per_message(rows[(scene, top)]) / per_message(rows[(scene, 4)])
            lines.append(f"| {scene}: wall per message, all work included, at most {TARGET_PER_KIND} x N = 4's "
                         f"(the issue reads it at 256x256) | {r:.2f} x | {'yes' if r <= TARGET_PER_KIND else 'NO'} |")
        if (scene, 4) in split and (scene, top) in split:
            _, step_ratio, message_ratio = kind_ratios(scene, [top], split)[0]
            for r, kind in ((message_ratio, "per message"), (step_ratio, "per ray step or test")):
                lines.append(f"| {scene}: {kind} at most {TARGET_PER_KIND} x N = 4's | {r:.2f} x | "
                             f"{'yes' if r <= TARGET_PER_KIND else 'NO'} |")
        if scene == "balls-5":
            w, m = statistics.median(rows[(scene, top)]["wall"]), max(rows[(scene, top)]["mem"])
            lines.append(f"| {scene}: wall at most {TARGET64_WALL_S:.0f} s | {w:.1f} s | {'yes' if w <= TARGET64_WALL_S else 'NO'} |")
            lines.append(f"| {scene}: peak memory at most 1.5 GiB | {m:.0f} MiB | {'yes' if m <= TARGET64_MEM_MIB else 'NO'} |")
    return "\n".join(lines) + "\n"


def positive(xs, ys):
    """The points a log axis can show: a small mesh's memory less the
    process's own can round to 0 (N = 2's idle mesh, 8 nodes)."""
    kept = [(x, y) for x, y in zip(xs, ys) if y > 0]
    return [x for x, _ in kept], [y for _, y in kept]


def kind_ratios(scene, ns, split):
    """Per N profiled: (N, per step or test, per message), each over N = 4's."""
    c4 = kind_costs(*split[(scene, 4)])
    out = []
    for n in ns:
        if (scene, n) in split:
            c = kind_costs(*split[(scene, n)])
            out.append((n, c[0] / c4[0], c[1] / c4[1]))
    return out


def chart(a, ns, rows, idle, split, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx, cx, dx) = plt.subplots(1, 4, figsize=(20, 4.2))
    for scene in a.scenes.split(","):
        ax.plot(ns, [per_event(rows[(scene, n)]) for n in ns], marker="o", label=scene)
        bx.plot(ns, [max(rows[(scene, n)]["mem"]) for n in ns], marker="o", label=f"{scene}: peak memory")
        bx.plot(ns, [statistics.median(rows[(scene, n)]["startup"]) * 1000 for n in ns], marker="x", linestyle="--",
                label=f"{scene}: start-up (ms)")
    if 4 in ns:
        for scene in a.scenes.split(","):
            ax.axhline(per_event(rows[(scene, 4)]) * TARGET_PER_EVENT, color="grey", linestyle=":", linewidth=1)
    ax.set_xlabel("N (N x N x N nodes)")
    ax.set_ylabel("wall time per modelled event (ns)")
    ax.set_title(f"wall per event, {a.size} (dotted: 1.3 x N = 4's)")
    ax.set_ylim(bottom=0)
    ax.legend()
    bx.set_xlabel("N (N x N x N nodes)")
    bx.set_yscale("log")
    bx.set_ylabel("MiB / ms")
    bx.set_title("peak memory and start-up")
    bx.legend(fontsize=8)
    for scene in a.scenes.split(","):
        cx.plot(*positive(ns, [kib_per_node(max(rows[(scene, n)]["mem"]), n, idle) for n in ns]), marker="o",
                label=f"{scene}: this run")
    cx.plot(*positive(ns, [kib_per_node(idle[n], n, idle) for n in ns]), marker="x", linestyle="--", color="black",
            label="idle mesh")
    cx.set_xlabel("N (N x N x N nodes)")
    cx.set_yscale("log")
    cx.set_ylabel("KiB per node (peak less the process's, / nodes)")
    cx.set_title("memory per node")
    cx.legend(fontsize=8)
    for scene in a.scenes.split(","):
        if (scene, 4) in split:
            got = kind_ratios(scene, ns, split)
            dx.plot([g[0] for g in got], [g[2] for g in got], marker="o", label=f"{scene}: per message")
            dx.plot([g[0] for g in got], [g[1] for g in got], marker="x", linestyle="--", label=f"{scene}: per step or test")
    dx.axhline(TARGET_PER_KIND, color="grey", linestyle=":", linewidth=1)
    dx.set_xlabel("N (N x N x N nodes)")
    dx.set_ylabel("wall per event of the kind / N = 4's")
    dx.set_title(f"each kind of event (perf split; dotted: {TARGET_PER_KIND} x)")
    dx.set_ylim(bottom=0)
    dx.legend(fontsize=8)
    for x in (ax, bx, cx, dx):
        x.set_xticks(ns)
        x.grid(True, alpha=0.3)
    fig.tight_layout()
    outputs.savefig(fig, path, dpi=110)


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_scaling.py", main))
