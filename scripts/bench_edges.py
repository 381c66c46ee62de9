#!/usr/bin/python3
"""Benchmark of rtsim's edges (doc/robustness.md, "Edges"): how soon a stop
takes effect wherever rtsim is (milliseconds from SIGTERM to its exit, in
start-up, in a running frame, between the frames of a sequence, in the
reference runs), the parent's peak memory over a --frames sequence, and
start-up's estimate of the nodes' grids against the peak memory measured.
Medians of --runs runs; with --against BUILD, the older build's too, in the
same run. The tables go to out/results/edges.md (and stdout); with --doc,
to doc/results/edges.md and into doc/robustness.md instead.

  /usr/bin/python3 scripts/bench_edges.py [--runs 5] [--against /path/to/older/rtsim] [--doc]

Uses only the Python standard library; run with /usr/bin/python3."""
import argparse
import contextlib
import os
import random
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import RESULTS, ROOT, RTSIM, publish_table, spd_scene  # noqa: E402

QUIET = ["--no-baseline", "-q", "--image", ""]


def stop_ms(rtsim, args, ready, tmp):
    """Milliseconds from SIGTERM to rtsim's exit, and its exit code. The
    signal goes once `ready(stderr so far, seconds since start)` holds."""
    err = os.path.join(tmp, "err")
    with open(err, "w") as e:
        p = subprocess.Popen([rtsim] + args, stderr=e, stdout=subprocess.DEVNULL, cwd=tmp)
        with ended_on_a_stop(p):
            t0 = time.monotonic()
            while p.poll() is None:
                with open(err) as f:
                    if ready(f.read(), time.monotonic() - t0):
                        break
                time.sleep(0.02)
            if p.poll() is not None:
                return None, p.returncode  # it ended before the signal
            t = time.monotonic()
            p.send_signal(signal.SIGTERM)
            code = p.wait()
            return (time.monotonic() - t) * 1000, code


@contextlib.contextmanager
def ended_on_a_stop(p):
    """Kills the child `p` if the block ends in an exception (a stop of this
    script, Ctrl-C or SIGTERM: outputs.guard), so that no rtsim outlives it."""
    try:
        yield p
    except BaseException:
        p.kill()
        p.wait()
        raise


def peak_mb(rtsim, args, tmp):
    """rtsim's own peak resident memory in MiB (not its children's)."""
    p = subprocess.Popen([rtsim] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=tmp)
    with ended_on_a_stop(p):
        _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    err = p.stderr.read().decode()
    if p.returncode != 0:
        raise outputs.ToolError(f"{' '.join(args)}: rtsim exit {p.returncode}: {err.strip()}", outputs.FAILED)
    return usage.ru_maxrss / 1024, err


def overlap_scene(path, count, radius):
    rng = random.Random(1)
    with open(path, "w") as f:
        f.write("v\nfrom 0 0 -3\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\nl 0 10 -10\nf 1 0 0 0.5 0.5 0 0 1\n")
        for _ in range(count):
            f.write(f"s {rng.random():.4f} {rng.random():.4f} {rng.random():.4f} {radius}\n")


STOPS = [
    ("start-up (300,000 spheres: 0.7 s in, binning them into 64 grids)", ["--spheres", "300000", "--size", "8x8"] + QUIET,
     lambda err, s: s > 0.7),
    ("a running frame (balls-4, 512x512, 8x8x8 mesh, slide)",
     ["--scene", spd_scene("balls-4"), "--size", "512x512", "--mesh", "8", "--balance", "slide", "--vcd", "w.vcd",
      "--report", "r.json"] + QUIET, lambda err, s: s > 4),
    ("between frames (200 frames of 200 spheres, 2x2x2, slide)",
     ["--spheres", "200", "--radius", "0.04", "--size", "16x16", "--mesh", "2", "--frames", "200", "--balance", "slide",
      "--report", "r.json"] + QUIET, lambda err, s: s > 1),
    ("the reference runs (256x256, 4x4x4; the 1x1x1 baseline)",
     ["--spheres", "2000", "--size", "256x256", "--mesh", "4", "-v", "--report", "r.json", "--image", "i.png"],
     lambda err, s: "reference runs:" in err),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--rtsim", default=RTSIM)
    ap.add_argument("--against", help="an older rtsim, measured alike in the same run")
    ap.add_argument("--doc", action="store_true",
                    help="write the tables to doc/results/edges.md and into doc/robustness.md (without it: "
                         "out/results/edges.md)")
    a = ap.parse_args()
    if a.runs < 1:
        raise outputs.ToolError(f"--runs {a.runs}: at least 1")
    outputs.check_input(a.rtsim, "--rtsim")
    if a.against:
        outputs.check_input(a.against, "--against")
    results = outputs.check_output(os.path.join(RESULTS, "edges.md") if a.doc else outputs.out_path("results", "edges.md"),
                                   "the table", doc=a.doc)
    if a.doc:
        outputs.check_output(os.path.join(ROOT, "doc", "robustness.md"), "--doc", doc=True)
    builds = [("this build", a.rtsim)] + ([("older", a.against)] if a.against else [])
    lines = [f"<!-- written by scripts/bench_edges.py{' --doc' if a.doc else ''}; do not edit -->",
             f"Medians of {a.runs} runs; SIGTERM to rtsim, milliseconds to its exit (outputs written), and its exit code.",
             "", "| where | " + " | ".join(f"{n}: ms, exit" for n, _ in builds) + " |",
             "|---|" + "---:|" * len(builds)]
    with tempfile.TemporaryDirectory() as tmp:
        for what, args, ready in STOPS:
            cells = []
            for _, exe in builds:
                got = [stop_ms(exe, args, ready, tmp) for _ in range(a.runs)]
                ms = [m for m, _ in got if m is not None]
                codes = sorted({c for _, c in got})
                cells.append(f"{statistics.median(ms):.0f}, {'/'.join(map(str, codes))}" if ms else
                             f"ended first, {'/'.join(map(str, codes))}")
            lines.append(f"| {what} | " + " | ".join(cells) + " |")
        lines += ["", "The parent's peak memory over a sequence (500 spheres, 16x16, 8x8x8 mesh, slide): MiB.", "",
                  "| frames | " + " | ".join(n for n, _ in builds) + " |", "|---:|" + "---:|" * len(builds)]
        for k in (2, 24, 96):
            args = ["--spheres", "500", "--size", "16x16", "--mesh", "8", "--balance", "slide", "--frames", str(k)] + QUIET
            lines.append(f"| {k} | " + " | ".join(f"{statistics.median(peak_mb(exe, args, tmp)[0] for _ in range(a.runs)):.0f}"
                                                 for _, exe in builds) + " |")
        lines += ["", "Start-up's estimate of the nodes' grids (`-v`) against rtsim's peak memory (this build): MiB.", "",
                  "| scene | mesh | estimate | peak |", "|---|---:|---:|---:|"]
        overlap = os.path.join(tmp, "overlap.nff")
        overlap_scene(overlap, 3000, 2)
        for scene, label, n in ((["--scene", overlap], "3,000 overlapping spheres", 1),
                                (["--scene", overlap], "3,000 overlapping spheres", 2),
                                (["--spheres", "300000"], "300,000 procedural spheres", 4)):
            mb, err = peak_mb(a.rtsim, scene + ["--size", "8x8", "--mesh", str(n), "-v"] + QUIET, tmp)
            est = re.search(r"about (\d+) MiB", err)
            lines.append(f"| {label} | {n}x{n}x{n} | {est.group(1) if est else '?'} | {mb:.0f} |")
    publish_table(lines, results, os.path.join(ROOT, "doc", "robustness.md") if a.doc else None, "edges")


if __name__ == "__main__":
    sys.exit(outputs.guard("bench_edges.py", main))
