#!/usr/bin/python3
"""Fidelity benchmark: --max-error against the exact model, where issue 63
sets its targets. Per case, the exact run (rtsim's default mode) and the
--max-error run, alternated, --runs times each, every run pinned to one
CPU: the medians of their process wall times (the --max-error run's
calibration included) and their ratio, the rung --max-error chose, the
rays sent from node to node in the exact run over those in the chosen
rung's (about the most it can gain: each is a message and a step of a
node's process; express sends a ray past empty boxes as one, through past
boxes with objects it crosses without a hit too), its render
time's error against the exact one, and whether the images are identical. Cases (--case NAME, repeatable; default all):

  big     balls-5 at 1024x1024 on 32x32x32, --max-error 2% (target: within
          2 %, at least 5x faster)
  small   balls-4 at 256x256 on 8x8x8, --max-error 1% (target: within 1 %,
          never slower; three times --runs runs, as they are short)

Prints the table; with --doc writes doc/benchmarks/fidelity.md (without it,
nothing is written), keeping the rows of the cases not run this time from
the page as it was. Run with /usr/bin/python3."""
import argparse
import filecmp
import json
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from bench_rtref import add_cpu_option, machine, pin_to_cpu  # noqa: E402
from bench_rtsim import timed  # noqa: E402
from project import ROOT, RTSIM, spd_scene, version  # noqa: E402

CASES = {  # name: (scene, size, N, --max-error, target error, target speed-up, runs per --runs)
    "big": ("balls-5", "1024x1024", 32, "2%", 0.02, 5.0, 1),
    # Three times the runs: its runs take about a second, and this VM's speed
    # moves by more than its target's margin from minute to minute (3 runs
    # each gave 0.81x, 5 runs 1.01x, where the chooser had picked the exact
    # rung and both modes ran the same frame).
    "small": ("balls-4", "256x256", 8, "1%", 0.01, 1.0, 3),
}

# How far apart two modes doing the same work measure here: pinned,
# alternated runs' ratios lie within 1 to 2 % of each other in a quiet
# spell (bench_rtsim.timed). A speed-up target is met within it: "never
# slower" was 0.998x where the chooser had picked the exact rung.
TIMING_NOISE = 0.02


def run(tmp, scene, size, n, extra, tag):
    """One timed run: (wall s, peak MiB, report)."""
    report, image = os.path.join(tmp, tag + ".json"), os.path.join(tmp, tag + ".png")
    cmd = [RTSIM, "--scene", spd_scene(scene), "--size", size, "--mesh", str(n), "--no-baseline", "-q",
           "--report-detail", "summary", "--report", report, "--image", image] + extra
    wall, mib = timed(cmd)
    with open(report) as f:
        return wall, mib, json.load(f)


def case(tmp, name, runs):
    scene, size, n, error, target_error, target_speedup, per_run = CASES[name]
    walls = {"exact": [], "max": []}
    reports = {}
    for i in range(runs * per_run):
        order = ("exact", "max") if i % 2 == 0 else ("max", "exact")  # (alternated)
        for which in order:
            wall, _, rep = run(tmp, scene, size, n, [] if which == "exact" else ["--max-error", error], which)
            walls[which].append(wall)
            reports[which] = rep
    ex, mx = reports["exact"], reports["max"]
    got = mx["render_time_ns"] / ex["render_time_ns"] - 1
    same = filecmp.cmp(os.path.join(tmp, "exact.png"), os.path.join(tmp, "max.png"), shallow=False)
    speedup = statistics.median(walls["exact"]) / statistics.median(walls["max"])
    cal = mx.get("fidelity", {}).get("calibration", {})
    ok = abs(got) <= target_error and speedup >= target_speedup * (1 - TIMING_NOISE) and same
    # What the rung can gain at most: a node's step and a link message per
    # ray between nodes is most of a frame's simulation, and the express
    # and through rungs keep those into boxes with work of their own.
    hops = ex["totals"]["rays_forwarded"] / max(1, mx["totals"]["rays_forwarded"])
    return (f"| {scene} {size}, {n}x{n}x{n} | {error} | {mx['config']['fidelity']['rung']} | "
            f"{statistics.median(walls['exact']):.1f} | {statistics.median(walls['max']):.1f} "
            f"(calibration {mx['wall_clock'].get('calibration_s', 0):.1f}, {cal.get('size', 'none')}) | "
            f"{speedup:.2f}x (target {target_speedup:g}x) | {hops:.2f}x | {got * 100:+.3f} % | {'yes' if same else 'NO'} | "
            f"{'met' if ok else 'NOT met'} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", action="append", choices=sorted(CASES), help="a case to run (repeatable; default all)")
    ap.add_argument("--runs", type=int, default=3, help="runs of each mode per case, alternated (default 3)")
    ap.add_argument("--doc", action="store_true", help="write doc/benchmarks/fidelity.md")
    add_cpu_option(ap)
    a = ap.parse_args()
    if a.runs < 1:
        ap.error(f"--runs {a.runs}: at least 1")
    cpu = pin_to_cpu(a.cpu, "bench_fidelity.py")
    lines = ["<!-- written by scripts/bench_fidelity.py; do not edit -->",
             f"{machine(os.path.dirname(RTSIM))}, {'pinned to CPU ' + str(cpu) if cpu is not None else 'not pinned'}; rtsim {version()}; "
             f"medians of {a.runs} alternated runs each ({CASES['small'][6] * a.runs} for the small case), process wall time.", "",
             "| case | --max-error | rung chosen | exact wall (s) | --max-error wall (s) | speed-up |"
             " rays between nodes, exact / chosen | render-time error | image identical | target |",
             "|---|---|---|---:|---:|---:|---:|---:|---|---|"]
    with tempfile.TemporaryDirectory(prefix="bench-fidelity-") as tmp:
        for name in a.case or sorted(CASES, key=lambda c: c != "small"):
            lines.append(case(tmp, name, a.runs))
            print(lines[-1], flush=True)
    print("\n".join(lines[1:]))
    if a.doc:
        page = os.path.join(ROOT, "doc", "benchmarks", "fidelity.md")
        lines += kept_rows(page, [lines[k].split(" | ")[0] for k in range(5, len(lines))])
        outputs.write_text(page, "# Fidelity benchmark (`scripts/bench_fidelity.py --doc`)\n\n" + "\n".join(lines) + "\n")


def kept_rows(page, run):
    """The table rows of `page` for the cases not in `run` (their first cells), each with its own run's line."""
    try:
        with open(page) as f:
            old = f.read().splitlines()
    except FileNotFoundError:
        return []
    marked = " (an earlier run) |"
    return [line if line.endswith(marked) else line[:-2] + marked for line in old
            if line.startswith("| ") and not line.startswith("| case") and line.split(" | ")[0] not in run]


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_fidelity.py", main))
