#!/usr/bin/python3
"""The paper's Fig. 4 against its bounds: image generation time with balancing
divided by the time without, against the fraction f of the space the spheres
crowd into (1/N .. 1), per mesh size N, for a view along the progress axis
and one across it. Each panel shows every policy (the static object-median
split and the dynamic ones), the column bound of the unbalanced run (the best
any balancer that slides boundaries along one axis could do with its work),
1/N, and the paper's 0.2. The --steady policies also have their
steady-state curves: the last of --frames frames of the same view, each
starting with the boundaries where the one before ended (rtsim --frames);
`resplit` re-splits its columns between frames.

Runs on a machine preset (--preset: configs/NAME.conf; modern is rtsim's
defaults) with the project's default balancing settings. With --doc, writes
doc/results/fig4[-PRESET].{csv,png,md} and the f = 1/N table into
doc/fig4.md. Needs python3-matplotlib (bash scripts/setup.sh plots);
run with /usr/bin/python3."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import project  # noqa: E402
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, VIEWS, check_variant, invocation, machine, preset_flags, publish_table, variant  # noqa: E402,E501

# The experiment (doc/balancing.md, "Fig. 4"): the paper's scene, progress
# axis x, the camera looking along x or across it (project.VIEWS).
POLICIES = "median,slide,sample,work"
STEADY = "slide,resplit,measured"  # their steady state too: "resplit@6" is resplit's frame 6
FRAMES = 6  # frames of a steady-state sequence (--frames)
PAPER = 0.2
# The policies whose steady state the gap table takes apart, the first of
# them run: measured (the between-frames policy), else sample (the
# recommended one on Fig. 4's columns of 2 to 8 boxes: `--policies sample
# --steady sample --tag recommended`).
STEADY_GAP = ("measured", "sample")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="2,3,4,5,6,7,8")
    ap.add_argument("--policies", default=POLICIES, help="policies compared with none")
    project.add_machine_arguments(ap, "modern", "fig4")
    ap.add_argument("--steady", default=STEADY, help="policies whose steady state is drawn too ('': none)")
    ap.add_argument("--frames", type=int, default=FRAMES, help="frames of the steady-state curves (the last is plotted)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "fig4.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    ns = outputs.numbers(a.n, "--n", least=2, most=32)  # (nodes per axis: a column has a plane; rtsim --mesh: at most 32)
    check_variant(a)
    policies = a.policies.split(",")
    if a.steady and a.frames > 1:
        policies += [f"{p}@{a.frames}" for p in a.steady.split(",")]
    stem = "fig4" + variant(a.preset, a.tag)
    csv_path = os.path.join(a.out, stem + ".csv")
    rows = driver.swept_rows(a, csv_path, lambda: sweep(a, ns, policies))
    for r in rows:
        r["N"] = int(r["N"])
        for k in ("f", "ratio", "column_bound", "perfect_bound", "fb_bound", "time_none_ns", "time_ns", "busy_ratio",
                  "own_column_bound", "max_busy"):
            r[k] = float(r[k])
    plot(a, rows, ns, policies, os.path.join(a.out, stem + ".png"))
    table(a, rows, ns, policies, os.path.join(a.out, stem + ".md"))
    frames_table(a, rows, policies, os.path.join(a.out, stem + "-frames.md"))
    gap = next((g for g in STEADY_GAP if f"{g}@{a.frames}" in policies), None)
    if gap:
        gap_table(a, rows, ns, f"{gap}@{a.frames}", os.path.join(a.out, stem + "-gap.md"))


def sweep(a, ns, policies):
    points = []
    for view, cam in VIEWS.items():
        for n in ns:
            for k in range(1, n + 1):
                for policy in ["none"] + policies:
                    name, _, frames = policy.partition("@")
                    points.append({"params": {"view": view, "N": n, "f": round(k / n, 6), "policy": policy},
                                   "args": preset_flags(a.preset) + PAPER_SCENE + cam +
                                   ["--mesh", n, "--concentration", f"{k / n:.6f}", "--balance", name] +
                                   (["--frames", frames] if frames else []) + a.extra.split()})
    runs = driver.run("fig4" + (variant(a.preset, a.tag) or "-modern"), points, extract, None, a)
    by = {(r["view"], r["N"], r["f"], r["policy"]): r for r in runs}
    rows = []
    for view in VIEWS:
        for n in ns:
            for k in range(1, n + 1):
                f = round(k / n, 6)
                none = by[(view, n, f, "none")]
                for policy in policies:
                    r = by[(view, n, f, policy)]
                    rows.append({"preset": a.preset, "view": view, "N": n, "f": f, "policy": policy,
                                 "time_none_ns": none["render_time_ns"], "time_ns": r["render_time_ns"],
                                 "ratio": r["render_time_ns"] / none["render_time_ns"],
                                 # the unbalanced run's bounds, as fractions of its time
                                 "column_bound": none["column_bound"], "perfect_bound": none["perfect_bound"],
                                 "fb_bound": none["fb_bound"], "slides": r["slides"],
                                 # work the balancing added: total node busy time, against none's
                                 "busy_ratio": r["busy_ns"] / none["busy_ns"],
                                 # the balanced run's own column bound, as a fraction of none's time:
                                 # what sliding could reach with the work this run did
                                 "own_column_bound": r["column_bound"] * r["render_time_ns"] / none["render_time_ns"],
                                 # its busiest node's busy time, as a fraction of none's time: what is
                                 # left beyond it is waiting (fill and drain)
                                 "max_busy": r["max_busy_ns"] / none["render_time_ns"],
                                 "max_over_mean_load": r["max_over_mean_load"], "stability": r["stability"],
                                 "frames_ns": r["frames_ns"], "settled": r["settled"],
                                 "version": r["version"], "command": r["command"]})
    return rows


def extract(r):
    b, bd = r["balance"], r["bounds"]
    return {"render_time_ns": r["render_time_ns"], "slides": b["slides"],
            "max_over_mean_load": b["max_over_mean_load"], "stability": b["stability"],
            "column_bound": bd["column"]["fraction"], "perfect_bound": bd["perfect"]["fraction"],
            "fb_bound": bd["frame_buffer"]["fraction"], "busy_ns": r["totals"]["busy_ns"],
            "max_busy_ns": max(n["busy_ns"] for n in r["nodes"]),
            # a sequence of frames (rtsim --frames): each frame's render time, and whether the last two agree
            # within 1 % (settled)
            "frames_ns": " ".join(f"{f['render_time_ns']:.0f}" for f in r.get("frames", [])),
            "settled": (abs(r["frames"][-1]["render_time_ns"] - r["frames"][-2]["render_time_ns"]) <=
                        0.01 * r["frames"][-2]["render_time_ns"]) if len(r.get("frames", [])) > 1 else ""}


def plot(a, rows, ns, policies, path):
    plt = project.pyplot()
    colours = {"median": "#7a7a7a", "slide": "#1f77b4", "work": "#d62728", "resplit": "#2a9d55",
               "quantile": "#9467bd", "measured": "#e07b00", "sample": "#8c564b"}
    fig, axes = plt.subplots(len(VIEWS), len(ns), figsize=(2.6 * len(ns) + 1, 2.7 * len(VIEWS) + 0.8),
                             sharey=True, squeeze=False)
    for row, view in enumerate(VIEWS):
        for col, n in enumerate(ns):
            ax = axes[row][col]
            pts = sorted((r for r in rows if r["view"] == view and r["N"] == n), key=lambda r: r["f"])
            fs = sorted({r["f"] for r in pts})
            for p in policies:
                ys = [next(r["ratio"] for r in pts if r["f"] == f and r["policy"] == p) for f in fs]
                name, _, frames = p.partition("@")
                ax.plot(fs, ys, marker="o" if not frames else "x", markersize=3, color=colours.get(name),
                        linestyle="--" if frames else "-", label=f"{name}, frame {frames} (steady)" if frames else p)
            bound = [next(r["column_bound"] for r in pts if r["f"] == f) for f in fs]
            ax.plot(fs, bound, "k--", linewidth=1, label="column bound (unbalanced run)")
            ax.axhline(1 / n, color="green", linestyle=":", linewidth=1, label="1/N")
            ax.axhline(PAPER, color="grey", linestyle="-.", linewidth=1, label="paper: about 0.2 at f = 1/N")
            ax.axhline(1.0, color="black", linewidth=0.5)
            ax.set_xlim(0, 1.05)
            ax.set_ylim(0, 1.4)
            ax.grid(alpha=0.3)
            ax.set_title(f"N = {n}, view {view}", fontsize=9)
            if row == len(VIEWS) - 1:
                ax.set_xlabel("f", fontsize=9)
        axes[row][0].set_ylabel("time / time without", fontsize=9)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=9)
    fig.suptitle(f"Fig. 4 against its bounds, preset {machine(a)}: 1,000 spheres crowded into the first f of x, "
                 f"256x256, default balancing settings", fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 0.95))
    outputs.savefig(fig, path, dpi=90)


def written_by(a):
    """The flags of this run, for a table's "written by" line: the
    machine's, and those of the policies and frames where not the defaults."""
    flags = [invocation(a)]
    flags += [f"--policies {a.policies}"] if a.policies != POLICIES else []
    flags += [f"--steady {a.steady}"] if a.steady != STEADY else []
    flags += [f"--frames {a.frames}"] if a.frames != FRAMES else []
    return " ".join(flags)


def table(a, rows, ns, policies, md_path):
    """The f = 1/N points: every policy's ratio beside the bounds and the
    best static split where searched, and for the paper's rule (slide) the
    work it added and its own column bound."""
    head = " | ".join(policies)
    best = project.best_static(a)
    main = "slide" if "slide" in policies else policies[0]
    lines = [f"<!-- written by scripts/experiments/fig4.py {written_by(a)}; do not edit -->",
             f"| view | N | {head} | best static split | column bound | perfect bound | frame buffer | 1/N | paper | "
             f"{main}: busy time added | {main}: its own column bound |",
             "|---|---:|" + "---:|" * (len(policies) + 8)]
    for view in VIEWS:
        for n in ns:
            at = [r for r in rows if r["view"] == view and r["N"] == n and abs(r["f"] - 1 / n) < 1e-6]
            ratio = {r["policy"]: r["ratio"] for r in at}
            m = next(r for r in at if r["policy"] == main)
            b = best.get((view, n), (None, None))[0]
            lines.append(f"| {view} | {n} | " + " | ".join(f"{ratio[p]:.2f}" for p in policies) +
                         f" | {f'{b:.2f}' if b else '-'} | {at[0]['column_bound']:.2f} | {at[0]['perfect_bound']:.2f} | {at[0]['fb_bound']:.3f}"
                         f" | {1 / n:.2f} | {PAPER} | {100 * (m['busy_ratio'] - 1):+.0f} % | {m['own_column_bound']:.2f} |")
    doc = a.doc if a.doc else None
    publish_table(lines, md_path, doc, f"fig4 table {machine(a)}")


def frames_table(a, rows, policies, md_path):
    """Over every point (both views, every N and f): how often each policy
    loses more than 2 % against the unbalanced frame, in its last frame and
    in any frame of its sequence, and its worst frame."""
    lines = [f"<!-- written by scripts/experiments/fig4.py {written_by(a)}; do not edit -->",
             "| policy | points | last frame above 1.02 | worst last frame | any frame above 1.02 | worst frame, where |",
             "|---|---:|---:|---:|---:|---|"]
    for p in policies:
        rs = [r for r in rows if r["policy"] == p]
        seqs = [([float(x) / r["time_none_ns"] for x in str(r["frames_ns"]).split()] or [r["ratio"]], r) for r in rs]
        worst, at = max(((max(x), r) for x, r in seqs), key=lambda w: w[0])
        frame = next(k for k, x in enumerate(next(x for x, r in seqs if r is at)) if x == worst) + 1
        lines.append(f"| {p} | {len(rs)} | {sum(1 for r in rs if r['ratio'] > 1.02)} | {max(r['ratio'] for r in rs):.3f} | "
                     f"{sum(1 for x, r in seqs if max(x) > 1.02)} | {worst:.3f} ({at['view']}, N = {at['N']}, "
                     f"f = {at['f']:.3g}, frame {frame}) |")
    publish_table(lines, md_path, a.doc or None, f"fig4 frames {machine(a)}")


def gap_table(a, rows, ns, policy, md_path):
    """Where the distance from 1/N goes, at f = 1/N, for `policy`'s steady
    state, as fractions of the unbalanced frame: the perfect bound (all the
    work over all the nodes), what the columns' unequal loads add (the
    column bound of the unbalanced work), the work balancing adds (thin
    boxes: more hops, passed rays, slabs; the column bound of the work it
    did), the imbalance left within the columns (its busiest node's busy
    time), and fill and drain (the busiest node's waiting). The parts sum
    to the ratio; the best static split beside it where searched, with
    its own busiest node where the search recorded it (a split with a
    busier busiest node can still make the shorter frame: it waits less)."""
    best = project.best_static(a)
    lines = [f"<!-- written by scripts/experiments/fig4.py {written_by(a)}; do not edit -->",
             f"| view | N | 1/N | perfect bound | + unequal columns | + work balancing added | + imbalance left | "
             f"+ fill and drain | = {policy} | best static split | its busiest node | "
             f"{policy} / max(1/N, best static) |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for view in VIEWS:
        for n in ns:
            r = next(x for x in rows if x["view"] == view and x["N"] == n and abs(x["f"] - 1 / n) < 1e-6
                     and x["policy"] == policy)
            perfect, column, own, busiest, ratio = (r["perfect_bound"], r["column_bound"], r["own_column_bound"],
                                                    r["max_busy"], r["ratio"])
            b, its = best.get((view, n), (None, None))
            floor = max(1 / n, b) if b else 1 / n
            lines.append(f"| {view} | {n} | {1 / n:.3f} | {perfect:.3f} | {column - perfect:+.3f} | {own - column:+.3f} | "
                         f"{busiest - own:+.3f} | {ratio - busiest:+.3f} | {ratio:.3f} | "
                         f"{f'{b:.3f}' if b else '-'} | {f'{its:.3f}' if its else '-'} | {ratio / floor:.2f} |")
    publish_table(lines, md_path, a.doc or None, f"fig4 gap {machine(a)}")


if __name__ == "__main__":
    sys.exit(outputs.guard("fig4.py", main))
