#!/usr/bin/python3
"""Does the recommended policy ever hurt, away from the tables' grids?
--count machines drawn at random from --seed (the built-in scene at a
random crowd and view, or an SPD scene along a random axis; a cube of 2 to
8 nodes a side or a mesh of another shape; 64x64 to 128x128; the modern,
1987 or paper machine; links of 100 MB/s to 10 GB/s), each rendered
without balancing and with --policy over --frames frames of the same view:
every frame against the unbalanced frame. Prints the points with a frame
above 1.02, the worst first, with the flags that make each again; with
--doc, writes doc/results/never_hurts_random.{csv,md} and the table into
doc/balancing.md (with --frames other than 3, never_hurts_random-Nframes.*
and its own table there: 14 frames show the polish's tries). The same seed
draws the same machines.

  /usr/bin/python3 scripts/experiments/never_hurts_random.py [--count 500] [--seed 1] [--frames 3] [--doc]

Run with /usr/bin/python3."""
import argparse
import os
import random
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import project  # noqa: E402
import sweep_driver as driver  # noqa: E402
from csv_rows import read_csv  # noqa: E402
from project import ROOT, SPD, VIEWS, preset_flags, publish_table  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # (its sibling, spd_never_hurts)
from spd_never_hurts import extract as frame_times  # noqa: E402

SPD_SCENES = ["balls-2", "balls-3", "balls-4", "gears-2", "rings-2", "tetra-3"]
SHAPES = ["64x1x1", "33x1x1", "1x16x1", "16x4x1", "8x8x2", "2x2x32", "1x1x2", "3x5x7", "12x3x3", "4x4x16"]
FRACTIONS = [0.01, 0.05, 0.125, 0.25, 0.5, 1.0]
SIZES = ["64x64", "96x96", "128x128"]
BANDWIDTHS = ["100MB/s", "400MB/s", "1GB/s", "10GB/s"]
LOSS = 1.02  # a frame above this share of the unbalanced frame loses
WORST = 15  # rows of the worst points in the table


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", default="500", help="machines drawn (default 500)")
    ap.add_argument("--seed", default="1", help="draws the machines (default 1)")
    ap.add_argument("--policy", default="recommended", help="the policy compared with none (default recommended)")
    ap.add_argument("--frames", default="3", help="frames per run of the policy (default 3)")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    a.count = outputs.numbers(a.count, "--count", least=1, most=10000)[0]
    a.seed = outputs.numbers(a.seed, "--seed", least=0)[0]
    a.frames = outputs.numbers(a.frames, "--frames", least=1, most=100)[0]
    if a.policy == "none":
        ap.error("--policy none: it is the baseline; name a balancing policy")
    how = project.changed_flags(ap, a, ("count", "seed", "policy", "frames"))
    stem = "never_hurts_random" + ("" if a.frames == 3 else f"-{a.frames}frames")
    csv_path = os.path.join(a.out, stem + ".csv")
    if a.plot_only:  # (the CSV of an earlier run)
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        points = []
        for k, machine in enumerate(draw(a.count, a.seed)):
            for policy in ("none", a.policy):
                frames = ["--frames", str(a.frames)] if policy != "none" else []
                points.append({"params": {"point": k, "machine": " ".join(machine), "policy": policy},
                               "args": machine + ["--balance", policy] + frames})
        driver.run("never-hurts-random", points, extract, csv_path, a)
    table(a, how, read_csv(csv_path), os.path.join(a.out, stem + ".md"))


def draw(count, seed):
    """count machines, each as the rtsim flags that make it (paths from
    ROOT's parent as `../shared/...` would not rerun elsewhere: absolute),
    a machine drawn twice drawn again."""
    rng = random.Random(seed)
    machines = []
    while len(machines) < count:
        preset = rng.choice(project.PRESETS)
        flags = preset_flags(preset)
        if rng.random() < 0.5:
            view = rng.choice(sorted(VIEWS))
            flags += ["--spheres", "1000", "--radius", "0.02", "--seed", "1", "--axis", "x",
                      "--concentration", str(rng.choice(FRACTIONS))] + VIEWS[view]
        else:
            flags += ["--scene", os.path.join(SPD, rng.choice(SPD_SCENES) + ".nff"), "--axis", rng.choice("xyz")]
        flags += ["--mesh", str(rng.randint(2, 8))] if rng.random() < 0.5 else ["--mesh-dims", rng.choice(SHAPES)]
        flags += ["--size", rng.choice(SIZES)]
        if preset != "paper":  # (the paper's simulator's links are its own)
            flags += ["--link-bandwidth", rng.choice(BANDWIDTHS)]
        if flags not in machines:
            machines.append(flags)
    return machines


def extract(r):
    """spd_never_hurts's figures (the frames' times), and the policy the run chose."""
    return {**frame_times(r), "chosen": r["config"]["balance"].get("policy", "")}


def table(a, how, rows, md_path):
    """Each point's frames against its unbalanced frame: a summary line,
    and the points with a frame above LOSS (the worst WORST of them)."""
    none = {r["point"]: float(r["render_time_ns"]) for r in rows if r["policy"] == "none"}
    points = []
    for r in rows:
        if r["policy"] != "none" and r["point"] in none:
            ratios = [float(x) / none[r["point"]] for x in str(r["frames_ns"]).split()]
            points.append({"machine": r["machine"], "chosen": r["chosen"], "ratios": ratios})
    if not points:
        raise outputs.ToolError(f"{md_path}: no point has both runs")
    points.sort(key=lambda p: -max(p["ratios"]))
    lost = [p for p in points if max(p["ratios"]) > LOSS]
    # (past the third frame: where a sequence of more frames polishes, or re-splits again)
    late = [p for p in lost if max(p["ratios"][3:], default=0) > LOSS]
    lines = [f"<!-- written by scripts/experiments/never_hurts_random.py{' ' + how if how else ''}; do not edit -->",
             f"{len(points)} machines drawn at random (seed {a.seed}); `--balance {a.policy}` over {a.frames} frames, each "
             f"frame's time / the unbalanced frame's. Points with a frame above {LOSS}: {len(lost)} "
             f"({sum(1 for p in lost if p['ratios'][0] > LOSS)} in the first frame"
             f"{f', {len(late)} past the third' if a.frames > 3 else ''}); worst frame "
             f"{max(max(p['ratios']) for p in points):.3f}; last frame: median "
             f"{statistics.median(p['ratios'][-1] for p in points):.3f}.", ""]
    if lost:
        lines += [f"The points with a frame above {LOSS}" + (f" (the worst {WORST})" if len(lost) > WORST else "") + ":", "",
                  "| machine (rtsim flags) | policy run | frames | worst |", "|---|---|---|---:|"]
        for p in lost[:WORST]:
            flags = p["machine"].replace(ROOT + os.sep, "").replace(os.path.dirname(SPD) + os.sep, "../shared/scenes/")
            lines.append(f"| `{flags}` | {p['chosen']} | " + " ".join(f"{x:.3f}" for x in p["ratios"]) +
                         f" | {max(p['ratios']):.3f} |")
    publish_table(lines, md_path, a.doc or None, "never hurts random" + ("" if a.frames == 3 else f" {a.frames} frames"))


if __name__ == "__main__":
    sys.exit(outputs.guard("never_hurts_random.py", main))
