#!/usr/bin/python3
"""Where the nodes' busy time goes under each machine preset (configs/):
rtsim's default experiment (1,000 spheres crowded into the first quarter of
x, 256x256, N = 4) viewed across the progress axis (the default camera) and
along it, without balancing. Splits the total node busy time into
intersection tests, voxel steps, shading, ray generation and message
handling (operation counts from the report times the preset's costs), and
gives the render time and speed-up. With --doc, writes doc/results/presets.{csv,md} and
the table in doc/machine.md. Standard library only; run with /usr/bin/python3."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, PRESETS, ROOT, VIEWS, preset_flags, publish_table  # noqa: E402
from csv_rows import read_csv  # noqa: E402

SCENE = PAPER_SCENE + ["--concentration", "0.25"]  # on 1 node and on 4x4x4 (--mesh, once)
PARTS = ["tests", "voxel_steps", "shading", "ray_generation", "messages"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "machine.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    csv_path = os.path.join(a.out, "presets.csv")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        points = [{"params": {"preset": p, "view": v, "mesh": m},
                   "args": preset_flags(p) + SCENE + cam + ["--mesh", str(m)]}
                  for p in PRESETS for v, cam in VIEWS.items() for m in (1, 4)]
        driver.run("presets", points, extract, csv_path, a)
    table(a, read_csv(csv_path))


def extract(r):
    c = r["config"]["costs"]
    t = dict.fromkeys(PARTS, 0.0)
    for n in r["nodes"]:
        k, p = n["counters"], n["counters"]["intersection_tests_by_primitive"]
        t["tests"] += (p["sphere"] * c["test_sphere_ns"] + p["polygon"] * c["test_polygon_ns"] +
                       p["cone"] * c["test_cone_ns"])
        t["voxel_steps"] += k["voxel_steps"] * c["voxel_step_ns"]
        t["shading"] += k["shadings"] * c["shading_ns"]
        t["ray_generation"] += n["rays_generated"] * c["ray_generation_ns"]
        t["messages"] += n["messages_sent"] * c["send_ns"] + n["messages_received"] * c["receive_ns"]
    busy = r["totals"]["busy_ns"]
    out = {"render_time_ns": r["render_time_ns"], "busy_ns": busy}
    out.update({k + "_share": v / busy for k, v in t.items()})
    out["other_share"] = 1 - sum(t.values()) / busy  # grid updates after slides (none here)
    return out


def table(a, rows):
    by = {(r["preset"], r["view"], int(r["mesh"])): r for r in rows}
    lines = ["<!-- written by scripts/experiments/presets.py; do not edit -->",
             "| preset | view | render time, N = 4 | speed-up over one node | intersection tests | voxel steps | "
             "shading | ray generation | messages |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    for p in PRESETS:
        for v in VIEWS:
            r, one = by[(p, v, 4)], by[(p, v, 1)]
            t = float(r["render_time_ns"])
            shown = f"{t / 1e6:.3g} ms" if t < 1e9 else f"{t / 1e9:.3g} s"
            lines.append(f"| {p} | {v} | {shown} | {float(one['render_time_ns']) / t:.2f} | " +
                         " | ".join(f"{100 * float(r[k + '_share']):.0f} %" for k in PARTS) + " |")
    publish_table(lines, os.path.join(a.out, "presets.md"), a.doc, "presets table")


if __name__ == "__main__":
    sys.exit(outputs.guard("presets.py", main))
