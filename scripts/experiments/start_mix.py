#!/usr/bin/python3
"""Where sample starts: the first frame of Fig. 4's experiment (f = 1/N,
256x256, both views, N where the best static split is known) under
`sample`, started with each column's boundaries at the quantiles of a mix
of its objects and its length (--start-mix A: A of the objects, 1 - A of
the length; 1 is the object median), on each machine: modern, 1987, the
paper's, and modern with sphere tests x100. For each machine and mix: how
many points meet the issue's target (the first frame at most 1.2 (paper) or
1.3 times max(1/N, the best static split)), the worst and the median of
that ratio, and how the start split alone (`median` at the same mix, no
messages) does against the unbalanced frame. A second table: the built-in
scene at 64x64 on meshes of odd shapes, where the object median loses on
its own, at the object median and at half of it. A third, the threshold of
--start-mix auto: the modern machine with sphere tests from 10 ns to 1 us,
sample's first frames at f = 1/N (N = 2 to 8, both views) from half the
length and from the object median, beside the mix auto chose. Every point is one rtsim
run through the sweep driver, so it runs locally or on a Dask cluster and a
stopped run resumes.

With --doc, writes doc/results/start_mix.{csv,md},
doc/results/start_mix-shapes.{csv,md} and doc/results/start_mix-auto.{csv,md},
and the tables into doc/balancing.md. Standard library only; run with /usr/bin/python3."""
import argparse
import os
import statistics
import sys
import types

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import project  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, VIEWS, preset_flags, publish_table  # noqa: E402

# The machines of first_frame.py's four tables: (preset, tag, extra flags).
MACHINES = [("modern", "", ""), ("transputer-1987", "", ""), ("paper", "", ""),
            ("modern", "sphere-x100", "--cost-sphere 1us")]
# The odd shapes (issue 61's), the built-in scene at 64x64, rtsim's own machine.
SHAPES = ["64x1x1", "33x1x1", "64x2x1", "16x16x4", "2x2x32", "8x8x8"]
SHAPE_MIXES = [1.0, 0.5]
# --start-mix auto's threshold: the modern machine's sphere test at these
# costs (a ray's hop there: 212 ns), sample from each start and from auto's.
AUTO_SPHERE_COSTS = ["10ns", "50ns", "100ns", "200ns", "600ns", "1us"]
AUTO_MIXES = ["0.5", "1", "auto"]
AUTO_NS = [2, 3, 4, 5, 6, 7, 8]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mixes", default="0.4,0.5,0.6,0.7,0.8,0.9,1", help="the start mixes, each in [0, 1]")
    ap.add_argument("--n", default="4,5,6,7,8", help="mesh sizes (a point counts where the best static split is known: N = 4 to 8 on the paper's machine, 4, 5 and 8 on the others)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    ns = outputs.numbers(a.n, "--n", least=2, most=32)  # (rtsim --mesh: at most 32)
    mixes = outputs.numbers(a.mixes, "--mixes", kind=float, least=0, most=1)
    if len(set(mixes)) < len(mixes):
        raise outputs.ToolError(f"--mixes {a.mixes!r}: a mix given twice")
    csv_path = os.path.join(a.out, "start_mix.csv")
    rows = driver.swept_rows(a, csv_path, lambda: sweep(a, ns, mixes))
    table(a, rows, os.path.join(a.out, "start_mix.md"))
    shapes_csv = os.path.join(a.out, "start_mix-shapes.csv")
    shapes_table(a, driver.swept_rows(a, shapes_csv, lambda: sweep_shapes(a)), os.path.join(a.out, "start_mix-shapes.md"))
    auto_csv = os.path.join(a.out, "start_mix-auto.csv")
    auto_table(a, driver.swept_rows(a, auto_csv, lambda: sweep_auto(a)), os.path.join(a.out, "start_mix-auto.md"))


def mix_flag(mix):
    """A mix as rtsim's flag: short where that is the same number (0.5, 1), else in full."""
    return f"{mix:g}" if float(f"{mix:g}") == mix else repr(mix)


def machine_of(preset, tag, a):
    """A machine of MACHINES as project's helpers take one (--preset, --tag, and the results folder)."""
    return types.SimpleNamespace(preset=preset, tag=tag, out=a.out)


def against_none(runs, fields, keep=()):
    """The CSV rows: each run's `fields` (its point's, the policy and the mix
    among them) and its frame beside the unbalanced run's of the same point
    (the same fields but the policy and the mix), the unbalanced runs aside;
    and each run's `keep` figures, which name no point."""
    def point(r):
        return tuple(r[f] for f in fields if f not in ("policy", "mix"))
    none = {point(r): r["render_time_ns"] for r in runs if r["policy"] == "none"}
    return [{**{f: r[f] for f in fields}, "time_none_ns": none[point(r)], "time_ns": r["render_time_ns"],
             "ratio": r["render_time_ns"] / none[point(r)], **{k: r[k] for k in keep},
             "version": r["version"], "command": r["command"]}
            for r in runs if r["policy"] != "none"]


def sweep(a, ns, mixes):
    points = []
    for preset, tag, extra in MACHINES:
        for view, cam in VIEWS.items():
            for n in ns:
                base = preset_flags(preset) + PAPER_SCENE + cam + ["--mesh", n, "--concentration", f"{1 / n:.6f}"]
                params = {"machine": project.machine(machine_of(preset, tag, a)), "view": view, "N": n}
                points.append({"params": dict(params, policy="none", mix=1.0),
                               "args": base + ["--balance", "none"] + extra.split()})
                for policy in ("sample", "median"):
                    for mix in mixes:
                        points.append({"params": dict(params, policy=policy, mix=mix),
                                       "args": base + ["--balance", policy, "--start-mix", mix_flag(mix)] + extra.split()})
    runs = driver.run("start_mix", points, lambda r: {"render_time_ns": r["render_time_ns"]}, None, a)
    return against_none(runs, ["machine", "view", "N", "policy", "mix"])


def table(a, rows, md_path):
    for r in rows:
        r["N"], r["mix"], r["ratio"] = int(r["N"]), float(r["mix"]), float(r["ratio"])
    lines = ["<!-- written by scripts/experiments/start_mix.py; do not edit -->",
             "| machine | start mix | sample: points within the target | sample / max(1/N, best): worst | median of "
             "it | the start alone (median): worst of the unbalanced frame |",
             "|---|---:|---:|---:|---:|---:|"]
    for preset, tag, _ in MACHINES:
        machine = machine_of(preset, tag, a)
        m = project.machine(machine)
        best = {k: v[0] for k, v in project.best_static(machine).items()}
        factor = project.target_factor(machine)
        for mix in sorted({r["mix"] for r in rows if r["machine"] == m}):
            sample = [r for r in rows if r["machine"] == m and r["mix"] == mix and r["policy"] == "sample"
                      and (r["view"], r["N"]) in best]
            start = [r["ratio"] for r in rows if r["machine"] == m and r["mix"] == mix and r["policy"] == "median"]
            ratios = [r["ratio"] / max(1 / r["N"], best[(r["view"], r["N"])]) for r in sample]
            if not ratios or not start:
                continue
            within = sum(x <= factor for x in ratios)
            lines.append(f"| {m} | {mix:g} | {within} of {len(ratios)} (target {factor} x) | {max(ratios):.2f} | "
                         f"{statistics.median(ratios):.2f} | {max(start):.3f} |")
    publish_table(lines, md_path, a.doc, "start mix")


def sweep_shapes(a):
    points = []
    for shape in SHAPES:
        base = ["--size", "64x64", "--mesh-dims", shape]
        points.append({"params": {"shape": shape, "policy": "none", "mix": 1.0}, "args": base + ["--balance", "none"]})
        for policy in ("median", "sample"):
            for mix in SHAPE_MIXES:
                points.append({"params": {"shape": shape, "policy": policy, "mix": mix},
                               "args": base + ["--balance", policy, "--start-mix", mix_flag(mix)]})
    runs = driver.run("start_mix-shapes", points, lambda r: {"render_time_ns": r["render_time_ns"]}, None, a)
    return against_none(runs, ["shape", "policy", "mix"])


def shapes_table(a, rows, md_path):
    cols = [(p, m) for p in ("median", "sample") for m in SHAPE_MIXES]
    lines = ["<!-- written by scripts/experiments/start_mix.py; do not edit -->",
             "| mesh | unbalanced frame | " + " | ".join(f"{p}, start mix {m:g}" for p, m in cols) + " |",
             "|---|---:|" + "---:|" * len(cols)]
    for shape in SHAPES:
        by = {(r["policy"], float(r["mix"])): r for r in rows if r["shape"] == shape}
        if len(by) < len(cols):
            continue
        none_us = float(by[cols[0]]["time_none_ns"]) / 1000
        lines.append(f"| {shape} | {none_us:.1f} us | " +
                     " | ".join(f"{float(by[c]['ratio']):.3f}" for c in cols) + " |")
    publish_table(lines, md_path, a.doc, "start mix shapes")


def sweep_auto(a):
    points = []
    for cost in AUTO_SPHERE_COSTS:
        for view, cam in VIEWS.items():
            for n in AUTO_NS:
                base = preset_flags("modern") + PAPER_SCENE + cam + ["--mesh", n, "--concentration", f"{1 / n:.6f}",
                                                                     "--cost-sphere", cost]
                params = {"sphere": cost, "view": view, "N": n}
                points.append({"params": dict(params, policy="none", mix="-"), "args": base + ["--balance", "none"]})
                for mix in AUTO_MIXES:
                    points.append({"params": dict(params, policy="sample", mix=mix),
                                   "args": base + ["--balance", "sample", "--start-mix", mix]})
    runs = driver.run("start_mix-auto", points, lambda r: {"render_time_ns": r["render_time_ns"],
                                                           "chosen": r["config"]["balance"]["start_mix"]}, None, a)
    rows = against_none(runs, ["sphere", "view", "N", "policy", "mix"])
    chosen = {(r["sphere"], r["view"], r["N"], r["mix"]): r["chosen"] for r in runs if r["policy"] != "none"}
    return [dict(r, chosen=chosen[(r["sphere"], r["view"], r["N"], r["mix"])]) for r in rows]


def auto_table(a, rows, md_path):
    lines = ["<!-- written by scripts/experiments/start_mix.py; do not edit -->",
             "| sphere test (a hop: 212 ns) | sample from 0.5: median, worst | from 1: median, worst | "
             "auto: its mix | auto: median, worst |",
             "|---|---:|---:|---:|---:|"]
    for cost in AUTO_SPHERE_COSTS:
        def of(mix):
            return [r for r in rows if r["sphere"] == cost and r["mix"] == mix]
        if not all(of(m) for m in AUTO_MIXES):
            continue
        cells = []
        for mix in AUTO_MIXES:
            ratios = [float(r["ratio"]) for r in of(mix)]
            cells.append(f"{statistics.median(ratios):.3f}, {max(ratios):.3f}")
        picked = sorted({f"{float(r['chosen']):g}" for r in of("auto")})
        lines.append(f"| {cost.replace('ns', ' ns').replace('us', ' us')} | {cells[0]} | {cells[1]} | "
                     f"{', '.join(picked)} | {cells[2]} |")
    publish_table(lines, md_path, a.doc, "start mix auto")


if __name__ == "__main__":
    sys.exit(outputs.guard("start_mix.py", main))
