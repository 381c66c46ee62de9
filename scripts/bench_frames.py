#!/usr/bin/python3
"""Benchmark of a frame sequence: the wall time of `--frames K` (default 20)
against one frame's, on the paper's scene at 64x64 on 8x8x8 (f = 1/8,
viewed along the axis), without balancing and with the recommended
policy. A sequence of K frames can cost no less than K frames' simulation;
what it costs beyond that is the sequence's own: the host phase between
two frames (one machine renders them all, in one elaboration: the nodes
re-boxed, their grids rebuilt, every part restarted) and, under the
recommended policy, the frame loop's forecast of the next frame's planes.
Runs alternate (one frame, then K frames),
medians of --runs; with --against BUILD, that build's rtsim is run in turn
with this one, so both are measured in the same minutes. Prints the table;
with --doc writes doc/benchmarks/frames.md.

  /usr/bin/python3 scripts/bench_frames.py [--runs 5] [--frames 20] [--against OLD_BUILD] [--doc]

Standard library only; run with /usr/bin/python3."""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from bench_rtref import add_cpu_option, build_fast, machine, pin_to_cpu  # noqa: E402
from bench_rtsim import timed  # noqa: E402
from project import FAST_BUILD, PAPER_SCENE, ROOT, VIEWS, version  # noqa: E402

N = 8
SCENE = list(PAPER_SCENE)
SCENE[SCENE.index("--size") + 1] = "64x64"
JOB = SCENE + ["--concentration", str(1 / N), "--mesh", str(N)] + VIEWS["along"] + ["--no-baseline", "-q", "--image", ""]
POLICIES = ["none", "recommended"]


def arguments():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5, help="runs of each case (medians)")
    ap.add_argument("--frames", type=int, default=20, help="frames in the sequence (K)")
    ap.add_argument("--against", metavar="BUILD", help="an older build folder whose rtsim is measured in turn with this one")
    add_cpu_option(ap)
    ap.add_argument("--doc", action="store_true", help="write doc/benchmarks/frames.md (without it: stdout only)")
    a = ap.parse_args()
    if a.runs < 1:
        raise outputs.ToolError(f"--runs {a.runs}: too few")
    if a.frames < 2:
        raise outputs.ToolError(f"--frames {a.frames}: a sequence has at least 2")
    if a.against:
        outputs.check_input(os.path.join(a.against, "rtsim"), "--against")
    if a.doc:
        outputs.check_output(os.path.join(ROOT, "doc", "benchmarks", "frames.md"), "--doc", doc=True)
    return a


def measure(a, builds):
    """{(build, policy): (one frame's walls, K frames' walls, K frames' peak MiB)}."""
    walls = {(b, p): ([], [], []) for b in builds for p in POLICIES}
    for run in range(a.runs):
        for p in POLICIES:
            for label, folder in builds.items():
                rtsim = [os.path.join(folder, "rtsim")] + JOB + ["--balance", p]
                one, _ = timed(rtsim)
                many, mib = timed(rtsim + ["--frames", str(a.frames)])
                w = walls[(label, p)]
                w[0].append(one)
                w[1].append(many)
                w[2].append(mib)
                print(f"run {run + 1}, {label}, {p}: one frame {one:.3f} s, {a.frames} frames {many:.2f} s "
                      f"({many / one:.1f}x)", file=sys.stderr)
    return walls


def table(a, builds, walls, pin):
    rows = ["| build | balancing | one frame | %d frames | %d frames / one frame | each frame after the first | peak memory, %d frames |"
            % (a.frames, a.frames, a.frames), "|---|---|---:|---:|---:|---:|---:|"]
    for label in builds:
        for p in POLICIES:
            one, many, mib = (statistics.median(x) for x in walls[(label, p)])
            rows.append(f"| {label} | {p} | {one:.3f} s | {many:.2f} s | **{many / one:.1f}** | "
                        f"{(many - one) / (a.frames - 1):.3f} s | {max(walls[(label, p)][2]):.0f} MiB |")
    job = " ".join(JOB)
    return ("\n".join(rows) + f"\n\nThe job: `rtsim {job} --balance POLICY [--frames {a.frames}]`; medians of "
            f"{a.runs} runs, one frame and {a.frames} frames alternated run by run"
            + (", the builds in turn" if len(builds) > 1 else "") + f". Machine: {machine()}"
            + (f"; every run pinned to CPU {pin}" if pin is not None else "") + f". Version: {version()}.\n")


def main():
    a = arguments()
    build_fast()
    pin = pin_to_cpu(a.cpu, "bench_frames")
    builds = {"this build": FAST_BUILD}
    if a.against:
        builds["--against " + os.path.basename(os.path.normpath(a.against))] = a.against
    out = table(a, builds, measure(a, builds), pin)
    print(out, end="")
    if a.doc:
        outputs.write_text(os.path.join(ROOT, "doc", "benchmarks", "frames.md"),
                           "# A frame sequence's cost\n\nWritten by `scripts/bench_frames.py --doc`; do not edit by "
                           "hand.\n\n" + out)


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_frames.py", main))
