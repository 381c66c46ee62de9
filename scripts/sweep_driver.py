"""The sweep driver every experiment script uses.

A sweep is a list of points; a point is one rtsim run, named by its
parameters (a dict) and given as its command-line flags. The driver
- runs the points in parallel on the local cores (one rtsim process each),
  or submits them to a Dask distributed cluster given a scheduler address;
- shows progress (done / total, elapsed, estimated time left) on stderr;
- journals every finished point to out/sweeps/<name>.jsonl as soon as it
  finishes, and on the next start skips every point already in the journal
  (a point is identified by a hash of its flags), so an interrupted or
  extended sweep never redoes finished work (scripts/sweep_journal.py);
- writes the CSV in point order, with each point's exact command and the
  version (git describe) of the tree that ran it.

From the command line, scripts/sweep.py sweeps any flags of any scene
(--help; the grid and its rows are in scripts/sweep_grid.py).

Standard library only, except python3-distributed for --dask. Runs rtsim
through project.run_rtsim (scripts/project.py).
Dask workers must see the same checkout at the same path (a shared file
system): they run the rtsim binary named in the command.
"""
import concurrent.futures
import contextlib
import csv
import fcntl
import os
import signal
import statistics
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import csv_rows  # noqa: E402
import outputs  # noqa: E402
import project  # noqa: E402
from outputs import ToolError  # noqa: E402
from project import ROOT, RTSIM, run_rtsim, version  # noqa: E402,F401
# The journal of finished points (scripts/sweep_journal.py).
from sweep_journal import JOURNALS, RECORD_FIELDS, Journal, bad_metrics, journal_path, locked  # noqa: E402,F401
# The flags every sweep script shares (scripts/sweep_flags.py), the driver's API.
from sweep_flags import (DASK_TIMEOUT, add_arguments, add_output_arguments, check_out_folder,  # noqa: E402,F401
                         extra_flags, parse_outputs)


# What a point is (scripts/sweep_points.py).
from sweep_points import FIXED_FLAGS, check_point, command, point_id  # noqa: E402,F401


class Cancelled(Exception):
    """A queued point that a stop reached before it started."""


def run_repeated(binary, args, repeats=1, timeout=None, stop=None):
    """Runs a point `repeats` times: (the report of the first run, the median
    wall time, every run's wall time). Every run must give the same render
    time (the model is deterministic), otherwise this is an error. A set
    `stop` event ends it before the next run starts."""
    walls, first = [], None
    for _ in range(repeats):
        if stop is not None and stop.is_set():
            raise Cancelled()
        rep, wall = run_rtsim(args, binary, timeout)
        if first is None:
            first = rep
        elif rep["render_time_ns"] != first["render_time_ns"]:
            raise RuntimeError("two runs of the same point gave different render times")
        walls.append(wall)
    return first, statistics.median(walls), walls


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
        outputs.line_open = True  # (a stop's line starts on a line of its own)


# --- running the points ----------------------------------------------------

def _end_running(futs, within=0.8):
    """After a stop: kills the children of the points still running, and any
    a worker thread started in the meantime, until every point has ended
    (each ends as soon as its child is killed)."""
    # (Not concurrent.futures.wait: a future the pool's shutdown cancelled
    # stays CANCELLED, never "notified", and wait would count it as running
    # until the deadline: every stop took the whole 0.8 s.)
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        outputs.clean_up()
        if all(f.done() for f in futs):
            return
        time.sleep(0.01)


STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


@contextlib.contextmanager
def _stop_first(stop):
    """While the block runs, a stop signal sets `stop` before anything else
    (before the handler in place, outputs.stop_handlers' under guard, kills
    the children): a worker whose rtsim was killed sees it and starts no
    queued point. Without a handler of the tool's, a stop kills the
    children, removes the temporaries and raises outputs.Stopped. An
    ignored signal stays ignored."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = {s: signal.getsignal(s) for s in STOP_SIGNALS}

    def handler(signum, frame):
        stop.set()
        then = before[signum]
        if callable(then) and then is not signal.default_int_handler:
            then(signum, frame)
        outputs.clean_up()
        raise outputs.Stopped(signum)

    for s, then in before.items():
        if then is not signal.SIG_IGN:
            signal.signal(s, handler)
    try:
        yield
    finally:
        for s, then in before.items():
            signal.signal(s, then)


def _local(todo, binary, jobs, repeats, timeout):
    """Yields (point, result or exception) as local runs finish. On a stop
    (or any other end before the last point), no queued point starts and
    the running ones are killed."""
    stop = threading.Event()
    with _stop_first(stop):
        yield from _run_pool(todo, binary, jobs, repeats, timeout, stop)


def _as_finished(futs, as_completed):
    """Yields (point, result or exception) as the futures {future: point}
    finish, by the pool's or the cluster's as_completed."""
    for fut in as_completed(futs):
        try:
            result = fut.result()
        except Exception as e:  # noqa: BLE001 - reported per point
            result = e
        yield futs[fut], result


def _run_pool(todo, binary, jobs, repeats, timeout, stop):
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=jobs)
    futs = {pool.submit(run_repeated, binary, p["args"], repeats, timeout, stop): p for p in todo}
    finished = False
    try:
        yield from _as_finished(futs, concurrent.futures.as_completed)
        finished = True
    finally:
        if not finished:
            stop.set()
            pool.shutdown(wait=False, cancel_futures=True)
            _end_running(futs)
        pool.shutdown(wait=False)


def _connect(address, timeout):
    """A Dask client of the scheduler at `address`, or ToolError within
    `timeout` seconds: one line, not distributed's traceback."""
    try:
        import logging
        import cloudpickle
        import distributed
    except ImportError:
        raise ToolError("--dask needs Debian's python3-distributed (bash scripts/setup.sh dask)") from None
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    # A stop while connecting leaves the client's tasks pending: asyncio
    # would complain of them in lines of its own at exit.
    logging.getLogger("asyncio").setLevel(logging.CRITICAL)
    try:
        return distributed, cloudpickle, distributed.Client(address, timeout=timeout)
    except Exception as e:  # noqa: BLE001 - OSError, TimeoutError, asyncio's: all say "no scheduler there"
        raise ToolError(f"--dask {address}: no scheduler answered within {timeout:g} s (--dask-timeout)"
                        f" ({type(e).__name__})") from None


def connect(opts):
    """The Dask connection of --dask (distributed, cloudpickle, client), made
    once and kept in opts, or None without --dask: the scheduler answers
    before anything is written, or one line and exit 2."""
    dask = getattr(opts, "dask", None)
    if not dask:
        return None
    if getattr(opts, "dask_connection", None) is None:
        opts.dask_connection = _connect(dask, getattr(opts, "dask_timeout", DASK_TIMEOUT))
    return opts.dask_connection


def kill_runs_of(binary):
    """On a Dask worker: kills the worker's children that run `binary` (the
    points a stopped sweep left running there; cancelling a future does not
    end a task already running). Returns how many."""
    import signal as signals  # (runs on a worker: shipped by value)
    me, killed = os.getpid(), 0
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                parent = int(f.read().rsplit(")", 1)[1].split()[1])
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                argv = f.read().decode(errors="replace").split("\0")
        except (OSError, ValueError, IndexError):
            continue
        if parent == me and binary in argv:
            try:
                os.kill(int(entry), signals.SIGKILL)
                killed += 1
            except OSError:
                pass
    return killed


def _dask(todo, binary, connection, repeats, timeout):
    """Yields (point, result or exception) as the cluster finishes them
    (connection: _connect's)."""
    distributed, cloudpickle, client = connection
    # Workers need not import these modules: ship their functions by value.
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    cloudpickle.register_pickle_by_value(project)
    futs, finished = {}, False
    try:
        futs = {client.submit(run_repeated, binary, p["args"], repeats, timeout, pure=False): p for p in todo}
        yield from _as_finished(futs, distributed.as_completed)
        finished = True
    finally:
        if futs:
            client.cancel(list(futs))
        if futs and not finished:  # (a stop: the runs already on the workers end too)
            with contextlib.suppress(Exception):
                client.run(kill_runs_of, binary, on_error="ignore")


def run(name, points, extract, csv_path, opts=None, repeats=1, timeout=None, binary=RTSIM, fields=None, counts=None):
    """Runs a sweep and writes its CSV; returns the rows in point order.

    points:  list of {"params": {name: value}, "args": [rtsim flags]}
    extract: report dict -> {column: value}, the figures kept per point
    opts:    the parsed flags of add_arguments (None: local, all cores)
    repeats: runs per point; wall_s is their median (for timing sweeps),
             wall_s_min and wall_s_max their spread (with repeats > 1)
    fields:  {column: float or str} that extract gives: a journalled
             record without them runs again (bad_metrics)
    counts:  a dict, given: counts["ran"] is the number of points run (the
             others resumed)
    Bad input (a NAME that is not a name, a CSV path that is not an output,
    a journal another sweep holds, a point's flags that sweep_points.
    check_point refuses) raises outputs.ToolError before any run;
    a CSV another process wrote while the sweep ran is not overwritten
    (write_csv), exit 2, the points journalled.
    """
    _check_points(name, points)
    jobs = getattr(opts, "jobs", 0) or 0
    if jobs < 0:
        raise ToolError(f"--jobs {jobs}: 0 (one per core) or more")
    jobs = jobs or os.cpu_count() or 1
    if repeats < 1:
        raise ToolError(f"--repeat {repeats}: at least 1")
    dask = getattr(opts, "dask", None)
    path = journal_path(name, opts)
    if csv_path:
        csv_path = outputs.check_output(csv_path, "--csv", doc=bool(getattr(opts, "doc", None)))
        outputs.check_distinct([("the journal", path), ("--csv", csv_path)])
        seen = csv_state(csv_path)
    connection = connect(opts)
    try:
        with locked(path, getattr(opts, "fresh", False), name) as journal:
            ver = version()
            todo = _to_run(name, points, journal, binary, repeats, fields)
            if counts is not None:
                counts["ran"] = len(todo)
            progress = Progress(name, len(points), len(points) - len(todo))
            runs = _dask(todo, binary, connection, repeats, timeout) if dask else _local(todo, binary, jobs, repeats, timeout)
            try:
                failed = _journal_runs(runs, journal, extract, binary, ver, progress)
            finally:
                runs.close()  # (on a stop: no queued point starts, the running ones are killed)
            if todo and outputs.line_open:
                print(file=sys.stderr)
                outputs.line_open = False
            if failed:
                raise ToolError(f"{name}: {len(failed)} point(s) failed; first: {failed[0]}", outputs.FAILED)
            rows = [row_of(p, journal.done[p["id"]], repeats) for p in points]
            _say_older(name, rows, ver)
            if csv_path:
                write_csv(csv_path, rows, seen)
    finally:
        if connection:
            connection[2].close(timeout=2)
            opts.dask_connection = None
    return rows


def _check_points(name, points):
    """Every point's flags (sweep_points.check_point), before the journal and any run."""
    for p in points:
        try:
            check_point(p["args"])
        except ToolError as e:
            raise ToolError(f"{name}: {e}") from None


def _to_run(name, points, journal, binary, repeats, fields):
    """Each point named by its flags (p["id"]); those the journal does not
    hold, or holds without the figures `fields` asks for, to run."""
    for p in points:
        p["id"] = point_id(p["args"], binary, repeats)
    ids = [p["id"] for p in points]
    if len(set(ids)) != len(ids):
        raise ToolError(f"{name}: two points have the same flags")
    for i in ids:
        why = bad_metrics(journal.done[i]["metrics"], fields) if i in journal.done else None
        if why:
            journal.forget(i, why)
    return [p for p in points if p["id"] not in journal.done]


def _say_older(name, rows, ver):
    """One line where points were resumed from another version of the tree."""
    old = {r["version"] for r in rows if r["version"] != ver}
    if old:
        print(f"{name}: {sum(r['version'] != ver for r in rows)} point(s) resumed from other versions "
              f"({', '.join(sorted(old))}); --fresh reruns them", file=sys.stderr)


def _journal_runs(runs, journal, extract, binary, ver, progress):
    """Journals each point as it finishes; returns the failures (command: error)."""
    failed = []
    for p, result in runs:
        if isinstance(result, Exception):
            failed.append(f"{command(p['args'], binary)}: {result}")
        else:
            report, wall, walls = result
            try:
                metrics = extract(report)
            except (KeyError, IndexError, TypeError, ValueError) as e:  # (--rtsim another program, or an older rtsim)
                failed.append(f"{command(p['args'], binary)}: its report lacks what the sweep reads "
                              f"({type(e).__name__}: {e}): not this rtsim's report?")
                progress.tick()
                continue
            rec = {"id": p["id"], "params": p["params"], "metrics": metrics,
                   "wall_s": round(wall, 4), "command": command(p["args"], binary), "version": ver}
            if len(walls) > 1:
                rec["walls_s"] = [round(w, 4) for w in walls]
            journal.add(rec)
        progress.tick()
    return failed


def row_of(point, rec, repeats):
    """A point's CSV row: its parameters, its figures, its wall time (and
    with repeats, their spread) and its provenance."""
    row = {**point["params"], **rec["metrics"], "wall_s": rec["wall_s"]}
    if repeats > 1:
        walls = rec.get("walls_s") or [rec["wall_s"]]
        row.update({"wall_s_min": min(walls), "wall_s_max": max(walls)})
    row.update({"id": rec["id"], "version": rec["version"], "command": rec["command"]})
    return row


_UNSEEN = object()


def csv_state(path):
    """What a CSV path holds, to tell later whether another process wrote
    it: None (absent) or its (device, inode, size, time of change)."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return None
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns)


def swept_rows(a, csv_path, make):
    """A sweep script's rows: with --plot-only, read from its CSV of an earlier
    run (which must be there); otherwise make()'s, written to that CSV first."""
    if a.plot_only:
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        write_csv(csv_path, make())
    return csv_rows.read_csv(csv_path)


def write_csv(path, rows, seen=_UNSEEN, shown=None):
    """Writes a list of dicts with the same keys as CSV, through a temporary
    beside it renamed over it (outputs.atomic): a kill never leaves half a
    CSV. The caller has checked `path` (outputs.check_output).

    With `seen` (csv_state when the sweep started), the CSV is written only
    if it still is what the sweep saw: two sweeps writing one CSV at once
    (another NAME, another --journal-dir) would silently replace each
    other's rows, so the later one refuses in one line (exit 2; its points
    are journalled, a rerun with another --csv writes them at once). The
    check and the rename hold a lock on the CSV's folder (flock), which
    every sweep takes to write: no other sweep writes between them."""
    if not rows:
        raise ToolError(f"{path}: no rows to write")
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    folder = os.open(os.path.dirname(os.path.abspath(path)), os.O_RDONLY | os.O_CLOEXEC)
    try:
        fcntl.flock(folder, fcntl.LOCK_EX)
        if seen is not _UNSEEN and csv_state(path) != seen:
            raise ToolError(f"{shown or '--csv ' + path}: written by another process while this sweep ran (another "
                            "sweep with the same --csv?); left as it is: every point is journalled, rerun with "
                            "another --csv to write this sweep's rows")
        with outputs.atomic(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()), lineterminator="\n")
            w.writeheader()
            w.writerows(rows)
    finally:
        os.close(folder)  # (and with it the lock)
