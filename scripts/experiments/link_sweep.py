#!/usr/bin/python3
"""Link-speed exploration: sweeps link latency and link bandwidth over
several decades (one at a time, the other at its default) for N = 2..8, with
and without balancing, on rtsim's default experiment (1,000 spheres crowded
into the first quarter of x, 256x256), on a machine preset (--preset:
configs/NAME.conf; the sweep spans the same decades around the preset's own
link). Charts render time, speed-up over one node and balancing gain; finds
the knee where links start to dominate. With --doc, writes
doc/results/link_sweep[-PRESET].{csv,png,md}.

Knee: the link speed at which the render time has doubled from its value
with the fastest links (links then take as long as everything else), found
by log-log interpolation between swept points; also where it has grown by
10 % (links start to matter). The latency sweep is repeated with deeper
links (--deep-depth, without balancing) to show what sets the latency knee.
Needs python3-matplotlib (bash scripts/setup.sh plots); run with
/usr/bin/python3."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import project  # noqa: E402
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, preset_flags, publish_table  # noqa: E402
from csv_rows import read_csv  # noqa: E402
from sweep_driver import write_csv  # noqa: E402

SCENE = PAPER_SCENE + ["--concentration", "0.25"]
# Per preset (configs/NAME.conf): its link, and the swept values around it:
# latency from a tenth to a thousand times the preset's, bandwidth from a
# hundredth to a hundred times, in half decades; the deep-link repeat at four
# times the preset's depth.
PRESETS = {
    "modern": {"latency": "100ns", "bandwidth": "1GB/s", "depth": 16,
               "latencies": "10ns,30ns,100ns,300ns,1us,3us,10us,30us,100us",
               "bandwidths": "10MB/s,30MB/s,100MB/s,300MB/s,1GB/s,3GB/s,10GB/s,30GB/s,100GB/s"},
    "transputer-1987": {"latency": "1.5us", "bandwidth": "1.2MB/s", "depth": 2,
                        "latencies": "150ns,450ns,1.5us,4.5us,15us,45us,150us,450us,1500us",
                        "bandwidths": "12KB/s,36KB/s,120KB/s,360KB/s,1.2MB/s,3.6MB/s,12MB/s,36MB/s,120MB/s"},
}
UNITS = {"ps": 1e-12, "ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0,
         "B/s": 1.0, "KB/s": 1e3, "MB/s": 1e6, "GB/s": 1e9}


def value(s):
    """'300ns' -> 3e-7 (seconds), '10GB/s' -> 1e10 (bytes per second)."""
    for u in sorted(UNITS, key=len, reverse=True):
        if s.endswith(u):
            return float(s[: -len(u)]) * UNITS[u]
    raise ValueError(s)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="2,3,4,5,6,7,8")
    ap.add_argument("--preset", default="modern", choices=sorted(PRESETS), help="configs/PRESET.conf")
    ap.add_argument("--latencies", help="swept latencies (default: the preset's)")
    ap.add_argument("--bandwidths", help="swept bandwidths (default: the preset's)")
    ap.add_argument("--balance", default="measured", help="the balancing policy compared with none (default: measured, the between-frames policy the tables were made with)")
    ap.add_argument("--frames", type=int, default=6,
                    help="its steady state too: the last of this many frames (1: the first frame only)")
    ap.add_argument("--deep-depth", type=int, help="link depth of the repeated latency sweep (default: 4x the preset's)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "exploration.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    a.steady = f"{a.balance}@{a.frames}" if a.frames > 1 else None
    p = PRESETS[a.preset]
    a.default_latency, a.default_bandwidth, a.default_depth = p["latency"], p["bandwidth"], p["depth"]
    a.latencies = a.latencies or p["latencies"]
    a.bandwidths = a.bandwidths or p["bandwidths"]
    a.deep_depth = a.deep_depth or 4 * p["depth"]
    a.stem = "link_sweep" if a.preset == "modern" else f"link_sweep-{a.preset}"
    csv_path = os.path.join(a.out, a.stem + ".csv")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        write_csv(csv_path, sweep(a))
    rows = read_csv(csv_path)
    for r in rows:
        r["balance"] = project.policy_named(r["balance"])
        r["N"] = int(r["N"])
        for k in ("latency_s", "bandwidth_Bps", "render_time_ns", "one_node_ns", "speedup", "balance_gain"):
            r[k] = float(r[k]) if r[k] != "" else None
    plot(a, rows)
    table(a, rows)


def settings(a):
    """(swept quantity, latency, bandwidth, depth, balancing policies) for the
    one-dimensional sweeps."""
    lats = sorted(set(a.latencies.split(",")) | {a.default_latency}, key=value)  # the default link is in all
    bws = sorted(set(a.bandwidths.split(",")) | {a.default_bandwidth}, key=value)
    both = ("none", a.balance) + ((a.steady,) if a.steady else ())
    return ([("latency", lat, a.default_bandwidth, a.default_depth, both) for lat in lats] +
            [("bandwidth", a.default_latency, bw, a.default_depth, both) for bw in bws] +
            [("latency, deep links", lat, a.default_bandwidth, a.deep_depth, ("none",)) for lat in lats])


def sweep(a):
    ns = outputs.numbers(a.n, "--n")
    preset = preset_flags(a.preset)
    points = [{"params": {"sweep": "one node", "N": 1, "balance": "none", "latency": a.default_latency,
                          "bandwidth": a.default_bandwidth, "depth": a.default_depth},
               "args": preset + SCENE + ["--mesh", 1]}]
    for swept, lat, bw, depth, bals in settings(a):
        for n in ns:
            for bal in bals:
                points.append({"params": {"sweep": swept, "N": n, "balance": bal, "latency": lat, "bandwidth": bw,
                                          "depth": depth},
                               "args": preset + SCENE + ["--mesh", n, "--balance", bal.partition("@")[0],
                                                         "--link-latency", lat, "--link-bandwidth", bw] +
                               (["--frames", bal.partition("@")[2]] if "@" in bal else []) +
                               ([] if depth == a.default_depth else ["--link-depth", depth])})
    # (The default link appears in every sweep: the later ones are the same point.)
    unique = list({driver.point_id(p["args"]): p for p in points}.values())
    runs = driver.run(a.stem, unique, extract, None, a)
    by = {(r["N"], r["balance"], r["latency"], r["bandwidth"], r.get("depth", a.default_depth)): r for r in runs}
    one = by[(1, "none", a.default_latency, a.default_bandwidth, a.default_depth)]["render_time_ns"]
    rows = []
    for swept, lat, bw, depth, bals in settings(a):
        for n in ns:
            for bal in bals:
                r = by[(n, bal, lat, bw, depth)]
                none = by[(n, "none", lat, bw, depth)]
                rows.append({"sweep": swept, "N": n, "balance": bal, "latency": lat, "bandwidth": bw, "depth": depth,
                             "latency_s": value(lat), "bandwidth_Bps": value(bw),
                             "render_time_ns": r["render_time_ns"], "one_node_ns": one,
                             "speedup": one / r["render_time_ns"],
                             "balance_gain": none["render_time_ns"] / r["render_time_ns"] if bal != "none" else "",
                             "slides": r["slides"], "link_bytes": r["link_bytes"],
                             # the 95th percentile age of the loads decisions used, in intervals, and issue
                             # 11's target for it: 2 intervals plus a load report's time across one link
                             "age_p95": r["age_p95"],
                             "age_target": 2 + (value(lat) + 52 / value(bw)) * 1e9 / r["interval_ns"],
                             "version": r["version"], "command": r["command"]})
    return rows


def extract(r):
    link_bytes = sum(sum(link["bytes"].values()) for link in r["links"] if not link["to"].startswith("fb"))
    ages = r["balance"].get("load_age_intervals") or {}
    return {"render_time_ns": r["render_time_ns"], "slides": r["balance"]["slides"], "link_bytes": link_bytes,
            "age_p95": ages.get("p95", ""), "interval_ns": r["config"]["balance"]["interval_ns"]}


def knee(points, factor, slower_is_larger):
    """The link speed where the render time first reaches factor x its value
    at the fastest link, interpolated in log-log; None if never within the
    sweep. points: (link value, render time), any order."""
    pts = sorted(points, key=lambda p: p[0], reverse=not slower_is_larger)  # fastest first
    target = factor * pts[0][1]
    for (x0, t0), (x1, t1) in zip(pts, pts[1:]):
        if t1 >= target:  # and t0 < target: the first crossing
            f = (math.log(target) - math.log(t0)) / (math.log(t1) - math.log(t0))
            return math.exp(math.log(x0) + f * (math.log(x1) - math.log(x0)))
    return None


def knees(rows, swept, bal, n, factor):
    by_latency = swept.startswith("latency")
    pts = [(r["latency_s"] if by_latency else r["bandwidth_Bps"], r["render_time_ns"])
           for r in rows if r["sweep"] == swept and r["balance"] == bal and r["N"] == n]
    return knee(pts, factor, slower_is_larger=by_latency)


def fmt_latency(s):
    if s is None:
        return "beyond the sweep"
    return f"{s * 1e9:.0f} ns" if s < 1e-6 else f"{s * 1e6:.1f} us" if s < 1e-3 else f"{s * 1e3:.2f} ms"


def fmt_bandwidth(b):
    if b is None:
        return "beyond the sweep"
    return f"{b / 1e3:.0f} KB/s" if b < 1e6 else f"{b / 1e6:.0f} MB/s" if b < 1e9 else f"{b / 1e9:.1f} GB/s"


def plot(a, rows):
    plt = project.pyplot()
    ns = sorted({r["N"] for r in rows})
    cmap = plt.get_cmap("viridis")
    colour = {n: cmap(i / max(1, len(ns) - 1)) for i, n in enumerate(ns)}
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.5))
    for row, swept in enumerate(("latency", "bandwidth")):
        key = "latency_s" if swept == "latency" else "bandwidth_Bps"
        scale = 1e6 if swept == "latency" else 1e-9
        for n in ns:
            for bal, style in (("none", "-"), (a.balance, "--")):
                pts = sorted((r for r in rows if r["sweep"] == swept and r["N"] == n and r["balance"] == bal),
                             key=lambda r: r[key])
                xs = [r[key] * scale for r in pts]
                lab = f"N = {n}" if bal == "none" else None
                axes[row][0].plot(xs, [r["render_time_ns"] / 1e3 for r in pts], style, color=colour[n], label=lab)
                axes[row][1].plot(xs, [r["speedup"] for r in pts], style, color=colour[n], label=lab)
                if bal != "none":
                    axes[row][2].plot(xs, [r["balance_gain"] for r in pts], style, color=colour[n], marker=".",
                                      label=f"N = {n}")
            if a.steady:  # the steady state's gain: dotted, crosses
                pts = sorted((r for r in rows if r["sweep"] == swept and r["N"] == n and r["balance"] == a.steady),
                             key=lambda r: r[key])
                axes[row][2].plot([r[key] * scale for r in pts], [r["balance_gain"] for r in pts], ":",
                                  color=colour[n], marker="x", markersize=4)
            if swept == "latency":
                deep = sorted((r for r in rows if r["sweep"] == "latency, deep links" and r["N"] == n),
                              key=lambda r: r[key])
                axes[row][0].plot([r[key] * scale for r in deep], [r["render_time_ns"] / 1e3 for r in deep], ":",
                                  color=colour[n], linewidth=1)
            k = knees(rows, swept, "none", n, 2.0)
            if k is not None:
                t = 2 * min(r["render_time_ns"] for r in rows
                            if r["sweep"] == swept and r["N"] == n and r["balance"] == "none") / 1e3
                axes[row][0].plot([k * scale], [t], marker="x", color=colour[n], markersize=9, mew=2)
        unit = "link latency (us)" if swept == "latency" else "link bandwidth (GB/s)"
        for ax in axes[row]:
            ax.set_xscale("log")
            ax.set_xlabel(unit)
            ax.grid(alpha=0.3, which="both")
        axes[row][0].set_yscale("log")
        axes[row][0].set_ylabel("render time (us)")
        axes[row][1].set_yscale("log")
        axes[row][1].set_ylabel("speed-up over one node")
        axes[row][2].axhline(1.0, color="grey", linewidth=0.8)
        axes[row][2].set_ylabel(f"balancing gain: time(none) / time({a.balance})")
        axes[row][0].set_title(f"render time against {swept} (x: knee, time doubled)", fontsize=10)
        axes[row][1].set_title(f"speed-up over one node against {swept}", fontsize=10)
        axes[row][2].set_title(f"balancing gain against {swept}" +
                               (f" (dashed: frame 1, dotted: frame {a.frames})" if a.steady else ""), fontsize=10)
    axes[0][0].legend(fontsize=8, title=f"solid: none, dashed: {a.balance};\ndotted: none, depth {a.deep_depth}",
                      title_fontsize=8)
    axes[0][2].legend(fontsize=8)
    other = {"latency": a.default_bandwidth, "bandwidth": a.default_latency}
    fig.suptitle(f"Link speed: top, latency swept at {other['latency']}; bottom, bandwidth swept at "
                 f"{other['bandwidth']}. rtsim default experiment (1,000 spheres, f = 0.25, 256x256), preset {a.preset}", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    outputs.savefig(fig, os.path.join(a.out, a.stem + ".png"), dpi=100)


def table(a, rows):
    ns = sorted({r["N"] for r in rows})
    lines = [f"<!-- written by scripts/experiments/link_sweep.py --preset {a.preset}; do not edit -->",
             "| N | latency: +10 % | latency: knee (x2) | latency knee (x2), depth "
             f"{a.deep_depth} | bandwidth: +10 % | bandwidth: knee (x2) |"
             f" knee (x2) with {a.balance}: latency, bandwidth | speed-up, fastest links | balancing gain, fastest"
             " / default / slowest latency | lowest balancing gain, frame 1 (link) | lowest balancing gain, frame "
             f"{a.frames} (link) | load age p95, worst against target |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for n in ns:
        lat = [r for r in rows if r["sweep"] == "latency" and r["N"] == n]
        fastest = min((r for r in lat if r["balance"] == "none"), key=lambda r: r["latency_s"])
        gains = sorted((r for r in lat if r["balance"] == a.balance), key=lambda r: r["latency_s"])
        default = next(r for r in gains if r["latency"] == a.default_latency)
        balanced = [r for r in rows if r["N"] == n and r["balance"] == a.balance and r["sweep"] in ("latency", "bandwidth")]
        low = min(balanced, key=lambda r: r["balance_gain"])
        steady = [r for r in rows if r["N"] == n and r["balance"] == a.steady and r["sweep"] in ("latency", "bandwidth")]
        low_steady = (f"{min(steady, key=lambda r: r['balance_gain'])['balance_gain']:.3f} "
                      f"({min(steady, key=lambda r: r['balance_gain'])['latency']}, "
                      f"{min(steady, key=lambda r: r['balance_gain'])['bandwidth']})") if steady else "-"
        aged = [r for r in balanced if r.get("age_p95") not in (None, "")]
        worst = max(aged, key=lambda r: float(r["age_p95"]) / float(r["age_target"])) if aged else None
        age = (f"{float(worst['age_p95']):.2f} (target {float(worst['age_target']):.2f}; {worst['latency']}, "
               f"{worst['bandwidth']})" if worst else "no decisions")
        lines.append(
            f"| {n} | {fmt_latency(knees(rows, 'latency', 'none', n, 1.1))} | "
            f"{fmt_latency(knees(rows, 'latency', 'none', n, 2.0))} | "
            f"{fmt_latency(knees(rows, 'latency, deep links', 'none', n, 2.0))} | "
            f"{fmt_bandwidth(knees(rows, 'bandwidth', 'none', n, 1.1))} | "
            f"{fmt_bandwidth(knees(rows, 'bandwidth', 'none', n, 2.0))} | "
            f"{fmt_latency(knees(rows, 'latency', a.balance, n, 2.0))}, "
            f"{fmt_bandwidth(knees(rows, 'bandwidth', a.balance, n, 2.0))} | "
            f"{fastest['speedup']:.2f} | {gains[0]['balance_gain']:.2f} / {default['balance_gain']:.2f} / "
            f"{gains[-1]['balance_gain']:.2f} | {low['balance_gain']:.3f} ({low['latency']}, {low['bandwidth']}) | "
            f"{low_steady} | "
            f"{age} |")
    section = "link_sweep table" if a.preset == "modern" else f"link_sweep table {a.preset}"
    publish_table(lines, os.path.join(a.out, a.stem + ".md"), a.doc, section)


if __name__ == "__main__":
    sys.exit(outputs.guard("link_sweep.py", main))
