#!/usr/bin/python3
"""The link sweep at scale: how the links' bandwidth knee moves with the
mesh size N, on balls-5 (256x256 by default) with N x N x N meshes of
N = 8, 16 and 32 over a sweep of link bandwidths, without balancing (the
knee of the machine itself). Per N: the render time at each bandwidth, and
the bandwidths below which the frame takes 10 % longer and twice as long
as at the fastest links (the knees, interpolated in log bandwidth), with
the busiest link's utilisation at the fastest links. Through the sweep
driver, so it runs locally (--jobs) or on a Dask cluster (--dask). With
--doc, writes doc/results/links_at_scale.{csv,md,png} and the table into
doc/exploration.md. Run with /usr/bin/python3."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from plot_sweep import knee, quantity  # noqa: E402
from project import ROOT, SPD, publish_table  # noqa: E402
from csv_rows import read_csv  # noqa: E402

BANDWIDTHS = "50MB/s,100MB/s,200MB/s,400MB/s,1GB/s,4GB/s,16GB/s"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="balls-5")
    ap.add_argument("--n", default="8,16,32")
    ap.add_argument("--bandwidths", default=BANDWIDTHS)
    ap.add_argument("--size", default="256x256")
    ap.add_argument("--extra", default="", help="more rtsim flags for every run")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "exploration.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    csv_path = os.path.join(a.out, "links_at_scale.csv")
    outputs.numbers(a.n, "--n")
    outputs.check_input(os.path.join(SPD, outputs.check_name(a.scene, "--scene") + ".nff"), "--scene")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        points = []
        for n in a.n.split(","):
            for bw in a.bandwidths.split(","):
                points.append({"params": {"N": int(n), "link-bandwidth": bw},
                               "args": ["--scene", os.path.join(SPD, a.scene + ".nff"), "--size", a.size, "--mesh", n,
                                        "--link-bandwidth", bw, "--balance", "none"] + a.extra.split()})
        driver.run("links-at-scale", points, extract, csv_path, a)
    rows = read_csv(csv_path)
    table(a, rows, os.path.join(a.out, "links_at_scale.md"))
    chart(a, rows, os.path.join(a.out, "links_at_scale.png"))


def extract(r):
    busiest = max((l for l in r["links"] if l.get("to") != "fb"), key=lambda l: l["utilisation"], default=None)
    return {"render_time_ns": r["render_time_ns"],
            "busiest_link": busiest["name"] if busiest else "",
            "busiest_link_utilisation": busiest["utilisation"] if busiest else 0}


def by_n(rows):
    out = {}
    for r in rows:
        out.setdefault(int(r["N"]), []).append((quantity(r["link-bandwidth"]), r))
    return {n: sorted(v, key=lambda p: p[0]) for n, v in sorted(out.items())}


def table(a, rows, md_path):
    lines = ["<!-- written by scripts/experiments/links_at_scale.py; do not edit -->",
             f"{a.scene} at {a.size}, no balancing; render time against the links' bandwidth per mesh size; the "
             "knees: the bandwidth below which the frame takes 1.1 x and 2 x its time at the fastest links "
             "(interpolated in log bandwidth).",
             "",
             "| N | nodes | " + " | ".join(a.bandwidths.split(",")) + " | 1.1 x below | 2 x below | "
             "busiest link at the fastest |",
             "|---:|---:|" + "---:|" * len(a.bandwidths.split(",")) + "---:|---:|---|"]
    for n, pts in by_n(rows).items():
        xs = [x for x, _ in pts]
        ys = [float(r["render_time_ns"]) for _, r in pts]
        # The knees are measured from the time at the fastest links (the
        # last point), as the table says, not from the line's best point.
        fast, at = ys[-1], len(ys) - 1
        k1, k2 = knee(xs, ys, 1.1 * fast, True, start=at), knee(xs, ys, 2 * fast, True, start=at)
        fastest = pts[-1][1]
        lines.append(f"| {n} | {n ** 3:,} | " + " | ".join(f"{y / 1e6:.3f} ms" for y in ys) +
                     f" | {rate(k1)} | {rate(k2)} | {fastest['busiest_link']} "
                     f"{float(fastest['busiest_link_utilisation']) * 100:.0f} % |")
    publish_table(lines, md_path, a.doc or None, "links at scale")


def rate(x):
    if x is None or not math.isfinite(x):
        return "-"
    return f"{x / 1e9:.2f} GB/s" if x >= 1e9 else f"{x / 1e6:.0f} MB/s"


def chart(a, rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for n, pts in by_n(rows).items():
        xs = [x for x, _ in pts]
        ys = [float(r["render_time_ns"]) for _, r in pts]
        ax.plot(xs, [y / min(ys) for y in ys], marker="o", label=f"N = {n} ({n ** 3:,} nodes)")
    ax.axhline(1.1, color="grey", linestyle=":", linewidth=1)
    ax.axhline(2, color="grey", linestyle=":", linewidth=1)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("link bandwidth (bytes/s)")
    ax.set_ylabel("render time / at the fastest links")
    ax.set_title(f"{a.scene} at {a.size}, no balancing")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    outputs.savefig(fig, path, dpi=110)


if __name__ == "__main__":
    sys.exit(outputs.guard("links_at_scale.py", main))
