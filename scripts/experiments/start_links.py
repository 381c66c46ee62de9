#!/usr/bin/python3
"""Where the half start floods a link: Fig. 4's scene viewed across the
progress axis on the modern machine, the spheres crowded at one end, at
link speeds from 100 MB/s to 1 GB/s. Per point, `sample`'s first frame
against the unbalanced frame from three starts: --start-mix auto (which
weighs the half start's busiest link against the uniform split's frame,
balance/start_links.h), the half start given by hand (0.5) and the
uniform split (0); and the most primary rays one box generates at each
start. Across the axis a box's length is its share of the image: the
half start's long box generates that share, and its rays leave it on one
link (doc/balancing.md, "Where sample starts"). Every point is one rtsim
run through the sweep driver, so it runs locally or on a Dask cluster
and a stopped run resumes.

With --doc, writes doc/results/start_links.{csv,md} and the table into
doc/balancing.md. Standard library only; run with /usr/bin/python3."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # start_mix: against_none
import argparse  # noqa: E402
import outputs  # noqa: E402
import project  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import ROOT, VIEWS, preset_flags, publish_table  # noqa: E402
from start_mix import against_none  # noqa: E402

# The cases: f, N, image side (the random run's losses at 400 MB/s, doc/balancing.md).
CASES = "0.125:5:128,0.5:7:128,0.25:6:64"
LINKS = "100MB/s,200MB/s,300MB/s,400MB/s,600MB/s,800MB/s,1GB/s"
MIXES = ["auto", "0.5", "0"]
LOSS = 1.02  # a frame slower than the unbalanced one by more than 2 % loses (issue 61)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", default=CASES, help="f:N:side, comma-separated (the crowd, the mesh, the image)")
    ap.add_argument("--links", default=LINKS, help="link bandwidths (rtsim --link-bandwidth)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    cases = []
    for c in a.cases.split(","):
        parts = c.split(":")
        if len(parts) != 3:
            raise outputs.ToolError(f"--cases {c!r}: give f:N:side, for example 0.125:5:128")
        f = outputs.numbers(parts[0], "--cases (f)", kind=float, least=1e-6, most=1)[0]
        n = outputs.numbers(parts[1], "--cases (N)", least=2, most=32)[0]
        side = outputs.numbers(parts[2], "--cases (side)", least=1, most=4096)[0]
        cases.append((f, n, side))
    links = [b for b in a.links.split(",") if b]
    if not links:
        raise outputs.ToolError(f"--links {a.links!r}: give one bandwidth or more")
    csv_path = os.path.join(a.out, "start_links.csv")
    rows = driver.swept_rows(a, csv_path, lambda: sweep(a, cases, links))
    changed = project.changed_flags(ap, a, ("cases", "links"))
    table(rows, cases, links, changed, os.path.join(a.out, "start_links.md"), a.doc)


def case_name(f, n, side):
    return f"f = {f:g}, {n}x{n}x{n}, {side}x{side}"


def sweep(a, cases, links):
    points = []
    for f, n, side in cases:
        for bw in links:
            base = (preset_flags("modern") + ["--spheres", "1000", "--radius", "0.02", "--seed", "1", "--axis", "x",
                                              "--concentration", f"{f:g}", "--mesh", str(n),
                                              "--size", f"{side}x{side}", "--link-bandwidth", bw] + VIEWS["across"])
            params = {"case": case_name(f, n, side), "link": bw}
            points.append({"params": dict(params, policy="none", mix="-"), "args": base + ["--balance", "none"]})
            for mix in MIXES:
                points.append({"params": dict(params, policy="sample", mix=mix),
                               "args": base + ["--balance", "sample", "--start-mix", mix]})
    runs = driver.run("start-links", points, extract, None, a)
    return against_none(runs, ["case", "link", "policy", "mix"], keep=("chosen", "busiest_box_rays"))


def extract(r):
    return {"render_time_ns": r["render_time_ns"], "chosen": r["config"]["balance"]["start_mix"],
            "busiest_box_rays": max(n["counters"]["primary_rays"] for n in r["nodes"])}


def table(rows, cases, links, inv, md_path, doc):
    lines = [f"<!-- written by scripts/experiments/start_links.py{' ' + inv if inv else ''}; do not edit -->",
             "`sample`'s first frame / the unbalanced frame, from each start; in brackets, the most primary rays "
             f"one box generates (auto: the start it chose, 0 or 0.5). **Bold**: above {LOSS}.", "",
             "| case | start | " + " | ".join(links) + " |", "|---|---|" + "---:|" * len(links)]
    for f, n, side in cases:
        name = case_name(f, n, side)
        for mix in MIXES:
            cells = []
            for bw in links:
                r = next((r for r in rows if (r["case"], r["link"], r["mix"]) == (name, bw, mix)), None)
                if r is None:
                    cells.append("-")
                    continue
                ratio = float(r["ratio"])
                said = f"{float(r['chosen']):g}, " if mix == "auto" else ""
                cell = f"{ratio:.3f} ({said}{int(float(r['busiest_box_rays']))})"
                cells.append(f"**{cell}**" if ratio > LOSS else cell)
            start = "`--start-mix auto`" if mix == "auto" else f"`--start-mix {mix}`"
            lines.append(f"| {name} | {start} | " + " | ".join(cells) + " |")
    auto = [float(r["ratio"]) for r in rows if r["mix"] == "auto"]
    half = [float(r["ratio"]) for r in rows if r["mix"] == "0.5"]
    if auto:
        lines.append("")
        lines.append(f"`auto`: {sum(x > LOSS for x in auto)} of {len(auto)} first frames above {LOSS}, worst "
                     f"{max(auto):.3f}; the half start by hand: {sum(x > LOSS for x in half)} of {len(half)}, "
                     f"worst {max(half):.3f}.")
    publish_table(lines, md_path, doc, "start links")


if __name__ == "__main__":
    sys.exit(outputs.guard("start_links.py", main))
