#!/usr/bin/python3
"""Speed against accuracy: sweeps the fidelity knobs (the quantum of temporal
decoupling, rays per link message) on balls-4 and on the concentrated
procedural scene, N = 4 and 8, with and without balancing; charts wall-clock
time against the render-time error relative to the exact mode (quantum 0,
one ray per message) and against the balancing outcome, with the Pareto
front marked. With --doc, writes doc/results/speed_accuracy.{csv,png,md}.

Timing: the points run one at a time (--jobs 1 unless told otherwise), each
--repeats times, wall = the median. Needs python3-matplotlib
(bash scripts/setup.sh plots); run with /usr/bin/python3."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import project  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, publish_table, spd_scene  # noqa: E402
from outputs import read_csv  # noqa: E402
from sweep_driver import write_csv  # noqa: E402

SCENES = {
    "balls-4": ["--scene", spd_scene("balls-4"), "--size", "256x256"],
    # rtsim's default experiment: the paper's scene crowded into the first quarter of x.
    "procedural": PAPER_SCENE + ["--concentration", "0.25"],
}
EXACT = ("0", 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="4,8")
    ap.add_argument("--quanta", default="0,100ns,1us,10us,100us", help="--quantum values (0 is exact)")
    ap.add_argument("--batches", default="1,4,16,64", help="--ray-batch values")
    ap.add_argument("--balance", default="slide", help="the balancing policy compared with none (not none itself)")
    ap.add_argument("--repeats", type=int, default=3, help="runs per point; wall = their median (default 3)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "exploration.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    if a.balance == "none":
        # Every point runs with none already: a policy against itself is no comparison.
        ap.error("--balance none: the policy to compare with none (slide, measured, ...), not none itself")
    if a.repeats < 1:
        ap.error(f"--repeats {a.repeats}: at least 1")
    a.jobs = a.jobs or 1  # timing: one run at a time unless asked
    csv_path = os.path.join(a.out, "speed_accuracy.csv")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        rows = sweep(a)
        write_csv(csv_path, rows)
    rows = read_csv(csv_path)
    for r in rows:
        for k in ("N", "ray_batch"):
            r[k] = int(r[k])
        for k in ("wall_s", "render_time_ns", "error", "exact_render_time_ns", "balance_gain", "exact_balance_gain"):
            r[k] = float(r[k]) if r[k] != "" else None
    plot(a, rows)
    table(a, rows)


def sweep(a):
    ns = [int(n) for n in a.n.split(",")]
    quanta, batches = a.quanta.split(","), [int(k) for k in a.batches.split(",")]
    points = []
    for scene, flags in SCENES.items():
        for n in ns:
            for bal in ("none", a.balance):
                for q in quanta:
                    for k in batches:
                        points.append({"params": {"scene": scene, "N": n, "balance": bal, "quantum": q, "ray_batch": k},
                                       "args": flags + ["--mesh", n, "--balance", bal, "--quantum", q,
                                                        "--ray-batch", k]})
    runs = driver.run("speed_accuracy", points, extract, None, a, repeats=a.repeats)
    by = {(r["scene"], r["N"], r["balance"], r["quantum"], r["ray_batch"]): r for r in runs}
    rows = []
    for r in runs:
        key = (r["scene"], r["N"])
        exact = by[key + (r["balance"],) + EXACT]
        row = {k: r[k] for k in ("scene", "N", "balance", "quantum", "ray_batch", "wall_s", "wall_s_min", "wall_s_max",
                                 "render_time_ns") if k in r}  # (the spread with --repeats > 1)
        row["exact_render_time_ns"] = exact["render_time_ns"]
        row["error"] = r["render_time_ns"] / exact["render_time_ns"] - 1
        # The balancing outcome: how much it shortened the frame in this mode,
        # against the same in exact mode.
        if r["balance"] != "none":
            unbalanced = by[key + ("none", r["quantum"], r["ray_batch"])]
            row["balance_gain"] = unbalanced["render_time_ns"] / r["render_time_ns"]
            ex_none = by[key + ("none",) + EXACT]
            row["exact_balance_gain"] = ex_none["render_time_ns"] / exact["render_time_ns"]
        else:
            row["balance_gain"] = row["exact_balance_gain"] = ""
        row["slides"] = r["slides"]
        row["version"], row["command"] = r["version"], r["command"]
        rows.append(row)
    return rows


def extract(r):
    return {"render_time_ns": r["render_time_ns"], "slides": r["balance"]["slides"]}


def pareto(points):
    """The points no other point beats in both wall time and |error|."""
    front, best = [], float("inf")
    for p in sorted(points, key=lambda p: (p["wall_s"], abs(p["error"]))):
        if abs(p["error"]) < best:
            front.append(p)
            best = abs(p["error"])
    return front


def pct(x):
    return "0 (identical)" if x == 0 else f"{x * 100:+.3g} %"


def plot(a, rows):
    import matplotlib.ticker
    plt = project.pyplot()
    cases = sorted({(r["scene"], r["N"]) for r in rows})
    fig, axes = plt.subplots(2, len(cases), figsize=(4.6 * len(cases), 8.2), squeeze=False)
    quanta = list(dict.fromkeys(r["quantum"] for r in rows))
    colours = dict(zip(quanta, ["black", "#2a6fdb", "#2a9d55", "#e9a23b", "#d1495b", "#7b4fb0"]))
    markers = dict(zip(sorted({r["ray_batch"] for r in rows}), ["o", "s", "^", "D", "v", "P"]))
    for col, (scene, n) in enumerate(cases):
        ax, bx = axes[0][col], axes[1][col]
        for bal, fill in (("none", True), (a.balance, False)):
            pts = [r for r in rows if r["scene"] == scene and r["N"] == n and r["balance"] == bal]
            for r in pts:
                style = dict(marker=markers[r["ray_batch"]], s=36, linewidths=1.2)
                if fill:
                    ax.scatter([abs(r["error"]) * 100], [r["wall_s"]], color=colours[r["quantum"]], **style)
                else:
                    ax.scatter([abs(r["error"]) * 100], [r["wall_s"]], facecolors="none",
                               edgecolors=colours[r["quantum"]], **style)
                    bx.scatter([r["balance_gain"]], [r["wall_s"]], color=colours[r["quantum"]], **style)
            front = sorted(pareto(pts), key=lambda p: abs(p["error"]))
            ax.step([abs(p["error"]) * 100 for p in front], [p["wall_s"] for p in front], where="post",
                    color="grey", linestyle="-" if fill else "--", linewidth=1,
                    label=f"Pareto front, balance {bal}")
            if not fill and pts:
                bx.axvline(pts[0]["exact_balance_gain"], color="black", linestyle=":", linewidth=1,
                           label="exact mode's gain")
        ax.axvline(1.0, color="#d1495b", linewidth=0.8, alpha=0.5)
        ax.set_xscale("symlog", linthresh=1e-3)
        ax.set_xlim(left=0)
        ax.set_yscale("log")
        ax.set_title(f"{scene}, {n}x{n}x{n}", fontsize=10)
        ax.set_xlabel("|render-time error| vs exact mode (%)")
        bx.set_xlabel(f"balancing gain: time(none) / time({a.balance})")
        bx.set_yscale("log")
        for x in (ax, bx):
            x.grid(alpha=0.3, which="both")
            x.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            x.yaxis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        if col == 0:
            ax.set_ylabel("wall-clock time (s)")
            bx.set_ylabel("wall-clock time (s)")
            ax.legend(fontsize=7, loc="upper right")
            bx.legend(fontsize=7, loc="upper right")
    handles = [plt.Line2D([], [], color=c, marker="o", linestyle="", label=f"quantum {q}") for q, c in colours.items()
               if q in quanta]
    handles += [plt.Line2D([], [], color="grey", marker=m, linestyle="", label=f"{k} rays/message")
                for k, m in markers.items()]
    handles += [plt.Line2D([], [], color="grey", marker="o", linestyle="", label="filled: no balancing"),
                plt.Line2D([], [], color="grey", marker="o", markerfacecolor="none", linestyle="",
                           label=f"hollow: {a.balance}")]
    fig.legend(handles=handles, loc="lower center", ncol=6, fontsize=8)
    fig.suptitle("Speed against accuracy (red line: 1 % error). Top: wall time against render-time error; "
                 "bottom: against the balancing outcome", fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 0.97))
    outputs.savefig(fig, os.path.join(a.out, "speed_accuracy.png"), dpi=100)


def table(a, rows):
    """The Pareto fronts as a markdown table (doc/results/speed_accuracy.md)."""
    lines = ["<!-- written by scripts/experiments/speed_accuracy.py; do not edit -->",
             "| scene | N | balance | mode (quantum, rays/message) | wall (s) | speed-up vs exact | render-time error |"
             " balancing gain (exact mode's) |",
             "|---|---|---|---|---|---|---|---|"]
    for scene, n in sorted({(r["scene"], r["N"]) for r in rows}):
        for bal in ("none", a.balance):
            pts = [r for r in rows if r["scene"] == scene and r["N"] == n and r["balance"] == bal]
            if not pts:
                continue
            exact = next(r for r in pts if (r["quantum"], r["ray_batch"]) == EXACT)
            for p in pareto(pts):
                gain = "" if p["balance_gain"] is None else f"{p['balance_gain']:.3f} ({p['exact_balance_gain']:.3f})"
                lines.append(f"| {scene} | {n} | {bal} | {p['quantum']}, {p['ray_batch']} | {p['wall_s']:.2f} | "
                             f"{exact['wall_s'] / p['wall_s']:.2f} | {pct(p['error'])} | {gain} |")
    publish_table(lines, os.path.join(a.out, "speed_accuracy.md"), a.doc, "speed_accuracy table")


if __name__ == "__main__":
    sys.exit(outputs.guard("speed_accuracy.py", main))
