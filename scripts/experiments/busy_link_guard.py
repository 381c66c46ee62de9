#!/usr/bin/python3
"""What the busy-link guard (`--guard-wire U`: no slide across a link whose
wire would take more than U of an interval after the slide: the last
interval's share plus a ray message for each ray step the slab's work
took) does where balancing is judged:
every point of the link sweep (latency and bandwidth, N = 2..8, `slide`'s
first frame: the default policy's until `measured`, whose first frame does
not slide) and of Fig. 4 (`slide`'s first frame, both views,
every f), on the modern and the 1987 machine, each run without balancing,
with the guard's other terms alone (--guard-wire 0), and with the busy-link
guard at each share (1, the default, and 0.8). Counts the
points where balancing loses more than 2 % (issue 11's "never hurts":
time(none) / time(balanced) >= 0.98), the lowest gain and the geometric
mean, and lists the points that still lose. With --doc, writes
doc/results/busy_link_guard.{csv,md} and the table into doc/balancing.md.
Run with /usr/bin/python3."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
import link_sweep  # noqa: E402
from project import PAPER_SCENE, ROOT, VIEWS, preset_flags, publish_table  # noqa: E402
from sweep_driver import write_csv  # noqa: E402

PRESETS = ("modern", "transputer-1987")


def points():
    """(set, preset, point label, rtsim args without balancing flags, balancing policy) for every point."""
    out = []
    for preset in PRESETS:
        cfg = preset_flags(preset)
        p = link_sweep.PRESETS[preset]
        for swept, values in (("latency", p["latencies"]), ("bandwidth", p["bandwidths"])):
            for v in values.split(","):
                if swept == "bandwidth" and v == p["bandwidth"]:
                    continue  # the preset's own link: a point of the latency sweep already
                lat, bw = (v, p["bandwidth"]) if swept == "latency" else (p["latency"], v)
                for n in range(2, 9):
                    out.append(("link sweep", preset, f"{swept} {v}, N = {n}",
                                cfg + link_sweep.SCENE + ["--mesh", n, "--link-latency", lat, "--link-bandwidth", bw],
                                "slide"))
        for view, cam in VIEWS.items():
            for n in range(2, 9):
                for k in range(1, n + 1):
                    out.append(("Fig. 4", preset, f"{view}, N = {n}, f = {k}/{n}",
                                cfg + PAPER_SCENE + cam + ["--mesh", n, "--concentration", f"{k / n:.6f}"], "slide"))
    return out


def variants(shares):
    return {"none": ["--balance", "none"], **{f"wire {s}": ["--guard-wire", s] for s in ["0"] + shares}}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--shares", default="1,0.8", help="busy-link guard shares to try (1: a full link)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"), plot_only=False)  # (it cannot redraw from a CSV)
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    shares = a.shares.split(",")
    outputs.numbers(a.shares, "--shares", float)
    vs = variants(shares)
    pts = points()
    todo = []
    for i, (_, preset, label, args, policy) in enumerate(pts):
        for v, flags in vs.items():
            bal = flags if v == "none" else ["--balance", policy] + flags
            todo.append({"params": {"point": i, "variant": v}, "args": args + bal})
    got = driver.run("busy_link_guard", todo, extract, None, a)
    by = {(r["point"], r["variant"]): r for r in got}
    rows = []
    for i, (what, preset, label, _, policy) in enumerate(pts):
        none = by[(i, "none")]
        row = {"set": what, "preset": preset, "point": label, "policy": policy, "none_ns": none["render_time_ns"]}
        for v in vs:
            if v == "none":
                continue
            r = by[(i, v)]
            row[f"{v} gain"] = none["render_time_ns"] / r["render_time_ns"]
            row[f"{v} slides"] = r["slides"]
            row[f"{v} stopped"] = r["busy_link"]
        row["version"] = by[(i, "wire 0")]["version"]
        rows.append(row)
    write_csv(os.path.join(a.out, "busy_link_guard.csv"), rows)
    publish_table(table(rows, vs), os.path.join(a.out, "busy_link_guard.md"), a.doc or None,
                         "busy-link guard")


def table(rows, vs):
    bal = [v for v in vs if v != "none"]
    lines = ["<!-- written by scripts/experiments/busy_link_guard.py; do not edit -->",
             "Balancing gain time(none) / time(balanced) of the first frame; \"wire 0\" is the guard without the "
             "busy-link term (`--guard-wire 0`), \"wire U\" with it at share U (1 is the default).", "",
             "| set | machine | points | " + " | ".join(f"losing > 2 %, {v}" for v in bal) + " | " +
             " | ".join(f"lowest gain, {v}" for v in bal) + " | " + " | ".join(f"geometric mean, {v}" for v in bal) +
             " |", "|---|---|---:|" + "---:|" * (3 * len(bal))]
    for what in ("link sweep", "Fig. 4"):
        for preset in PRESETS:
            rs = [r for r in rows if r["set"] == what and r["preset"] == preset]
            gains = {v: [r[f"{v} gain"] for r in rs] for v in bal}
            lines.append(f"| {what} ({rs[0]['policy']}) | {preset} | {len(rs)} | " +
                         " | ".join(str(sum(g < 0.98 for g in gains[v])) for v in bal) + " | " +
                         " | ".join(f"{min(gains[v]):.3f}" for v in bal) + " | " +
                         " | ".join(f"{math.exp(sum(map(math.log, gains[v])) / len(rs)):.3f}" for v in bal) + " |")
    lines += ["", "Points where any of them loses more than 2 %:", "",
              "| set | machine | point | " + " | ".join(f"gain, {v} (slides; stopped by the busy link)" for v in bal) +
              " |", "|---|---|---|" + "---:|" * len(bal)]
    for r in rows:
        if any(r[f"{v} gain"] < 0.98 for v in bal):
            lines.append(f"| {r['set']} | {r['preset']} | {r['point']} | " +
                         " | ".join(f"{r[f'{v} gain']:.3f} ({r[f'{v} slides']:,}; {r[f'{v} stopped']:,})"
                                    for v in bal) + " |")
    return lines


def extract(r):
    b = r["balance"]
    return {"render_time_ns": r["render_time_ns"], "slides": b.get("slides", 0),
            "busy_link": b.get("guard_busy_link", 0)}


if __name__ == "__main__":
    sys.exit(outputs.guard("busy_link_guard.py", main))
