#!/usr/bin/python3
"""Randomized stress: random meshes, link and per-link settings, node
speeds, policies, intervals, gains, quanta, batches and frame-buffer layouts
on small scenes. Every run must exit 0 (the run checks its own
conservation), give the image rtref gives for the same scene and size, and
give the same image and report again when rerun (wall-clock fields aside).
A seed fixes the configurations.

  /usr/bin/python3 scripts/stress.py --count 1000 --doc   # the full run; figures to doc/results/stress.md
  /usr/bin/python3 scripts/stress.py --count 50           # the slice ctest runs (StressSlice)
"""
import argparse
import concurrent.futures
import os
import random
import shlex
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from project import RESULTS, ROOT, RTREF, RTSIM, publish_table, run_rtsim, spd_scene  # noqa: E402

POLICIES = ["none", "slide", "work", "quantile", "resplit", "median", "default"]
DIRS = ["+x", "-x", "+y", "-y", "+z", "-z"]


def time_between(rng, lo_ps, hi_ps):
    """A time with a unit, log-uniform between lo and hi picoseconds."""
    ps = int(round(10 ** rng.uniform(len(str(lo_ps)) - 1, len(str(hi_ps)) - 1)))
    ps = max(lo_ps, min(hi_ps, ps))
    return f"{ps}ps"


def configuration(rng):
    """One random configuration: (scene flags shared with rtref, rtsim-only flags)."""
    w, h = rng.randint(8, 40), rng.randint(8, 40)
    if rng.random() < 0.3:
        scene = [spd_scene(rng.choice(["balls-1", "tetra-3", "balls-2"])), "--size", f"{w}x{h}"]
        rtsim_scene = ["--scene"] + scene[:1] + scene[1:]
    else:
        scene = ["--spheres", str(rng.randint(5, 300)), "--radius", f"{rng.uniform(0.01, 0.08):.3f}",
                 "--concentration", f"{rng.choice([0.25, 0.5, 1.0])}", "--seed", str(rng.randint(1, 10 ** 6)),
                 "--axis", rng.choice("xyz"), "--size", f"{w}x{h}"]
        rtsim_scene = scene
    dims = [rng.randint(1, 4) for _ in range(3)]
    a = ["--mesh-dims", "x".join(map(str, dims)),
         "--link-latency", time_between(rng, 1000, 10 ** 7),
         "--link-bandwidth", f"{rng.choice([10, 100, 1000, 10000])}MB/s",
         "--link-depth", str(rng.randint(1, 16)),
         "--link-control-depth", str(rng.choice([0, 0, 1, 2])),
         "--fb-units", str(rng.choice([1, 2, 3, 16])),
         "--fb-batch", str(rng.randint(1, 64)),
         "--ray-batch", str(rng.choice([1, 1, 2, 8])),
         "--balance", rng.choice(POLICIES),
         "--balance-interval", f"{rng.choice([1, 2, 5, 20, 50])}us",
         "--gain", f"{rng.choice([0, 0.1, 0.5, 1.0])}",
         "--quantum", rng.choice(["0", "lookahead", "lookahead", "1us", "20us"])]
    cells = [(x, y, z) for x in range(dims[0]) for y in range(dims[1]) for z in range(dims[2])]
    for _ in range(rng.randint(0, 3)):
        x, y, z = rng.choice(cells)
        a += ["--node-speed", f"{x},{y},{z}={rng.choice([0.25, 0.5, 2.0, 4.0])}"]
    for _ in range(rng.randint(0, 3)):
        x, y, z = rng.choice(cells)
        d = rng.choice(DIRS)
        axis, step = "xyz".index(d[1]), 1 if d[0] == "+" else -1
        if not 0 <= (x, y, z)[axis] + step < dims[axis]:
            continue
        a += ["--link-set", f"{x},{y},{z},{d}:latency={time_between(rng, 1000, 10 ** 7)},depth={rng.randint(1, 4)}"]
    if rng.random() < 0.2:
        a += ["--frames", str(rng.randint(2, 3))]
    return scene, rtsim_scene + a


def without_wall(report):
    """The report without what depends on the wall clock."""
    if isinstance(report, dict):
        return {k: without_wall(v) for k, v in report.items() if "wall" not in k}
    if isinstance(report, list):
        return [without_wall(v) for v in report]
    return report


def check(index, scene, args, rtsim, rtref, tmp):
    """'' if the configuration passes, else what failed."""
    try:
        return run_and_compare(index, scene, args, rtsim, rtref, tmp)
    except OSError as e:  # a program that cannot be run (replaced by a build meanwhile, say)
        return f"could not run: {e}"


def run_and_compare(index, scene, args, rtsim, rtref, tmp):
    d = os.path.join(tmp, str(index))
    os.makedirs(d)
    ref = subprocess.run([rtref] + scene + ["-o", os.path.join(d, "ref.png")], capture_output=True, text=True)
    if ref.returncode != 0:
        return f"rtref failed: {ref.stderr.strip()}"
    runs = []
    for k in (1, 2):
        image = os.path.join(d, f"{k}.png")
        try:
            report, _ = run_rtsim(args, rtsim, timeout=120, image=image, report=os.path.join(d, f"{k}.json"))
        except subprocess.TimeoutExpired:
            return "timed out after 120 s"
        except RuntimeError as e:
            return str(e)
        with open(image, "rb") as f:
            runs.append((f.read(), without_wall(report)))
    with open(os.path.join(d, "ref.png"), "rb") as f:
        if runs[0][0] != f.read():
            return "image differs from rtref's"
    if runs[0][0] != runs[1][0]:
        return "rerun: image differs"
    if runs[0][1] != runs[1][1]:
        return "rerun: report differs"
    return ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--rtsim", default=RTSIM)
    ap.add_argument("--rtref", default=RTREF)
    ap.add_argument("--doc", action="store_true", help="write the figures to doc/results/stress.md")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    configs = [configuration(rng) for _ in range(a.count)]
    t0 = time.time()
    failures = []
    with tempfile.TemporaryDirectory() as tmp, concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {pool.submit(check, i, s, args, a.rtsim, a.rtref, tmp): (i, args) for i, (s, args) in enumerate(configs)}
        for done, fut in enumerate(concurrent.futures.as_completed(futures), 1):
            i, args = futures[fut]
            why = fut.result()
            if why:
                failures.append((i, why, args))
                print(f"stress: configuration {i} failed: {why}\n  rtsim {shlex.join(args)}", file=sys.stderr)
            if sys.stderr.isatty():
                print(f"\rstress: {done}/{a.count}", end="", file=sys.stderr)
    wall = time.time() - t0
    policies = {}
    for _, args in configs:
        p = args[args.index("--balance") + 1]
        policies[p] = policies.get(p, 0) + 1
    summary = (f"{a.count} configurations (seed {a.seed}), {a.count - len(failures)} passed, "
               f"{len(failures)} failed, {wall:.0f} s")
    print(f"stress: {summary}")
    if a.doc:
        lines = ["<!-- written by scripts/stress.py --doc; do not edit -->",
                 f"`scripts/stress.py --count {a.count} --seed {a.seed}`: {summary} on {a.jobs} workers.",
                 "Each configuration: rtsim twice and rtref once; exit 0, the image rtref gives, and the same "
                 "image and report (wall-clock fields aside) on the rerun.", "",
                 "| policy | configurations |", "|---|---:|"]
        lines += [f"| {p} | {n} |" for p, n in sorted(policies.items())]
        if failures:
            lines += ["", "Failures:", ""] + [f"- {i}: {why} (`rtsim {shlex.join(args)}`)" for i, why, args in failures]
        publish_table(lines, os.path.join(RESULTS, "stress.md"),
                      os.path.join(ROOT, "doc", "robustness.md"), "stress")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
