"""The sweep driver every experiment script uses.

A sweep is a list of points; a point is one rtsim run, named by its
parameters (a dict) and given as its command-line flags. The driver
- runs the points in parallel on the local cores (one rtsim process each),
  or submits them to a Dask distributed cluster given a scheduler address;
- shows progress (done / total, elapsed, estimated time left) on stderr;
- journals every finished point to out/sweeps/<name>.jsonl as soon as it
  finishes, and on the next start skips every point already in the journal
  (a point is identified by a hash of its flags), so an interrupted or
  extended sweep never redoes finished work;
- writes the CSV in point order, with each point's exact command and the
  version (git describe) of the tree that ran it.

From the command line it sweeps any flags of any scene (scripts/sweep.py
--help; the grid and its rows are in scripts/sweep_grid.py).

Standard library only, except python3-distributed for --dask. Runs rtsim
through project.run_rtsim (scripts/project.py).
Dask workers must see the same checkout at the same path (a shared file
system): they run the rtsim binary named in the command.
"""
import concurrent.futures
import csv
import hashlib
import json
import os
import shlex
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import project  # noqa: E402
from project import ROOT, RTSIM, run_rtsim, version  # noqa: E402

JOURNALS = os.path.join(ROOT, "out", "sweeps")
# Flags every point gets (project.run_rtsim): no reference runs, quiet, no image.
FIXED_FLAGS = project.QUIET + ["--image", ""]


def add_arguments(ap):
    """The driver's flags, shared by every sweep script."""
    g = ap.add_argument_group("sweep driver")
    g.add_argument("--jobs", type=int, default=0, help="parallel local runs (default: the number of cores)")
    g.add_argument("--dask", metavar="ADDRESS", help="submit the points to this Dask scheduler (tcp://host:8786)")
    g.add_argument("--fresh", action="store_true", help="forget the journal and rerun every point")
    g.add_argument("--journal-dir", default=JOURNALS, help="where finished points are journalled")


def add_output_arguments(ap, doc_page=None):
    """Where a sweep script writes, shared by every one: --out (the results
    folder), --plot-only, and --doc, which publishes into doc/results/ and,
    with `doc_page` (a script that publishes a table, publish_table), that
    page's generated sections. Read them with parse_outputs."""
    ap.add_argument("--out", help="the results folder (default: out/results/; with --doc, doc/results/)")
    what = "chart and table" if doc_page else "chart"
    ap.add_argument("--plot-only", action="store_true", help=f"redraw the {what} from the CSV")
    page = f", and the generated tables of {os.path.relpath(doc_page, ROOT)}" if doc_page else ""
    ap.add_argument("--doc", action="store_true",
                    help="publish: write the results into doc/results/" + page + " (without it nothing in doc/ changes)")
    ap.set_defaults(doc_page=doc_page)


def parse_outputs(ap):
    """Parses the flags of a script set up by add_output_arguments: a.out is
    the results folder (made if missing); a.doc the page to publish into, or
    None. A user's run writes under out/ and leaves doc/ as committed."""
    a = ap.parse_args()
    publish = bool(getattr(a, "doc", False))
    a.out = a.out or (project.RESULTS if publish else os.path.join(ROOT, "out", "results"))
    a.doc = a.doc_page if publish else None
    os.makedirs(a.out, exist_ok=True)
    return a


def point_id(args):
    """A stable name for a point: a hash of its flags and, when they name a
    preset file (--config), of the settings in it, so that a point whose
    preset was edited is run again rather than resumed from the journal."""
    key = "\0".join(str(a) for a in args)
    settings = preset_settings(args)
    if settings is not None:
        key += "\0--config settings\0" + settings
    return hashlib.sha1(key.encode()).hexdigest()[:12]


def preset_settings(args):
    """The settings of the preset file the flags name (its lines without
    comments and blanks, as rtsim reads them), or None if they name none or
    it cannot be read (rtsim then says why)."""
    args = [str(a) for a in args]
    path = None
    for i, a in enumerate(args):
        if a == "--config" and i + 1 < len(args):
            path = args[i + 1]
        elif a.startswith("--config="):
            path = a.split("=", 1)[1]
    if path is None:
        return None
    try:
        with open(path) as f:
            lines = [ln.split("#", 1)[0].strip() for ln in f if not ln.lstrip().startswith(";")]
    except OSError:
        return None
    return "\n".join(" ".join(ln.split()) for ln in lines if ln)


def command(args, binary=RTSIM):
    """The command line of a point as run, relative to the repository."""
    rel = os.path.relpath(binary, ROOT)
    return shlex.join([rel] + [str(a) for a in args] + FIXED_FLAGS + ["--report", "REPORT.json"])


def run_repeated(binary, args, repeats=1, timeout=None):
    """Runs a point `repeats` times; the median wall time and the report of the
    first run. Every run must give the same render time (the model is
    deterministic), otherwise this is an error."""
    walls, first = [], None
    for _ in range(repeats):
        rep, wall = run_rtsim(args, binary, timeout)
        if first is None:
            first = rep
        elif rep["render_time_ns"] != first["render_time_ns"]:
            raise RuntimeError("two runs of the same point gave different render times")
        walls.append(wall)
    return first, statistics.median(walls)


class Journal:
    """Finished points, one JSON object per line, appended as they finish."""

    def __init__(self, path, fresh):
        self.path = path
        self.done = {}
        os.makedirs(os.path.dirname(path), exist_ok=True)
        if fresh and os.path.exists(path):
            os.remove(path)
        if os.path.exists(path):
            with open(path) as f:
                for line in f:
                    line = line.strip()
                    if not line:
                        continue
                    try:
                        rec = json.loads(line)
                    except json.JSONDecodeError:
                        continue  # a line cut short by an interrupted run
                    self.done[rec["id"]] = rec

    def add(self, rec):
        self.done[rec["id"]] = rec
        with open(self.path, "a") as f:
            f.write(json.dumps(rec, sort_keys=True) + "\n")
            f.flush()
            os.fsync(f.fileno())


class Progress:
    def __init__(self, name, total, resumed):
        self.name, self.total, self.done, self.resumed = name, total, resumed, resumed
        self.t0 = time.monotonic()

    def tick(self):
        self.done += 1
        ran = self.done - self.resumed
        elapsed = time.monotonic() - self.t0
        left = (self.total - self.done) * elapsed / ran if ran else 0
        print(f"\r{self.name}: {self.done}/{self.total} points ({self.resumed} resumed), "
              f"{elapsed:.0f} s, about {left:.0f} s left   ", end="", file=sys.stderr, flush=True)


def _local(todo, binary, jobs, repeats, timeout):
    """Yields (point, result or exception) as local runs finish."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futs = {pool.submit(run_repeated, binary, p["args"], repeats, timeout): p for p in todo}
        for fut in concurrent.futures.as_completed(futs):
            try:
                yield futs[fut], fut.result()
            except Exception as e:  # noqa: BLE001 - reported per point
                yield futs[fut], e


def _dask(todo, binary, address, repeats, timeout):
    """Yields (point, result or exception) as the cluster finishes them."""
    import cloudpickle
    import distributed
    # Workers need not import these modules: ship their functions by value.
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    cloudpickle.register_pickle_by_value(project)
    with distributed.Client(address) as client:
        futs = {client.submit(run_repeated, binary, p["args"], repeats, timeout, pure=False): p for p in todo}
        for fut in distributed.as_completed(futs):
            try:
                yield futs[fut], fut.result()
            except Exception as e:  # noqa: BLE001 - reported per point
                yield futs[fut], e


def run(name, points, extract, csv_path, opts=None, repeats=1, timeout=None, binary=RTSIM):
    """Runs a sweep and writes its CSV; returns the rows in point order.

    points:  list of {"params": {name: value}, "args": [rtsim flags]}
    extract: report dict -> {column: value}, the figures kept per point
    opts:    the parsed flags of add_arguments (None: local, all cores)
    repeats: runs per point; wall_s is their median (for timing sweeps)
    """
    jobs = getattr(opts, "jobs", 0) or os.cpu_count() or 1
    dask = getattr(opts, "dask", None)
    journal = Journal(os.path.join(getattr(opts, "journal_dir", JOURNALS), name + ".jsonl"),
                      getattr(opts, "fresh", False))
    ver = version()
    for p in points:
        p["id"] = point_id(p["args"])
    ids = [p["id"] for p in points]
    if len(set(ids)) != len(ids):
        raise ValueError(f"{name}: two points have the same flags")
    todo = [p for p in points if p["id"] not in journal.done]
    progress = Progress(name, len(points), len(points) - len(todo))
    runs = _dask(todo, binary, dask, repeats, timeout) if dask else _local(todo, binary, jobs, repeats, timeout)
    failed = []
    for p, result in runs:
        if isinstance(result, Exception):
            failed.append(f"{command(p['args'], binary)}: {result}")
        else:
            report, wall = result
            journal.add({"id": p["id"], "params": p["params"], "metrics": extract(report),
                         "wall_s": round(wall, 4), "command": command(p["args"], binary), "version": ver})
        progress.tick()
    print(file=sys.stderr)
    if failed:
        raise RuntimeError(f"{name}: {len(failed)} point(s) failed; first: {failed[0]}")
    rows = []
    for p in points:
        rec = journal.done[p["id"]]
        rows.append({**p["params"], **rec["metrics"], "wall_s": rec["wall_s"],
                     "id": rec["id"], "version": rec["version"], "command": rec["command"]})
    old = {r["version"] for r in rows if r["version"] != ver}
    if old:
        print(f"{name}: {sum(r['version'] != ver for r in rows)} point(s) resumed from other versions "
              f"({', '.join(sorted(old))}); --fresh reruns them", file=sys.stderr)
    if csv_path:
        write_csv(csv_path, rows)
    return rows


def write_csv(path, rows):
    """Writes a list of dicts with the same keys as CSV."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


if __name__ == "__main__":  # the command line: sweeps of any flags (scripts/sweep_grid.py)
    import sweep_grid
    sys.exit(sweep_grid.main())
