#!/usr/bin/python3
"""Stability map of the sliding-boundary balancing: gain x balancing
interval, at two link latencies, on the paper's experiment at rtsim's
defaults (1,000 spheres crowded into the first quarter of x, 4x4x4 mesh).
Each point is judged converged, oscillating or diverging from its boundaries'
movement after the transient (the report's balance.stability, computed by
models/analysis/stability.cpp). With --doc, writes doc/results/stability[-PRESET].csv and .png;
--preset transputer-1987 maps the 1987 machine (intervals in ms, its link
latency and 30 times it). `resplit` balances a frame as `slide` does, so
this map is its within-frame map too; its between-frame behaviour is in
Fig. 4's steady-state curves.
Needs python3-matplotlib (bash scripts/setup.sh plots); run with /usr/bin/python3."""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import project  # noqa: E402
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, preset_flags  # noqa: E402

DEFAULT_GAIN = 0.25  # models/config/machine_config.h
# Per preset: the default interval (us), the swept intervals and latencies.
PRESETS = {
    "modern": {"interval_us": 20, "intervals_us": "2,5,10,20,50", "latencies": "100ns,2us"},
    "transputer-1987": {"interval_us": 34000, "intervals_us": "3400,8500,17000,34000,85000",
                        "latencies": "1.5us,45us"},
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--gains", default="0.0625,0.125,0.25,0.5,1,2,4")
    ap.add_argument("--preset", default="modern", choices=sorted(PRESETS), help="configs/PRESET.conf")
    ap.add_argument("--intervals-us", help="swept intervals (default: the preset's)")
    ap.add_argument("--latencies", help="swept link latencies (default: the preset's)")
    ap.add_argument("--policy", default="slide")
    driver.add_output_arguments(ap)
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    p = PRESETS[a.preset]
    a.intervals_us = a.intervals_us or p["intervals_us"]
    a.latencies = a.latencies or p["latencies"]
    a.default_interval_us = p["interval_us"]
    a.stem = "stability" if a.preset == "modern" else f"stability-{a.preset}"
    gains = outputs.numbers(a.gains, "--gains", float)
    intervals = outputs.numbers(a.intervals_us, "--intervals-us", float)
    lats = a.latencies.split(",")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(os.path.join(a.out, a.stem + ".csv"), "--plot-only: the CSV")
    else:
        sweep(a, gains, intervals, lats)
    plot(a, lats)


def sweep(a, gains, intervals, lats):
    points = [{"params": {"latency": lat, "gain": g, "interval_us": iv},
               "args": preset_flags(a.preset) + PAPER_SCENE + ["--concentration", "0.25", "--balance", a.policy,
                        "--gain", g, "--balance-interval", f"{iv}us", "--link-latency", lat]}
              for lat in lats for g in gains for iv in intervals]
    driver.run(a.stem, points, extract, os.path.join(a.out, a.stem + ".csv"), a)


def extract(r):
    b = r["balance"]
    return {"stability": b["stability"], "slides": b["slides"], "render_time_ns": r["render_time_ns"],
            "max_over_mean_load": b["max_over_mean_load"], "oscillating": b["boundaries_oscillating"],
            "diverging": b["boundaries_diverging"]}


def plot(a, lats):
    with open(os.path.join(a.out, a.stem + ".csv")) as f:
        rows = [dict(r, gain=float(r["gain"]), interval_us=float(r["interval_us"]),
                     render_time_ns=float(r["render_time_ns"])) for r in csv.DictReader(f)]
    plt = project.pyplot()
    colour = {"converged": "#2a9d55", "oscillating": "#e9a23b", "diverging": "#d1495b"}
    fig, axes = plt.subplots(1, len(lats), figsize=(5.2 * len(lats), 4.4), sharey=True)
    axes = axes if len(lats) > 1 else [axes]
    slow = max(r["render_time_ns"] for r in rows) > 1e8  # the 1987 machine's frames last seconds
    scale, unit = (1e6, "ms") if slow else (1e3, "us")
    for ax, lat in zip(axes, lats):
        for cls, c in colour.items():
            pts = [r for r in rows if r["latency"] == lat and r["stability"] == cls]
            ax.scatter([r["interval_us"] for r in pts], [r["gain"] for r in pts], s=260, c=c, marker="s", label=cls)
        for r in rows:
            if r["latency"] == lat:
                ax.annotate(f"{r['render_time_ns'] / scale:.0f}", (r["interval_us"], r["gain"]), ha="center",
                            va="center", fontsize=6, color="white")
        ax.scatter([a.default_interval_us], [DEFAULT_GAIN], s=600, facecolors="none", edgecolors="black", linewidths=1.5,
                   label="default")
        ax.set_xscale("log")
        ax.set_yscale("log", base=2)
        ax.set_xlabel("balancing interval (us)")
        ax.set_title(f"link latency {lat}")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("gain")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8, markerscale=0.5)
    fig.suptitle(f"Stability of '{a.policy}', preset {a.preset} (numbers: render time in {unit}); rtsim default scene, "
                 "4x4x4", fontsize=10)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    outputs.savefig(fig, os.path.join(a.out, a.stem + ".png"), dpi=110)
    for r in rows:
        if r["gain"] == DEFAULT_GAIN and r["interval_us"] == a.default_interval_us:
            print(f"default at latency {r['latency']}: {r['stability']}")


if __name__ == "__main__":
    sys.exit(outputs.guard("stability_map.py", main))
