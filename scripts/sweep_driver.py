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
import argparse
import concurrent.futures
import contextlib
import csv
import fcntl
import hashlib
import json
import os
import re
import shlex
import signal
import statistics
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
import project  # noqa: E402
from outputs import ToolError  # noqa: E402
from project import ROOT, RTSIM, run_rtsim, version  # noqa: E402
# The journal of finished points (scripts/sweep_journal.py).
from sweep_journal import JOURNALS, RECORD_FIELDS, Journal, bad_metrics, journal_path, locked  # noqa: E402,F401
# Flags every point gets (project.run_rtsim): no reference runs, quiet, no image.
FIXED_FLAGS = project.QUIET + ["--image", ""]
DASK_ADDRESS = re.compile(r"(tcp|tls)://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):([0-9]{1,5})")
DASK_TIMEOUT = 10.0


def jobs_count(text):
    """--jobs: 0 is every core; a negative count is refused."""
    try:
        n = int(text)
    except ValueError:
        n = -1
    if n < 0:
        raise argparse.ArgumentTypeError(f"{text!r}: a count of parallel runs, 0 (one per core) or more")
    return n


def dask_address(text):
    """--dask: a scheduler's address, tcp://HOST:PORT (or tls://)."""
    m = DASK_ADDRESS.fullmatch(text)
    if not m or not 0 < int(m.group(3)) < 65536:
        raise argparse.ArgumentTypeError(f"{text!r}: a scheduler's address, tcp://HOST:PORT (such as tcp://10.0.0.5:8786)")
    return text


one_line_errors = outputs.one_line_errors  # (the experiments call it as sweep's)


def dask_seconds(text):
    """--dask-timeout: seconds, more than 0 and at most an hour (nan and inf
    would wait for ever, or not at all)."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value <= 3600:
        raise argparse.ArgumentTypeError(f"{text!r}: seconds, more than 0 and at most 3600")
    return value


def add_arguments(ap):
    """The driver's flags, shared by every sweep script."""
    if not isinstance(ap, argparse.ArgumentParser) or type(ap).error is argparse.ArgumentParser.error:
        one_line_errors(ap)
    g = ap.add_argument_group("sweep driver")
    g.add_argument("--jobs", type=jobs_count, default=0,
                   help="parallel local runs (default 0: one per core; a negative count is refused)")
    g.add_argument("--dask", metavar="ADDRESS", type=dask_address,
                   help="submit the points to this Dask scheduler (tcp://HOST:PORT, such as tcp://10.0.0.5:8786)")
    g.add_argument("--dask-timeout", metavar="SECONDS", type=dask_seconds, default=DASK_TIMEOUT,
                   help=f"how long to wait for the Dask scheduler to answer (default {DASK_TIMEOUT:g} s); "
                        "no answer: one line, exit 2")
    g.add_argument("--fresh", action="store_true", help="forget the journal and rerun every point")
    g.add_argument("--journal-dir", default=JOURNALS,
                   help="the folder where finished points are journalled (default out/sweeps)")


def add_output_arguments(ap, doc_page=None, plot_only=True):
    """Where a sweep script writes, shared by every one: --out (the results
    folder), --plot-only (only with plot_only: a script that can redraw its
    results from its CSV; one that cannot must not offer it) and --doc,
    which publishes into doc/results/ and, with `doc_page` (a script that
    publishes a table, publish_table), that page's generated sections. Read
    them with parse_outputs (a.plot_only is False where not offered)."""
    one_line_errors(ap)
    ap.add_argument("--out", help="the results folder (default: out/results/; with --doc, doc/results/); "
                                  "in doc/ only with --doc")
    what = "chart and table" if doc_page else "chart"
    if plot_only:
        ap.add_argument("--plot-only", action="store_true", help=f"redraw the {what} from the CSV")
    ap.set_defaults(plot_only=False)
    page = f", and the generated tables of {os.path.relpath(doc_page, ROOT)}" if doc_page else ""
    ap.add_argument("--doc", action="store_true",
                    help="publish: write the results into doc/results/" + page + " (without it nothing in doc/ changes)")
    ap.set_defaults(doc_page=doc_page)


def check_out_folder(path, publish):
    """The results folder of --out: a folder (made if missing), in doc/ only
    when publishing. ToolError otherwise."""
    if os.path.lexists(path) and not os.path.isdir(path):
        raise ToolError(f"--out {path}: not a folder")
    if not publish and outputs.under(path, outputs.DOC):
        raise ToolError(f"--out {path}: in doc/, which changes only with --doc")
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise ToolError(f"--out {path}: {e.strerror}")
    if not os.access(path, os.W_OK | os.X_OK):
        raise ToolError(f"--out {path}: the folder takes no new file")
    return path


def parse_outputs(ap):
    """Parses the flags of a script set up by add_output_arguments: a.out is
    the results folder (checked, made if missing); a.doc the page to publish
    into, or None. A user's run writes under out/ and leaves doc/ as
    committed. Bad flags: one line (ap.error), exit 2."""
    a = ap.parse_args()
    publish = bool(getattr(a, "doc", False))
    a.out = a.out or (project.RESULTS if publish else os.path.join(ROOT, "out", "results"))
    a.doc = a.doc_page if publish else None
    try:
        check_out_folder(a.out, publish)
    except ToolError as e:
        ap.error(str(e))
    return a


# --- what a point is -------------------------------------------------------

_binary_ids = {}


def binary_id(binary):
    """The identity of an rtsim binary: the SHA-256 of its bytes (cached by
    path, size and time of change), so that points run by another binary,
    or by this one rebuilt, are not resumed as this one's."""
    try:
        st = os.stat(binary)
    except OSError as e:
        raise ToolError(f"--rtsim {binary}: {e.strerror}")
    key = (os.path.realpath(binary), st.st_size, st.st_mtime_ns)
    if key not in _binary_ids:
        h = hashlib.sha256()
        with open(binary, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        _binary_ids[key] = h.hexdigest()[:16]
    return _binary_ids[key]


def point_id(args, binary=None, repeats=1):
    """A stable name for a point: a hash of its flags, of the settings in
    the preset files they name (--config), of the rtsim binary that runs it
    (binary_id) and, when a point runs more than once, of its repeats; so
    that a point whose preset was edited, or run by another binary, runs
    again rather than being resumed from the journal."""
    key = "\0".join(str(a) for a in args)
    settings = preset_settings(args)
    if settings is not None:
        key += "\0--config settings\0" + settings
    if binary is not None:
        key += "\0binary\0" + binary_id(binary)
    if repeats > 1:
        key += f"\0repeats\0{repeats}"
    return hashlib.sha1(key.encode()).hexdigest()[:12]


def config_paths(args):
    """The preset files (--config FILE, --config=FILE) a list of flags names, in order."""
    args = [str(a) for a in args]
    paths = []
    for i, a in enumerate(args):
        if a == "--config" and i + 1 < len(args):
            paths.append(args[i + 1])
        elif a.startswith("--config="):
            paths.append(a.split("=", 1)[1])
    return paths


def config_lines(path):
    """The settings of a preset file as rtsim reads it (tb/config_file.h):
    [(line number, name, value)] for its `name = value` lines (comments and
    blanks aside; the value unquoted, its inline comment dropped; a flag
    alone has the value 'true'). ToolError 'PATH:LINE: why' for a line that
    is not text; a line rtsim cannot read is left for rtsim to name."""
    outputs.check_input(path, "--config")
    with open(path, "rb") as f:
        return parse_config(f.read((1 << 20) + 1), path)


def rerun_lines(path):
    """The settings a report's rerun.flags give a run (rtsim --rerun
    REPORT), as config_lines gives a preset's; ToolError if it is not a
    report."""
    outputs.check_input(path, "--rerun")
    try:
        with open(path, "rb") as f:
            flags = json.loads(f.read().decode("utf-8"))["rerun"]["flags"]
        if not isinstance(flags, str):
            raise TypeError
    except (UnicodeDecodeError, json.JSONDecodeError, KeyError, TypeError):
        raise ToolError(f"--rerun {path}: not an rtsim report (no rerun.flags)") from None
    return parse_config(flags.encode(), f"{path}: rerun.flags")


def parse_config(data, origin):
    """config_lines of the bytes of a config text; `origin` names it in errors."""
    out = []
    for n, raw in enumerate(data.split(b"\n"), 1):
        if b"\0" in raw:
            raise ToolError(f"{origin}:{n}: a NUL byte (not a text file)")
        line = raw.strip()
        if not line or line[:1] in (b"#", b";"):
            continue
        try:
            text = line.decode("utf-8")
        except UnicodeDecodeError:
            raise ToolError(f"{origin}:{n}: not UTF-8 text (rtsim's presets are UTF-8)") from None
        m = re.match(r"([A-Za-z0-9][A-Za-z0-9_-]*)\s*(?:=\s*(.*))?$", text)
        if not m:
            continue
        value = "true" if m.group(2) is None else re.split(r"\s#", m.group(2), 1)[0].strip()
        if len(value) >= 2 and value[0] == value[-1] and value[0] in "\"'":
            value = value[1:-1]
        out.append((n, m.group(1), value))
    return out


def preset_settings(args):
    """The settings of the preset files the flags name (their lines without
    comments and blanks, as rtsim reads them), or None if they name none.
    ToolError for a preset that is not a readable text file."""
    paths = config_paths(args)
    if not paths:
        return None
    return "\n".join(f"{name} = {value}" for path in paths for _, name, value in config_lines(path))


def command(args, binary=RTSIM):
    """The command line of a point as run, relative to the repository."""
    rel = os.path.relpath(binary, ROOT)
    return shlex.join([rel] + [str(a) for a in args] + FIXED_FLAGS + ["--report", "REPORT.json"])


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


def _run_pool(todo, binary, jobs, repeats, timeout, stop):
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=jobs)
    futs = {pool.submit(run_repeated, binary, p["args"], repeats, timeout, stop): p for p in todo}
    finished = False
    try:
        for fut in concurrent.futures.as_completed(futs):
            try:
                result = fut.result()
            except Exception as e:  # noqa: BLE001 - reported per point
                result = e
            yield futs[fut], result
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
        for fut in distributed.as_completed(futs):
            try:
                result = fut.result()
            except Exception as e:  # noqa: BLE001 - reported per point
                result = e
            yield futs[fut], result
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
    a journal another sweep holds) raises outputs.ToolError before any run;
    a CSV another process wrote while the sweep ran is not overwritten
    (write_csv), exit 2, the points journalled.
    """
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
            for p in points:
                p["id"] = point_id(p["args"], binary, repeats)
            ids = [p["id"] for p in points]
            if len(set(ids)) != len(ids):
                raise ToolError(f"{name}: two points have the same flags")
            for i in ids:
                why = bad_metrics(journal.done[i]["metrics"], fields) if i in journal.done else None
                if why:
                    journal.forget(i, why)
            todo = [p for p in points if p["id"] not in journal.done]
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
            old = {r["version"] for r in rows if r["version"] != ver}
            if old:
                print(f"{name}: {sum(r['version'] != ver for r in rows)} point(s) resumed from other versions "
                      f"({', '.join(sorted(old))}); --fresh reruns them", file=sys.stderr)
            if csv_path:
                write_csv(csv_path, rows, seen)
    finally:
        if connection:
            connection[2].close(timeout=2)
            opts.dask_connection = None
    return rows


def _journal_runs(runs, journal, extract, binary, ver, progress):
    """Journals each point as it finishes; returns the failures (command: error)."""
    failed = []
    for p, result in runs:
        if isinstance(result, Exception):
            failed.append(f"{command(p['args'], binary)}: {result}")
        else:
            report, wall, walls = result
            rec = {"id": p["id"], "params": p["params"], "metrics": extract(report),
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
    return outputs.read_csv(csv_path)


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
