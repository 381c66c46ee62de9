#!/usr/bin/python3
"""Records what a build of rtsim writes for a fixed set of runs (reports,
images, VCDs), or checks that a build writes the same bytes as a recorded set.
Used around every speed change (issue 14): a faster simulator must compute
the same machine, so every exact mode must give byte-identical outputs.

  scripts/same_outputs.py --record DIR [--build build]
  scripts/same_outputs.py --compare DIR [--build build]

The runs: the benchmark run (balls-4 at 512x512, N = 4) in the default
lookahead mode and in lockstep (--quantum 0); 10 and 100 us quanta
(approximate, but deterministic: they must not change either; 100 us is
the benchmark's fastest mode under 1 % error); fully traced runs with a VCD,
with and without balancing; balancing with the control lane; finite output
buffers (senders block); frame sequences (resplit, slide's boundaries
carried on, recommended, sample, a moving eye, the last frame traced); the
express rung on 16x16x16. Reports are compared
without the fields that measure the host, not the machine: wall_s,
wall_clock, rerun.version and kernel.delta_cycles (how many delta cycles the SystemC
kernel ran depends on how processes wait, not on what the machine does).
DIR is a folder of the user's (in doc/ it is refused): --record writes its
files there, --compare writes the new run's beside it, in DIR.new.
Standard library only; run with /usr/bin/python3.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import BUILD, SPD, run_rtsim, spd_scene  # noqa: E402

# (name, flags, files it writes besides the report and image)
RUNS = [
    ("bench-lookahead", ["--scene", "balls-4", "--size", "512x512", "--mesh", "4"], []),
    ("bench-lockstep", ["--scene", "balls-4", "--size", "512x512", "--mesh", "4", "--quantum", "0"], []),
    ("bench-10us", ["--scene", "balls-4", "--size", "512x512", "--mesh", "4", "--quantum", "10us"], []),
    ("bench-100us", ["--scene", "balls-4", "--size", "512x512", "--mesh", "4", "--quantum", "100us"], []),
    ("traced", ["--scene", "balls-4", "--size", "128x128", "--mesh", "3", "--vcd", "{out}.vcd"], ["vcd", "gtkw"]),
    ("traced-lockstep", ["--scene", "balls-4", "--size", "128x128", "--mesh", "3", "--quantum", "0",
                         "--vcd", "{out}.vcd"], ["vcd"]),
    ("slide-traced", ["--spheres", "1000", "--size", "128x128", "--mesh", "4", "--balance", "slide",
                      "--balance-interval", "5us", "--vcd", "{out}.vcd"], ["vcd"]),
    ("slide-lane", ["--spheres", "1000", "--size", "128x128", "--mesh", "4", "--balance", "quantile",
                    "--balance-interval", "5us", "--link-control-depth", "2", "--vcd", "{out}.vcd"], ["vcd"]),
    ("out-depth", ["--scene", "balls-4", "--size", "128x128", "--mesh", "4", "--link-out-depth", "2000",
                   "--fb-out-depth", "1", "--fb-depth", "1", "--vcd", "{out}.vcd"], ["vcd"]),
    ("out-depth-lockstep", ["--scene", "balls-4", "--size", "128x128", "--mesh", "4", "--link-out-depth", "2000",
                            "--fb-out-depth", "1", "--fb-depth", "1", "--quantum", "0"], []),
    ("resplit-frames", ["--spheres", "1000", "--size", "128x128", "--mesh", "4", "--balance", "resplit",
                        "--frames", "3", "--ray-batch", "4", "--fb-units", "3"], []),
    # Frame sequences: a dynamic policy's boundaries carried on, a moving
    # eye, the recommended policy, sample's first frame, and the last
    # frame's waveforms.
    ("slide-frames-traced", ["--spheres", "1000", "--size", "96x96", "--mesh", "4", "--balance", "slide",
                             "--balance-interval", "5us", "--frames", "3", "--eye-step", "0.05,0,0",
                             "--vcd", "{out}.vcd"], ["vcd"]),
    ("recommended-frames", ["--spheres", "1000", "--size", "96x96", "--mesh", "4", "--balance", "recommended",
                            "--frames", "4", "--link-control-depth", "2"], []),
    ("sample-frames", ["--spheres", "1000", "--size", "96x96", "--mesh", "3", "--balance", "sample",
                       "--frames", "3", "--link-out-depth", "2000", "--fb-units", "2"], []),
    # The express rung (rays across empty boxes in one relay) on a mesh
    # large enough to have empty boxes, and the links it leaves unused.
    ("express", ["--scene", "balls-5", "--size", "64x64", "--mesh", "16", "--balance", "none",
                 "--fidelity", "express"], []),
    ("frames-lockstep-traced", ["--scene", "balls-4", "--size", "64x64", "--mesh", "3", "--frames", "3",
                                "--eye-step", "0,0.1,0", "--quantum", "0", "--vcd", "{out}.vcd"], ["vcd"]),
]

HOST_FIELDS = [("wall_s",), ("wall_elaboration_s",), ("wall_startup_s",), ("wall_clock",), ("rerun", "version"),
               ("kernel", "delta_cycles")]


def run(build, out_dir, name, flags):
    out = os.path.join(out_dir, name)
    args = [a.format(out=out) for a in flags]
    if "--scene" in args:
        i = args.index("--scene") + 1
        args[i] = spd_scene(args[i])
    try:
        report, _ = run_rtsim(args, os.path.join(build, "rtsim"), image=out + ".png", report=out + ".json")
    except RuntimeError as e:
        raise outputs.ToolError(f"{name} failed ({e})", outputs.FAILED)
    for path in HOST_FIELDS:
        d = report
        for k in path[:-1]:
            d = d.get(k, {})
        d.pop(path[-1], None)
    with outputs.atomic(out + ".json") as f:
        f.write(beside_the_clone(json.dumps(report, indent=1, sort_keys=True)))


def beside_the_clone(text):
    """The report with the scenes' folder named as beside the clone
    (rerun.flags and config.scene.file hold it absolute), so that a record
    made in one clone or worktree compares with a run in another."""
    return text.replace(json.dumps(SPD)[1:-1], "../shared/scenes/spd")


def folder(path, flag):
    """An output folder, made if missing: not a file, not in doc/."""
    if os.path.lexists(path) and not os.path.isdir(path) or os.path.islink(path):
        raise outputs.ToolError(f"{flag} {path}: not a folder")
    if outputs.under(path, outputs.DOC):
        raise outputs.ToolError(f"{flag} {path}: in doc/, which this script never writes")
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise outputs.ToolError(f"{flag} {path}: {e.strerror}")
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--record", metavar="DIR")
    g.add_argument("--compare", metavar="DIR")
    ap.add_argument("--build", default=BUILD)
    ap.add_argument("--only", nargs="*", help="run names (default: all)")
    a = ap.parse_args()
    runs = [r for r in RUNS if not a.only or r[0] in a.only]
    unknown = set(a.only or []) - {r[0] for r in RUNS}
    if unknown:
        raise outputs.ToolError(f"--only: no run named {', '.join(sorted(unknown))} (runs: {', '.join(r[0] for r in RUNS)})")
    outputs.check_input(os.path.join(a.build, "rtsim"), "--build")
    if a.record:
        folder(a.record, "--record")
        for name, flags, _ in runs:
            run(a.build, a.record, name, flags)
            print(f"recorded {name}")
        return
    if not os.path.isdir(a.compare):
        raise outputs.ToolError(f"--compare {a.compare}: not a folder (one that --record wrote)")
    new = folder(a.compare.rstrip("/") + ".new", "--compare")
    differ = 0
    for name, flags, extra in runs:
        run(a.build, new, name, flags)
        for ext in ["json", "png"] + extra:
            x, y = outputs.check_input(os.path.join(a.compare, f"{name}.{ext}"), "--compare"), os.path.join(new, f"{name}.{ext}")
            with open(x, "rb") as f, open(y, "rb") as g:
                same = f.read() == g.read()
            if not same and ext == "gtkw":  # it names the VCD's path, which differs by folder
                with open(x) as f, open(y) as g:
                    same = f.read().replace(a.compare.rstrip("/"), "") == g.read().replace(new, "")
            print(f"{name}.{ext}: {'same' if same else 'DIFFERENT'}")
            differ += not same
    print(f"{differ} files differ" if differ else "all the same")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(outputs.guard("same_outputs.py", main))
