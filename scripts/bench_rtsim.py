#!/usr/bin/python3
"""Benchmark of the machine model: rtsim's wall time against rtref's on the
same scene (default balls-4 at 512x512, N = 4) in each fidelity mode, each
rtsim run between two rtref runs on the same CPU; messages per wall second;
peak memory; the 16x16x16 mesh on balls-5 at 1024x1024 (time and memory);
and how wall time grows with the mesh size N = 1..8 (where rtsim's time
goes against rtref's: bench_split.py). Prints tables; with
--doc writes them to doc/benchmarks/rtsim.md. Standard library only; run
with /usr/bin/python3."""
import argparse
import json
import os
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from bench_rtref import add_cpu_option, build_fast, machine, pin_to_cpu  # noqa: E402
from project import FAST_BUILD, ROOT, run_rtsim, spd_scene, update_doc_section, version  # noqa: E402


def timed(cmd):
    """Runs cmd; returns (wall seconds, peak resident set in MiB).

    Every run is pinned to one CPU (--cpu): this VM's two CPUs ran at
    different speeds for minutes at a time (the same run took 1.5 s on one
    and 2.3 s on the other, at the same moment), so a run the scheduler
    moved between them took either time or anything between, and rtsim's
    and rtref's runs, alternated, could fall on different CPUs. Pinned,
    alternated runs' ratios lay within 1 to 2 % of each other in a quiet
    spell; the pinned CPU's own speed still changes from one minute to the
    next, which measure() deals with.

    The peak comes from GNU time, which runs cmd as its own child: a child
    of this script starts with the script's peak resident set (fork copies
    it and exec keeps it), so once the script had read the 16x16x16 report
    every run's own peak read as the script's (136 MiB for N = 1 to 8)."""
    t0 = time.monotonic()
    # (run_child: a stop of this script ends the run too)
    p = outputs.run_child(["/usr/bin/time", "-f", "maxrss_kib=%M"] + cmd)
    wall = time.monotonic() - t0
    err = p.stderr.rstrip("\n").split("\n")
    if p.returncode != 0 or not err[-1].startswith("maxrss_kib="):
        raise outputs.ToolError(f"{' '.join(cmd)} failed: {' '.join(err).strip()}", outputs.FAILED)
    return wall, int(err[-1].split("=")[1]) / 1024.0


# Fidelity modes compared with rtref (doc/exploration.md, "Fidelity knobs"):
# the two exact ones, the two quanta whose render-time error stays under 1 %
# on every case without balancing in the speed-against-accuracy sweep
# (doc/results/speed_accuracy.md), the 100 us quantum with the links keeping
# counts only (--link-stats counts: no latency percentiles or high-water
# marks in the report, the same timing), and the fastest setting swept. The
# target table takes the fastest mode whose error here is under 1 %, and
# names the fastest that keeps the full report beside it.
MODES = [
    ("exact, lockstep", ["--quantum", "0"]),
    ("exact, quantum = lookahead (the default)", []),
    ("10 us quantum", ["--quantum", "10us"]),
    ("100 us quantum", ["--quantum", "100us"]),
    ("100 us quantum, link counts only", ["--quantum", "100us", "--link-stats", "counts"]),
    ("fastest swept (64 rays per message)", ["--quantum", "100us", "--ray-batch", "64"]),
]
DRIFT, RERUNS = 0.10, 2  # a mode whose rtref strays this far from rtref's median is measured again
BRACKET, REDOS = 0.05, 10  # an rtsim run whose rtref before and after differ this much is made again


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=spd_scene("balls-4"))
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--mesh", type=int, default=4)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--growth", default="1,2,3,4,5,6,7,8", help="mesh sizes for the growth table ('' to skip)")
    ap.add_argument("--growth-runs", type=int, default=3)
    ap.add_argument("--big-runs", type=int, default=3, help="runs of the 16x16x16 mesh on balls-5 (0 to skip)")
    ap.add_argument("--tracing-runs", type=int, default=3,
                    help="runs of each tracing case (0 to skip); --tracing-only: only those")
    ap.add_argument("--tracing-only", action="store_true")
    ap.add_argument("--against", metavar="BUILD",
                    help="only compare this build's rtsim with BUILD's (an older build folder), alternated run by "
                         "run, --against-runs times each mode; with --doc into doc/benchmarks/rtsim-against.md")
    ap.add_argument("--against-runs", type=int, default=7)
    add_cpu_option(ap)
    ap.add_argument("--doc", action="store_true",
                    help="write doc/benchmarks/rtsim.md (or rtsim-against.md) and the generated sections of "
                         "doc/exploration.md and doc/waveforms.md (without it: the tables to stdout only)")
    a = ap.parse_args()
    check_arguments(a)
    build_fast()
    # The script pins itself: every run, GNU time's child too, inherits it.
    pin = pin_to_cpu(a.cpu, "bench_rtsim")
    # The tree's version before anything is written: the tracing section goes
    # into doc/ first, and would make the main tables say "-dirty".
    a.version = version()
    with tempfile.TemporaryDirectory() as tmp:
        return benchmark(a, pin, tmp)


def check_arguments(a):
    """The inputs and the doc pages written with --doc, before any work."""
    outputs.image_size(a.size)
    for flag in ("runs", "growth_runs", "big_runs", "tracing_runs", "against_runs"):
        if getattr(a, flag) < (1 if flag in ("runs", "against_runs") else 0):
            raise outputs.ToolError(f"--{flag.replace('_', '-')} {getattr(a, flag)}: too few")
    outputs.check_input(a.scene, "--scene")
    if a.against:
        outputs.check_input(os.path.join(a.against, "rtsim"), "--against")
    try:
        [int(x) for x in a.growth.split(",") if a.growth]
    except ValueError:
        raise outputs.ToolError(f"--growth {a.growth}: not a list of whole numbers")
    if a.doc:
        for page in ("exploration.md", "waveforms.md", "benchmarks/rtsim.md", "benchmarks/rtsim-against.md"):
            outputs.check_output(os.path.join(ROOT, "doc", page), "--doc", doc=True)


class Runs:
    """The command lines of one benchmark, in the temporary folder `tmp`."""

    def __init__(self, a, tmp):
        self.a, self.tmp, self.build = a, tmp, FAST_BUILD
        self.report = os.path.join(tmp, "r.json")

    def rtsim(self, n, extra=(), scene=None, size=None, image="s.png"):
        a = self.a
        return [os.path.join(self.build, "rtsim"), "--scene", scene or a.scene, "--size", size or a.size,
                "--mesh", str(n), "--no-baseline", "-q", "--image", os.path.join(self.tmp, image),
                "--report", self.report] + list(extra)

    def rtref(self, scene=None, size=None, image="r.png"):
        return [os.path.join(self.build, "rtref"), scene or self.a.scene, "--size", size or self.a.size,
                "-o", os.path.join(self.tmp, image)]

    def same(self, x, y):
        with open(os.path.join(self.tmp, x), "rb") as f, open(os.path.join(self.tmp, y), "rb") as g:
            return f.read() == g.read()

    def last_report(self):
        with open(self.report) as f:
            return json.load(f)


def measure(runs, label, flags, redos):
    """Each rtsim run between two rtref runs (the one after it is the next
    one's before): its ratio is to their mean, and a run whose two rtref
    times differ by more than BRACKET fell across a change of the CPU's
    speed and is made again (at most REDOS times a mode; counted in
    `redos`)."""
    a = runs.a
    sim, ref, ratios, mem = [], [], [], []
    redone = 0
    before, _ = timed(runs.rtref())
    while len(sim) < a.runs:
        ws, ms = timed(runs.rtsim(a.mesh, flags))
        after, _ = timed(runs.rtref())
        wr = (before + after) / 2
        spread = abs(after / before - 1)
        before = after
        if spread > BRACKET and redone < REDOS:
            redone += 1
            print(f"{label}: rtref {spread * 100:.0f} % apart around rtsim's run; made again", file=sys.stderr)
            continue
        sim.append(ws)
        ref.append(wr)
        ratios.append(ws / wr)
        mem.append(ms)
        print(f"{label}, run {len(sim)}: rtsim {ws:.3f} s, rtref {wr:.3f} s, ratio {ws / wr:.2f}", file=sys.stderr)
    redos[label] = redos.get(label, 0) + redone
    return sim, ref, ratios, mem, runs.last_report(), runs.same("s.png", "r.png")


def measure_modes(runs, redos, reruns):
    """Every mode of MODES measured. This machine has slow spells that last
    minutes and need not slow rtsim and rtref alike (one try had lockstep
    faster than the lookahead). A mode whose rtref median strays more than
    DRIFT from the median of every rtref run is measured again, at most
    RERUNS times (counted in `reruns`)."""
    measured = {label: measure(runs, label, flags, redos) for label, flags in MODES}
    for label, flags in MODES:
        for _ in range(RERUNS):
            usual = statistics.median(t for m in measured.values() for t in m[1])
            if abs(statistics.median(measured[label][1]) / usual - 1) <= DRIFT:
                break
            print(f"{label}: rtref's median {statistics.median(measured[label][1]):.3f} s strays from "
                  f"{usual:.3f} s; measured again", file=sys.stderr)
            measured[label] = measure(runs, label, flags, redos)
            reruns[label] = reruns.get(label, 0) + 1
    return measured


def modes_table(measured):
    """The table of modes against rtref, each mode's (ratio, error), and the
    exact mode's report, peak memory and wall."""
    modes = "| mode | flags | rtsim wall | rtref wall | rtsim / rtref | render time | error vs exact | image = rtref |\n" \
            "|---|---|---:|---:|---:|---:|---:|---|\n"
    exact, ratio_of = None, {}
    for label, flags in MODES:
        sim, ref, ratios, mem, r, identical = measured[label]
        if exact is None:
            exact = (r, max(mem), statistics.median(sim))
        err = r["render_time_ns"] / exact[0]["render_time_ns"] - 1
        ratio_of[label] = (statistics.median(ratios), err)
        modes += (f"| {label} | `{' '.join(flags) or '(defaults)'}` | {statistics.median(sim):.3f} s | "
                  f"{statistics.median(ref):.3f} s | **{statistics.median(ratios):.2f}** | "
                  f"{r['render_time_ns'] / 1e6:.3f} ms | {err * 100:+.4f} % | "
                  f"{'yes' if identical else 'NO'} |\n")
    return modes, ratio_of, exact


def quantities_table(a, pin, exact, redos, reruns):
    r, exact_mem, exact_wall = exact
    name = os.path.splitext(os.path.basename(a.scene))[0]
    msgs = sum(r["totals"]["messages"].values())
    rows = [
        ("scene", f"{name} at {a.size}, N = {a.mesh} ({a.mesh ** 3} nodes), default costs and links; "
                  f"medians of {a.runs} runs, each between two rtref runs"),
        ("messages in exact mode (ray / contributions / credit)",
         " / ".join(f"{r['totals']['messages'][k]:,}" for k in ("ray", "contributions", "credit"))),
        ("messages per wall second, exact mode", f"{msgs / exact_wall:,.0f}"),
        ("rtsim peak memory, exact mode (max over runs)", f"{exact_mem:.0f} MiB"),
        ("runs made again because the rtref runs around them differed by more than "
         f"{BRACKET * 100:.0f} %", ", ".join(f"{k} ({v})" for k, v in redos.items() if v) or "none"),
        ("modes measured again because rtref's time strayed more than "
         f"{DRIFT * 100:.0f} % from its median", ", ".join(f"{k} ({v}x)" for k, v in reruns.items()) or "none"),
        ("machine", machine() + (f"; every run pinned to CPU {pin}" if pin is not None else "; runs not pinned")),
        ("version (git describe)", a.version),
    ]
    return "| quantity | value |\n|---|---|\n" + "".join(f"| {k} | {v} |\n" for k, v in rows)


def big_table(runs):
    """The 16x16x16 mesh on balls-5 at 1024x1024: the table and (median
    wall, peak memory, image identical), or ("", None) when skipped."""
    a = runs.a
    if not a.big_runs:
        return "", None
    spd5 = os.path.join(os.path.dirname(a.scene), "balls-5.nff")
    walls, mems = [], []
    for i in range(a.big_runs):
        w, m = timed(runs.rtsim(16, [], spd5, "1024x1024", "big.png"))
        walls.append(w)
        mems.append(m)
        print(f"16x16x16 balls-5 1024x1024, run {i + 1}: {w:.1f} s, {m:.0f} MiB", file=sys.stderr)
    g = runs.last_report()
    wr, _ = timed(runs.rtref(spd5, "1024x1024", "bigref.png"))
    identical = runs.same("big.png", "bigref.png")
    return (("\n16x16x16 mesh (4,096 nodes) on balls-5 (66,430 spheres) at 1024x1024, exact mode, "
             f"{a.big_runs} runs:\n\n| quantity | value |\n|---|---|\n"
             f"| rtsim wall (median) | {statistics.median(walls):.1f} s (runs: "
             f"{', '.join(f'{w:.1f}' for w in walls)}) |\n"
             f"| rtsim peak memory (max) | {max(mems):.0f} MiB |\n"
             f"| rtref wall (one run) | {wr:.1f} s |\n"
             f"| simulated render time | {g['render_time_ns'] / 1e6:.3f} ms |\n"
             f"| ray messages | {g['totals']['messages']['ray']:,} |\n"
             f"| image identical to rtref's | {'yes' if identical else 'NO'} |\n"),
            (statistics.median(walls), max(mems), identical))


def growth_table(runs):
    a = runs.a
    if not a.growth:
        return ""
    growth = ("\nWall time against mesh size (same scene and costs, exact mode):\n\n"
              "| N | nodes | rtsim wall (median of %d) | peak memory | ray messages | render time |\n"
              "|---:|---:|---:|---:|---:|---:|\n" % a.growth_runs)
    for n in [int(x) for x in a.growth.split(",")]:
        walls, mems = [], []
        for _ in range(a.growth_runs):
            w, m = timed(runs.rtsim(n))
            walls.append(w)
            mems.append(m)
        g = runs.last_report()
        growth += (f"| {n} | {n ** 3} | {statistics.median(walls):.3f} s | {max(mems):.0f} MiB | "
                   f"{g['totals']['messages']['ray']:,} | {g['render_time_ns'] / 1e6:.3f} ms |\n")
        print(f"N={n}: {statistics.median(walls):.3f} s", file=sys.stderr)
    return growth


def benchmark(a, pin, tmp):
    """Every table but the comparison with another build (against), in the
    temporary folder `tmp`."""
    runs = Runs(a, tmp)
    if a.against:
        return against(a, tmp, runs.rtsim, pin)
    if a.tracing_runs:
        tracing(a, tmp, runs.rtsim, runs.report)
    if a.tracing_only:
        return
    redos, reruns = {}, {}  # by mode: runs made again, modes measured again
    measured = measure_modes(runs, redos, reruns)
    modes, ratio_of, exact = modes_table(measured)
    table = quantities_table(a, pin, exact, redos, reruns)
    big, big_figures = big_table(runs)
    growth = growth_table(runs)
    goals = targets(ratio_of, big_figures)
    out = "Against the targets (issue 14):\n\n" + goals + "\n" + modes + "\n" + table + big + growth
    print(out, end="")
    if a.doc:
        update_doc_section(os.path.join(ROOT, "doc", "exploration.md"), "performance targets", goals.rstrip("\n"))
        outputs.write_text(os.path.join(ROOT, "doc", "benchmarks", "rtsim.md"),
                           "# rtsim benchmark\n\nWritten by `scripts/bench_rtsim.py --doc`; do not edit by hand.\n\n" + out)


def tracing(a, tmp, rtsim, report):
    """What the VCD costs (vcd_stream.h: written as the run goes): wall time
    and peak memory without it, tracing one node and its links, and tracing
    every node and link; alternated run by run, medians; on the default job
    and on the 16x16x16 mesh (balls-5 at 128x128, every one of its 4,096
    nodes traced). Into doc/waveforms.md's "tracing overhead" section."""
    vcd = os.path.join(tmp, "t.vcd")
    spd5 = os.path.join(os.path.dirname(a.scene), "balls-5.nff")
    jobs = [(f"{os.path.splitext(os.path.basename(a.scene))[0]} at {a.size}, N = {a.mesh}", a.mesh, None, None),
            ("balls-5 at 128x128, N = 16", 16, spd5, "128x128")]
    cases = [("no VCD", []), ("one node and its links (`--trace-nodes 0,0,0`)", ["--vcd", vcd, "--trace-nodes", "0,0,0"]),
             ("every node and link", ["--vcd", vcd])]
    rows = ["| job | tracing | wall (median) | wall / untraced | peak memory | VCD size |", "|---|---|---:|---:|---:|---:|"]
    for job, n, scene, size in jobs:
        walls = {c: [] for c, _ in cases}
        mems = {c: [] for c, _ in cases}
        sizes = {}
        for i in range(a.tracing_runs):
            for label, flags in cases:
                w, m = timed(rtsim(n, flags, scene, size))
                walls[label].append(w)
                mems[label].append(m)
                sizes[label] = os.path.getsize(vcd) if flags else 0
                if flags:
                    os.remove(vcd)
                print(f"tracing, {job}, {label}, run {i + 1}: {w:.2f} s, {m:.0f} MiB", file=sys.stderr)
        base = statistics.median(walls[cases[0][0]])
        for label, _ in cases:
            w = statistics.median(walls[label])
            rows.append(f"| {job} | {label} | {w:.2f} s | {w / base:.2f} | {max(mems[label]):.0f} MiB | "
                        f"{sizes[label] / 2 ** 20:.1f} MiB |")
    rows.append(f"\n{a.tracing_runs} runs of each, alternated; {machine()}; {a.version}.")
    text = "\n".join(rows)
    print(text)
    if a.doc:
        update_doc_section(os.path.join(ROOT, "doc", "waveforms.md"), "tracing overhead", text)


def against(a, tmp, rtsim, pin):
    """This build's rtsim against another build's on each mode of MODES and
    (with --big-runs) the 16x16x16 job: the two alternated run by run on the
    same pinned CPU, the first of each pair swapped every run, so that both
    see the same spells of the CPU's speed; the medians of each and of the
    run-by-run ratios, and the images compared."""
    old = os.path.join(os.path.abspath(a.against), "rtsim")
    jobs = [(label, lambda binary, flags=flags: [binary] + rtsim(a.mesh, flags)[1:]) for label, flags in MODES]
    if a.big_runs:
        spd5 = os.path.join(os.path.dirname(a.scene), "balls-5.nff")
        jobs.append(("16x16x16, balls-5 at 1024x1024, exact",
                     lambda binary: [binary] + rtsim(16, [], spd5, "1024x1024")[1:]))
    rows = ["| job | this build (median) | older build (median) | this / older (median of pairs) | pairs: min .. max |"
            " images |", "|---|---:|---:|---:|---|---|"]
    for label, cmd in jobs:
        new, older, ratios, same = [], [], [], True
        for i in range(a.against_runs):
            pair = {}
            for which in (("new", "old") if i % 2 == 0 else ("old", "new")):
                image = os.path.join(tmp, which + ".png")
                args = cmd(os.path.join(FAST_BUILD, "rtsim") if which == "new" else old)
                args[args.index("--image") + 1] = image
                pair[which], _ = timed(args)
            with open(os.path.join(tmp, "new.png"), "rb") as f, open(os.path.join(tmp, "old.png"), "rb") as g:
                same = same and f.read() == g.read()
            new.append(pair["new"])
            older.append(pair["old"])
            ratios.append(pair["new"] / pair["old"])
            print(f"{label}, pair {i + 1}: {pair['new']:.3f} s against {pair['old']:.3f} s", file=sys.stderr)
        rows.append(f"| {label} | {statistics.median(new):.3f} s | {statistics.median(older):.3f} s | "
                    f"**{statistics.median(ratios):.3f}** | {min(ratios):.3f} .. {max(ratios):.3f} | "
                    f"{'the same' if same else 'DIFFERENT'} |")
    older_version = run_rtsim(["--size", "8x8", "--mesh", "1"], old)[0]["rerun"]["version"]
    text = "\n".join(rows) + (f"\n\n{a.against_runs} pairs each; this build {a.version}, the older build "
                               f"{older_version}, both profile-guided; {machine()}" +
                               (f"; every run pinned to CPU {pin}" if pin is not None else "") + ".\n")
    print(text, end="")
    if a.doc:
        outputs.write_text(os.path.join(ROOT, "doc", "benchmarks", "rtsim-against.md"),
                           "# rtsim against an older build\n\nWritten by `scripts/bench_rtsim.py --against BUILD --doc`; "
                           "do not edit by hand.\n\n" + text)


def targets(ratio_of, big):
    """Issue 14's performance targets against what was measured: a table for
    doc/benchmarks/rtsim.md and doc/exploration.md's generated section."""
    lock, look = ratio_of[MODES[0][0]], ratio_of[MODES[1][0]]
    honest = [(ratio_of[label], " ".join(flags) or "(defaults)") for label, flags in MODES
              if abs(ratio_of[label][1]) < 0.01]
    fast, fast_flags = min(honest)
    full, full_flags = min(h for h in honest if "--link-stats" not in h[1])
    also = "" if full_flags == fast_flags else f"; {full[0]:.2f} keeping the full report (`{full_flags}`)"
    rows = ["| target | measured | met? |", "|---|---|---|",
            f"| exact mode (the default lookahead quantum): rtsim / rtref at most 2.5 | {look[0]:.2f} "
            f"({lock[0]:.2f} in lockstep, `--quantum 0`) | {'yes' if look[0] <= 2.5 else 'no'} |",
            f"| fastest mode with render-time error under 1 %: at most 1.5 | {fast[0]:.2f} at `{fast_flags}` "
            f"(error {fast[1] * 100:+.4f} %){also} | {'yes' if fast[0] <= 1.5 and abs(fast[1]) < 0.01 else 'no'} |"]
    if big:
        rows.append(f"| 16x16x16 mesh on balls-5 at 1024x1024, exact: at most 45 s | {big[0]:.1f} s (median), "
                    f"image {'identical to' if big[2] else 'DIFFERENT from'} rtref's | "
                    f"{'yes' if big[0] <= 45 and big[2] else 'no'} |")
        rows.append(f"| the same run: at most 700 MiB | {big[1]:.0f} MiB peak (the largest of the runs) | "
                    f"{'yes' if big[1] <= 700 else 'no'} |")
    return "\n".join(rows) + "\n"


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_rtsim.py", main))
