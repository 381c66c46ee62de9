#!/usr/bin/python3
"""Would faces that stay in line stop `slide` from losing? Each Fig. 4 point
(modern machine) where `slide`'s first frame loses more than 2 % in
doc/results/fig4.csv, and the points where it gains most, rendered without
balancing, with `slide` (each column moves its own faces) and with `slide
--faces ideal-layer` (faces shared by a layer, moved by the paper's rule on
the layer's summed loads, read without messages: an optimistic bound on any
layer agreement built from messages; models/balance/ideal_layer_faces.h). Reports
the ratios to the unbalanced frame, the busy time, the rays passed on
untraced between columns and the slides. With --doc, writes
doc/results/aligned_faces.{csv,md} and the table into doc/fig4.md.
Run with /usr/bin/python3."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, VIEWS, publish_table  # noqa: E402
from csv_rows import read_csv  # noqa: E402
from sweep_driver import write_csv  # noqa: E402

# Where `slide` gains most (f = 1/N along the axis, and the view across at
# N = 4): what the shared planes cost where balancing works.
GAINING = [("along", 4, 1 / 4), ("along", 5, 1 / 5), ("along", 8, 1 / 8), ("across", 4, 1 / 4)]
RUNS = {"none": ["--balance", "none"], "slide": ["--balance", "slide"],
        "ideal-layer": ["--balance", "slide", "--faces", "ideal-layer"]}


def losing_points(fig4_csv, worse):
    """The (view, N, f) where slide's first frame took more than `worse` x the unbalanced one."""
    return [(r["view"], int(r["N"]), float(r["f"])) for r in read_csv(fig4_csv)
            if r["policy"] == "slide" and r["preset"] == "modern" and float(r["ratio"]) > worse]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fig4", default=os.path.join(ROOT, "doc", "results", "fig4.csv"),
                    help="Fig. 4's results, for the points where slide loses")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "fig4.md"), plot_only=False)  # (it cannot redraw from a CSV)
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    losing = losing_points(outputs.check_input(a.fig4, "--fig4"), 1.02)
    if not losing:
        raise outputs.ToolError(f"no point of {a.fig4} where slide loses more than 2 %")
    chosen = [(p, "gains") for p in GAINING] + [(p, "loses") for p in losing]
    points = [{"params": {"view": v, "N": n, "f": round(f, 6), "run": run},
               "args": PAPER_SCENE + VIEWS[v] + ["--mesh", n, "--concentration", f"{f:.6f}"] + flags}
              for (v, n, f), _ in chosen for run, flags in RUNS.items()]
    got = driver.run("aligned_faces", points, extract, None, a)
    by = {(r["view"], r["N"], r["f"], r["run"]): r for r in got}
    rows, lines = [], ["<!-- written by scripts/experiments/aligned_faces.py; do not edit -->",
                       "| Fig. 4 point | slide there | slide / none | ideal layer / none | busy, slide / none | "
                       "ideal layer | passed between columns, slide | ideal layer | slides, slide | ideal layer |",
                       "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for (v, n, f), what in chosen:
        r = {run: by[(v, n, round(f, 6), run)] for run in RUNS}
        none, sl, il = r["none"], r["slide"], r["ideal-layer"]
        ratio = {k: r[k]["render_time_ns"] / none["render_time_ns"] for k in ("slide", "ideal-layer")}
        busy = {k: r[k]["busy_ns"] / none["busy_ns"] for k in ("slide", "ideal-layer")}
        rows.append({"view": v, "N": n, "f": round(f, 6), "slide_there": what, "none_ns": none["render_time_ns"],
                     "slide_ns": sl["render_time_ns"], "ideal_layer_ns": il["render_time_ns"],
                     "busy_none_ns": none["busy_ns"], "busy_slide_ns": sl["busy_ns"], "busy_ideal_layer_ns": il["busy_ns"],
                     "passed_between_slide": sl["passed_between"], "passed_between_ideal_layer": il["passed_between"],
                     "slides_slide": sl["slides"], "slides_ideal_layer": il["slides"], "version": il["version"]})
        lines.append(f"| {v}, N = {n}, f = {f:.3g} | {what} | {ratio['slide']:.3f} | {ratio['ideal-layer']:.3f} | "
                     f"{busy['slide']:.3f} | {busy['ideal-layer']:.3f} | {sl['passed_between']:,} | "
                     f"{il['passed_between']:,} | {sl['slides']:,} | {il['slides']:,} |")
    lost = [row for row in rows if row["slide_there"] == "loses"]
    still = sum(row["ideal_layer_ns"] > 1.02 * row["none_ns"] for row in lost)
    lines.append("")
    lines.append(f"Of the {len(lost)} points where `slide` loses more than 2 %, the ideal layer's faces still lose "
                 f"more than 2 % at {still}.")
    write_csv(os.path.join(a.out, "aligned_faces.csv"), rows)
    publish_table(lines, os.path.join(a.out, "aligned_faces.md"), a.doc or None, "aligned faces")


def extract(r):
    t = r["totals"]
    return {"render_time_ns": r["render_time_ns"], "busy_ns": t["busy_ns"],
            "passed_between": t["rays_passed_between_columns"], "slides": r["balance"].get("slides", 0)}


if __name__ == "__main__":
    sys.exit(outputs.guard("aligned_faces.py", main))
