"""Running rtsim from the sweep scripts: one point = one rtsim run with a
report, run in parallel on the local cores. Standard library only."""
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RTSIM = os.path.join(ROOT, "build", "rtsim")


def write_csv(path, rows):
    """Writes a list of dicts with the same keys as CSV."""
    import csv
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def run_point(args):
    """Runs rtsim with `args` (a list); returns its report as a dict."""
    fd, report = tempfile.mkstemp(suffix=".json")
    os.close(fd)
    try:
        cmd = [RTSIM] + [str(a) for a in args] + ["--no-baseline", "-q", "--image", "", "--report", report]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)}: {p.stderr.strip()}")
        with open(report) as f:
            return json.load(f)
    finally:
        os.remove(report)


def run_all(points, jobs=None, label="runs"):
    """Runs every point (a list of argument lists) in parallel; returns the
    reports in the same order, printing progress on stderr."""
    jobs = jobs or os.cpu_count() or 1
    out = [None] * len(points)
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(run_point, p): i for i, p in enumerate(points)}
        for done, fut in enumerate(concurrent.futures.as_completed(futures), 1):
            out[futures[fut]] = fut.result()
            print(f"\r{label}: {done}/{len(points)}", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    return out
