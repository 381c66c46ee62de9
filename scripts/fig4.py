#!/usr/bin/python3
"""The paper's Fig. 4: image generation time with sliding-boundary balancing
divided by the time without, against the fraction f of the space the spheres
crowd into (1/N .. 1), one line per N, for a view along the progress axis and
one across it. Writes doc/results/fig4.csv and doc/results/fig4.png.
Needs python3-matplotlib (bash scripts/setup.sh plots); run with /usr/bin/python3."""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sweep as driver  # noqa: E402
from sweep import ROOT, write_csv  # noqa: E402

# The experiment's settings (doc/balancing.md, "Fig. 4"): the procedural scene,
# progress axis x; the camera either looks along x or across it (along y).
SCENE = ["--spheres", "1000", "--radius", "0.02", "--size", "256x256", "--axis", "x", "--seed", "1"]
VIEWS = {
    "along": ["--eye=-1.3,0.5,0.5", "--look-at=0.5,0.5,0.5", "--fov", "50"],
    "across": ["--eye=0.5,-1.6,0.5", "--look-at=0.5,0.5,0.5", "--fov", "40"],
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="2,3,4,5,6")
    ap.add_argument("--policy", default="slide", help="balancing policy compared with none")
    ap.add_argument("--interval", default="5us")
    ap.add_argument("--gain", default="0.25")
    ap.add_argument("--extra", default="", help="more rtsim flags for every run")
    driver.add_output_arguments(ap)
    driver.add_arguments(ap)
    a = ap.parse_args()
    ns = [int(x) for x in a.n.split(",")]
    if not a.plot_only:
        sweep(a, ns)
    plot(a, ns)


def sweep(a, ns):
    points = []
    for view, cam in VIEWS.items():
        for n in ns:
            for k in range(1, n + 1):
                f = k / n
                for policy in ("none", a.policy):
                    points.append({"params": {"view": view, "N": n, "f": round(f, 6), "policy": policy},
                                   "args": SCENE + cam + ["--mesh", n, "--concentration", f"{f:.6f}",
                                                          "--balance", policy, "--balance-interval", a.interval,
                                                          "--gain", a.gain] + a.extra.split()})
    runs = driver.run("fig4", points, extract, None, a)
    by = {(r["view"], r["N"], r["f"], r["policy"]): r for r in runs}
    rows = []
    for view in VIEWS:
        for n in ns:
            for k in range(1, n + 1):
                f = round(k / n, 6)
                r0, r1 = by[(view, n, f, "none")], by[(view, n, f, a.policy)]
                rows.append({"view": view, "N": n, "f": f, "time_none_ns": r0["render_time_ns"],
                             "time_balanced_ns": r1["render_time_ns"],
                             "ratio": r1["render_time_ns"] / r0["render_time_ns"], "slides": r1["slides"],
                             "max_over_mean_load": r1["max_over_mean_load"], "stability": r1["stability"],
                             "version": r1["version"], "command_balanced": r1["command"]})
    write_csv(os.path.join(a.out, "fig4.csv"), rows)


def extract(r):
    b = r["balance"]
    return {"render_time_ns": r["render_time_ns"], "slides": b["slides"],
            "max_over_mean_load": b["max_over_mean_load"], "stability": b["stability"]}


def plot(a, ns):
    with open(os.path.join(a.out, "fig4.csv")) as f:
        rows = [dict(r, N=int(r["N"]), f=float(r["f"]), ratio=float(r["ratio"]),
                     max_over_mean_load=float(r["max_over_mean_load"])) for r in csv.DictReader(f)]

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    for ax, view in zip(axes, VIEWS):
        for n in ns:
            pts = [(r["f"], r["ratio"]) for r in rows if r["view"] == view and r["N"] == n]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=f"N = {n}")
        ax.axhline(0.2, color="grey", linestyle=":", linewidth=1)
        ax.annotate("paper: about 0.2 at f = 1/N", (0.02, 0.22), color="grey", fontsize=9)
        ax.set_title(f"view {view} the progress axis")
        ax.set_xlabel("fraction f of the space holding the spheres")
        ax.set_xlim(0, 1.05)
        ax.set_ylim(0, 1.3)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(f"time with balancing ({a.policy}) / time without")
    axes[1].legend(loc="lower right")
    fig.suptitle("Fig. 4 reproduced: procedural scene, %s spheres, %s, interval %s, gain %s"
                 % (SCENE[1], SCENE[5], a.interval, a.gain), fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "fig4.png"), dpi=110)
    for r in rows:
        if abs(r["f"] - 1 / r["N"]) < 1e-6:
            print(f"{r['view']:6s} N={r['N']} f=1/N: ratio {r['ratio']:.3f} (max/mean load {r['max_over_mean_load']:.2f})")


if __name__ == "__main__":
    main()
