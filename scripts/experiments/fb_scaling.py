#!/usr/bin/python3
"""Does the frame buffer scale with the mesh? rtsim's default experiment
(1,000 spheres crowded into the first quarter of x, 256x256, no balancing)
with the fastest links of the link sweep (10 ns, 100 GB/s), N = 2..8, with
one frame-buffer unit (the single host) and with the default 16. For each:
the render time, the busiest unit's busy time as a share of it, and the
busiest node's busy time, which no frame buffer can take off the frame.
With --doc, writes doc/results/fb_scaling.{csv,md} and the table in doc/machine.md.
Standard library only; run with /usr/bin/python3."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, publish_table  # noqa: E402
from csv_rows import read_csv  # noqa: E402

SCENE = PAPER_SCENE + ["--concentration", "0.25", "--link-latency", "10ns", "--link-bandwidth", "100GB/s"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="2,3,4,5,6,7,8")
    ap.add_argument("--units", default="1,16")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "machine.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    ns = outputs.numbers(a.n, "--n")
    units = outputs.numbers(a.units, "--units")
    csv_path = os.path.join(a.out, "fb_scaling.csv")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        points = [{"params": {"N": n, "units": k}, "args": SCENE + ["--mesh", n, "--fb-units", k]}
                  for k in units for n in ns]
        driver.run("fb_scaling", points, extract, csv_path, a)
    rows = read_csv(csv_path)
    for r in rows:
        r["N"], r["units"] = int(r["N"]), int(r["units"])
        for k in ("render_time_ns", "fb_busy_ns", "max_node_busy_ns"):
            r[k] = float(r[k])
    table(a, rows, ns, units)


def extract(r):
    return {"render_time_ns": r["render_time_ns"], "fb_busy_ns": r["frame_buffer"]["busy_ns"],
            "max_node_busy_ns": max(n["busy_ns"] for n in r["nodes"])}


def table(a, rows, ns, units):
    by = {(r["N"], r["units"]): r for r in rows}
    head = " | ".join(f"{k} unit{'s' if k > 1 else ''}: render time, frame buffer busy" for k in units)
    lines = ["<!-- written by scripts/experiments/fb_scaling.py; do not edit -->",
             f"| N | {head} | busiest node's busy time |",
             "|---:|" + "---|" * len(units) + "---:|"]
    for n in ns:
        cells = [f"{by[(n, k)]['render_time_ns'] / 1e3:.1f} us, {100 * by[(n, k)]['fb_busy_ns'] / by[(n, k)]['render_time_ns']:.1f} %"
                 for k in units]
        lines.append(f"| {n} | " + " | ".join(cells) + f" | {by[(n, units[-1])]['max_node_busy_ns'] / 1e3:.1f} us |")
    if 6 in ns and 8 in ns:
        lines.append("")
        for k in units:
            t6, t8 = by[(6, k)]["render_time_ns"], by[(8, k)]["render_time_ns"]
            lines.append(f"N = 8 against N = 6, {k} unit{'s' if k > 1 else ''}: {t8 / t6:.3f} of the time "
                         f"(the busiest node at N = 8 alone: {by[(8, k)]['max_node_busy_ns'] / t6:.3f}; "
                         f"node count alone: {(6 / 8) ** 3:.3f}).")
    publish_table(lines, os.path.join(a.out, "fb_scaling.md"), a.doc, "fb_scaling table")


if __name__ == "__main__":
    sys.exit(outputs.guard("fb_scaling.py", main))
