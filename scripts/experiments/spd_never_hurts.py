#!/usr/bin/python3
"""Does the default balancing ever hurt on real scenes? Eric Haines' SPD
scenes (balls-4, balls-5, tetra-3, gears-2, rings-2) on N x N x N meshes
(N = 4 to 8), or meshes of other shapes (--shapes 64x1x1,...), over a
sweep of link bandwidths, each rendered without
balancing and with the default policy over --frames frames of the same
view: every frame's time against the unbalanced frame's, the first frame
and the steady state (the last) apart. With --doc, writes doc/results/spd_never_hurts.{csv,md}
and, with --doc, the table of the worst points into doc/balancing.md
(with --tag TAG: spd_never_hurts-TAG.*, and its own section).
Run with /usr/bin/python3."""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
import project  # noqa: E402
from project import ROOT, SPD, publish_table  # noqa: E402
from csv_rows import read_csv  # noqa: E402

SCENES = "balls-4,balls-5,tetra-3,gears-2,rings-2"
WORST = 10  # rows of the worst points in the table


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default=SCENES)
    ap.add_argument("--n", default="4,5,6,7,8")
    ap.add_argument("--shapes", default="", help="mesh shapes WxHxD instead of --n's cubes (e.g. 64x1x1,33x1x1)")
    ap.add_argument("--tag", default="", help="names the files (spd_never_hurts-TAG.*) and the doc section")
    ap.add_argument("--bandwidths", default="100MB/s,200MB/s,400MB/s,1GB/s")
    ap.add_argument("--size", default="256x256")
    ap.add_argument("--policy", default="recommended",
                    help="the policy compared with none (default: recommended, rtsim's choice for the mesh: sample on "
                         "columns of at most 8 boxes, else measured)")
    ap.add_argument("--frames", type=int, default=6)
    ap.add_argument("--extra", default="", help="more rtsim flags for every run")
    ap.add_argument("--policy-extra", default="",
                    help="more rtsim flags for the compared policy's runs only (e.g. --start-mix 0, which none refuses)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    a.how = project.changed_flags(ap, a, ("scenes", "n", "shapes", "bandwidths", "size", "policy", "frames", "extra",
                                          "policy_extra", "tag"))  # (the table's "written by" line)
    if a.doc and not a.tag and (project.policy_named(a.policy) != "recommended" or a.policy_extra):
        ap.error(f"--tag: --doc with --policy {a.policy}" + (" and --policy-extra" if a.policy_extra else "") +
                 " needs one: untagged, its table would replace the recommended policy's in doc/")
    stem = "spd_never_hurts" + ("-" + outputs.check_name(a.tag, "--tag") if a.tag else "")
    csv_path = os.path.join(a.out, stem + ".csv")
    outputs.numbers(a.n, "--n", least=1)
    outputs.numbers(str(a.frames), "--frames", least=1)
    outputs.image_size(a.size)
    meshes = [["--mesh-dims", d] for d in outputs.mesh_shapes(a.shapes)] if a.shapes else [["--mesh", n] for n in a.n.split(",")]
    for scene in a.scenes.split(","):
        outputs.check_input(os.path.join(SPD, outputs.check_name(scene, "--scenes") + ".nff"), "--scenes")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        points = []
        for scene in a.scenes.split(","):
            for mesh in meshes:
                for bw in a.bandwidths.split(","):
                    base = ["--scene", os.path.join(SPD, scene + ".nff"), "--size", a.size, *mesh,
                            "--link-bandwidth", bw] + a.extra.split()
                    for policy in ("none", a.policy):
                        frames = ["--frames", a.frames] if policy != "none" else []
                        n = mesh[1] if a.shapes else int(mesh[1])
                        own = a.policy_extra.split() if policy != "none" else []
                        points.append({"params": {"scene": scene, "N": n, "bandwidth": bw, "policy": policy},
                                       "args": base + own + ["--balance", policy] + frames})
        driver.run("spd-never-hurts" + ("-" + a.tag if a.tag else ""), points, extract, csv_path, a)
    rows = read_csv(csv_path)
    for r in rows:
        r["policy"] = project.policy_named(r["policy"])
    table(a, rows, os.path.join(a.out, stem + ".md"))


def extract(r):
    return {"render_time_ns": r["render_time_ns"],
            "frames_ns": " ".join(f"{f['render_time_ns']:.0f}" for f in r.get("frames", [])) or
            f"{r['render_time_ns']:.0f}"}


def table(a, rows, md_path):
    """Per point: each frame against the unbalanced frame; the worst points
    by their worst frame, and a summary line."""
    none = {(r["scene"], r["N"], r["bandwidth"]): float(r["render_time_ns"]) for r in rows if r["policy"] == "none"}
    points = []
    for r in rows:
        if r["policy"] == "none":
            continue
        t0 = none[(r["scene"], r["N"], r["bandwidth"])]
        ratios = [float(x) / t0 for x in r["frames_ns"].split()]
        points.append({"scene": r["scene"], "N": r["N"], "bandwidth": r["bandwidth"], "none": t0, "ratios": ratios})
    points.sort(key=lambda p: -max(p["ratios"]))
    lines = [f"<!-- written by scripts/experiments/spd_never_hurts.py{' ' + a.how if a.how else ''}; do not edit -->",
             f"{len(points)} points ({a.scenes.replace(',', ', ')}; "
             f"{'meshes ' + a.shapes.replace(',', ', ') if a.shapes else 'N = ' + a.n.replace(',', ', ')}; links "
             f"{a.bandwidths.replace(',', ', ')}; {a.size}); `--balance {a.policy}{' ' + a.policy_extra if a.policy_extra else ''}` over {a.frames} frames, each "
             f"frame's time / the unbalanced frame's. First frame: worst {max(p['ratios'][0] for p in points):.3f}; "
             f"any frame: worst {max(max(p['ratios']) for p in points):.3f}, points with a frame above 1.02: "
             f"{sum(1 for p in points if max(p['ratios']) > 1.02)}; last frame: median "
             f"{statistics.median(p['ratios'][-1] for p in points):.3f}, worst "
             f"{max(p['ratios'][-1] for p in points):.3f}.",
             "",
             "| scene | points | worst first frame | worst frame | points with a frame above 1.02 | last frame, median "
             "| last frame, worst |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for scene in a.scenes.split(","):
        ps = [p for p in points if p["scene"] == scene]
        if ps:
            lines.append(f"| {scene} | {len(ps)} | {max(p['ratios'][0] for p in ps):.3f} | "
                         f"{max(max(p['ratios']) for p in ps):.3f} | {sum(1 for p in ps if max(p['ratios']) > 1.02)} | "
                         f"{statistics.median(p['ratios'][-1] for p in ps):.3f} | {max(p['ratios'][-1] for p in ps):.3f} |")
    lines += ["",
             f"The {WORST} worst points:",
             "",
             "| scene | N | links | none | " + " | ".join(f"frame {k + 1}" for k in range(a.frames)) + " | worst |",
             "|---|---:|---|---:|" + "---:|" * (a.frames + 1)]
    for p in points[:WORST]:
        t = p["none"] / 1e6
        lines.append(f"| {p['scene']} | {p['N']} | {p['bandwidth']} | {t:,.2f} ms | " +
                     " | ".join(f"{x:.3f}" for x in p["ratios"]) + f" | {max(p['ratios']):.3f} |")
    publish_table(lines, md_path, a.doc or None, "spd never hurts" + (" " + a.tag if a.tag else ""))


if __name__ == "__main__":
    sys.exit(outputs.guard("spd_never_hurts.py", main))
