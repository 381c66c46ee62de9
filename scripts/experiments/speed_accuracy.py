#!/usr/bin/python3
"""Speed against accuracy, rung by rung: every fidelity rung of rtsim
(doc/fidelity.md: express, through, a 10 us quantum, express with it) and what --max-error
chooses, against the exact model in rtsim's default mode, on any scenes,
meshes and machine flags. Charts each point's |render-time error| against
its wall-time speed-up over the default mode (the process's wall time, a
--max-error run's calibration included), with each case's Pareto front.
With --doc, writes doc/results/speed_accuracy.{csv,png,md}.

  /usr/bin/python3 scripts/experiments/speed_accuracy.py --scenes balls-4 --n 4,8 --size 64x64
  /usr/bin/python3 scripts/experiments/speed_accuracy.py --doc        # the SPD scenes at N = 4, 8, 16, 32

The points run through the sweep driver (scripts/sweep_driver.py: locally,
or on a Dask cluster with --dask), one at a time unless --jobs says
otherwise, each --repeats times; wall = the median. Needs
python3-matplotlib (bash scripts/setup.sh plots); run with /usr/bin/python3."""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import project  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, publish_table, spd_scene  # noqa: E402
from csv_rows import read_csv  # noqa: E402
from sweep_driver import write_csv  # noqa: E402

SPD = ["balls-1", "balls-2", "balls-3", "balls-4", "balls-5", "gears-2", "rings-2", "tetra-3"]
# The rungs (tb/fidelity_choice.cpp's, by the flags that set them); "exact" is rtsim's default mode.
RUNGS = {
    "exact": [],
    "express": ["--fidelity", "express"],
    "through": ["--fidelity", "through"],
    "quantum 10 us": ["--quantum", "10us"],
    "express, quantum 10 us": ["--fidelity", "express", "--quantum", "10us"],
}
# The flags a point sets itself (its scene, image, mesh and rung): not for --flags.
OWN = ["--scene", "--size", "--mesh", "--mesh-dims", "--fidelity", "--quantum", "--max-error"]
COLOURS = {"exact": "black", "express": "#2a6fdb", "through": "#2a9d5b", "quantum 10 us": "#e9a23b",
           "express, quantum 10 us": "#7b4fb0"}


def scene_flags(name):
    """The flags of a scene by name: an SPD scene, or "procedural" (rtsim's paper scene)."""
    if name == "procedural":
        flags = list(PAPER_SCENE)
        del flags[flags.index("--size"):flags.index("--size") + 2]  # (--size is the sweep's)
        return flags
    return ["--scene", spd_scene(name)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default=",".join(SPD), help="SPD scene names or 'procedural', comma-separated")
    ap.add_argument("--n", default="4,8,16,32", help="mesh sizes N (N x N x N)")
    ap.add_argument("--size", default="128x128", help="image size WxH")
    ap.add_argument("--max-errors", default="1%", help="--max-error values to run, comma-separated (empty: none)")
    ap.add_argument("--flags", default="", help="more rtsim flags for every point (the machine), e.g. '--link-bandwidth 200MB/s'")
    ap.add_argument("--repeats", type=int, default=3, help="runs per point; wall = their median (default 3)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "exploration.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    if a.repeats < 1:
        ap.error(f"--repeats {a.repeats}: at least 1")
    try:
        a.ns = [int(n) for n in a.n.split(",")]
    except ValueError:
        ap.error(f"--n {a.n!r}: comma-separated whole numbers")
    if not all(1 <= n <= 32 for n in a.ns):
        ap.error(f"--n {a.n}: each N in 1..32")
    for name in a.scenes.split(","):
        if name not in SPD + ["procedural"]:
            ap.error(f"--scenes: {name!r} is not one of {', '.join(SPD + ['procedural'])}")
    outputs.image_size(a.size)
    a.errors = [error_share(e) for e in a.max_errors.split(",")] if a.max_errors else []
    if len(set(a.errors)) != len(a.errors):
        ap.error(f"--max-errors {a.max_errors!r}: a value given twice")
    # The flags each point sets itself: given again, a row would name one value and rtsim run another.
    a.extra = driver.extra_flags(a.flags, "--flags", OWN + ([f for f in PAPER_SCENE if f.startswith("--")] if "procedural" in a.scenes.split(",") else []))
    a.jobs = a.jobs or 1  # timing: one run at a time unless asked
    csv_path = os.path.join(a.out, "speed_accuracy.csv")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        write_csv(csv_path, sweep(a))
    rows = read_csv(csv_path, {"N": int, "wall_s": float, "render_time_ns": float, "error": float, "speedup": float,
                               "scene": str, "mode": str, "rung": str})
    cases = {(r["scene"], r["N"]) for r in rows}
    exact = {(r["scene"], r["N"]) for r in rows if r["mode"] == "exact"}
    if cases - exact:
        scene, n = sorted(cases - exact)[0]
        raise outputs.ToolError(f"{csv_path}: no exact row for {scene} at N = {n}, which the others are measured against")
    plot(a, rows)
    table(a, rows)


def error_share(text):
    """A --max-errors value as rtsim's --max-error takes it: a share above 0
    and below 1 (0.02) or a percentage (2%); ToolError otherwise, before
    any run."""
    m = re.fullmatch(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?(%?)", text)
    share = (float(text.rstrip("%")) / (100 if m.group(4) else 1)) if m else 0
    if not 0 < share < 1:
        raise outputs.ToolError(f"--max-errors: {text!r} is not a share above 0 and below 1 (0.02) "
                                "or a percentage (2%); comma-separated")
    return text


def sweep(a):
    extra, errors = a.extra, a.errors
    points = []
    for scene in a.scenes.split(","):
        flags = scene_flags(scene) + ["--size", a.size] + extra
        for n in a.ns:
            modes = dict(RUNGS, **{f"--max-error {e}": ["--max-error", e] for e in errors})
            for mode, more in modes.items():
                points.append({"params": {"scene": scene, "N": n, "mode": mode},
                               "args": flags + ["--mesh", n] + more})
    runs = driver.run("speed_accuracy", points, extract, None, a, repeats=a.repeats)
    exact = {(r["scene"], r["N"]): r for r in runs if r["mode"] == "exact"}
    rows = []
    for r in runs:
        e = exact[(r["scene"], r["N"])]
        rows.append({"scene": r["scene"], "N": r["N"], "mode": r["mode"], "rung": r["rung"],
                     "render_time_ns": r["render_time_ns"], "error": r["render_time_ns"] / e["render_time_ns"] - 1,
                     "wall_s": r["wall_s"], "speedup": e["wall_s"] / r["wall_s"],
                     "calibration_s": r["calibration_s"], "version": r["version"], "command": r["command"]})
    return rows


def extract(r):
    return {"render_time_ns": r["render_time_ns"], "rung": r["config"]["fidelity"]["rung"],
            "calibration_s": r["wall_clock"].get("calibration_s", 0.0)}


def pareto(points):
    """The points no other point beats in both speed-up and |error|."""
    front, best = [], float("inf")
    for p in sorted(points, key=lambda p: (-p["speedup"], abs(p["error"]))):
        if abs(p["error"]) < best:
            front.append(p)
            best = abs(p["error"])
    return front


def pct(x):
    return "0 (identical)" if x == 0 else f"{x * 100:+.3g} %"


def plot(a, rows):
    plt = project.pyplot()
    ns = sorted({r["N"] for r in rows})
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    markers = dict(zip(scenes, ["o", "s", "^", "D", "v", "P", "X", "*", "h"]))
    fig, axes = plt.subplots(1, len(ns), figsize=(max(10.0, 4.6 * len(ns)), 4.8), squeeze=False)
    for ax, n in zip(axes[0], ns):
        for scene in scenes:
            pts = [r for r in rows if r["N"] == n and r["scene"] == scene]
            for r in pts:
                chosen = r["mode"].startswith("--max-error")
                ax.scatter([abs(r["error"]) * 100], [r["speedup"]], marker=markers[scene], s=40 if chosen else 30,
                           facecolors="none" if chosen else COLOURS.get(r["rung"], "grey"),
                           edgecolors=COLOURS.get(r["rung"], "grey"), linewidths=1.2)
            front = sorted(pareto([p for p in pts if not p["mode"].startswith("--max-error")]), key=lambda p: abs(p["error"]))
            ax.step([abs(p["error"]) * 100 for p in front], [p["speedup"] for p in front], where="post", color="grey",
                    linewidth=0.8, alpha=0.6)
        ax.axvline(1.0, color="#d1495b", linewidth=0.8, alpha=0.5)
        ax.axhline(1.0, color="black", linewidth=0.6, alpha=0.4)
        ax.set_xscale("symlog", linthresh=1e-2)
        ax.set_xlim(left=0)
        ax.set_title(f"{n}x{n}x{n}", fontsize=10)
        ax.set_xlabel("|render-time error| vs exact (%)")
        ax.grid(alpha=0.3, which="both")
    axes[0][0].set_ylabel("wall-time speed-up over the default mode")
    handles = [plt.Line2D([], [], color=c, marker="o", linestyle="", label=k) for k, c in COLOURS.items()]
    handles += [plt.Line2D([], [], color="grey", marker=m, linestyle="", label=s) for s, m in markers.items()]
    handles += [plt.Line2D([], [], color="grey", marker="o", markerfacecolor="none", linestyle="",
                           label="hollow: --max-error's choice (calibration included)")]
    fig.legend(handles=handles, loc="lower center", ncol=7, fontsize=8)
    fig.suptitle(f"Speed against accuracy by rung (image {a.size}{', ' + a.flags if a.flags else ''}); grey steps: "
                 "each scene's Pareto front; red line: 1 % error", fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    outputs.savefig(fig, os.path.join(a.out, "speed_accuracy.png"), dpi=100)


def table(a, rows):
    """Each case's rungs and --max-error's choices (doc/results/speed_accuracy.md)."""
    modes = list(dict.fromkeys(r["mode"] for r in rows))
    lines = ["<!-- written by scripts/experiments/speed_accuracy.py; do not edit -->",
             "| scene | N | exact wall (s) | " + " | ".join(m.replace("--max-error ", "max-error ") for m in modes[1:]) + " |",
             "|---|---|---|" + "---|" * (len(modes) - 1)]
    for scene in dict.fromkeys(r["scene"] for r in rows):
        for n in sorted({r["N"] for r in rows if r["scene"] == scene}):
            by = {r["mode"]: r for r in rows if r["scene"] == scene and r["N"] == n}
            cells = []
            for m in modes[1:]:
                r = by.get(m)
                if r is None:
                    cells.append("")
                    continue
                chose = f"{r['rung']}: " if m.startswith("--max-error") else ""
                cells.append(f"{chose}{r['speedup']:.2f}x, {pct(r['error'])}")
            lines.append(f"| {scene} | {n} | {by['exact']['wall_s']:.2f} | " + " | ".join(cells) + " |")
    publish_table(lines, os.path.join(a.out, "speed_accuracy.md"), a.doc, "speed_accuracy table")


if __name__ == "__main__":
    sys.exit(outputs.guard("speed_accuracy.py", main))
