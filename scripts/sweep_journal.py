"""The sweep driver's journal (scripts/sweep_driver.py): finished points, one
JSON record per line in out/sweeps/NAME.jsonl, appended as they finish;
locked while a sweep uses it; a damaged line named FILE:LINE and skipped,
its point run again. Standard library only."""
import fcntl
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from outputs import ToolError  # noqa: E402
from project import ROOT  # noqa: E402

JOURNALS = os.path.join(ROOT, "out", "sweeps")

RECORD_FIELDS = {"id": str, "params": dict, "metrics": dict, "wall_s": (int, float), "command": str, "version": str}
_held = {}  # journal path -> [Journal, holders]: a sweep of this process may take its own lock again


def journal_path(name, opts=None, make=True):
    """NAME's journal in the journal folder (--journal-dir), both checked:
    NAME a name, the folder a folder outside doc/. The default out/sweeps
    is made with its parents; a folder the user names is made only when its
    parent exists (as mkdir would: a typo makes no chain of folders), the
    rule --out follows too. Nothing is made unless `make` (a check before
    any work writes nothing)."""
    outputs.check_name(name, "NAME")
    folder = getattr(opts, "journal_dir", None)
    if folder == "":
        raise ToolError("--journal-dir '': an empty folder name")
    folder = folder or JOURNALS
    if os.path.lexists(folder) and not os.path.isdir(folder):
        raise ToolError(f"--journal-dir {folder}: not a folder")
    if outputs.under(folder, outputs.DOC):
        raise ToolError(f"--journal-dir {folder}: in doc/, which a sweep does not write")
    path = os.path.abspath(os.path.join(folder, name + ".jsonl"))
    parent = os.path.dirname(os.path.abspath(folder))
    if not os.path.lexists(folder) and os.path.abspath(folder) != os.path.abspath(JOURNALS) and not os.path.isdir(parent):
        raise ToolError(f"--journal-dir {folder}: no folder {parent} to make it in")
    if not make:
        return path
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as e:
        raise ToolError(f"--journal-dir {folder}: {e.strerror}")
    return outputs.check_output(path, "journal")


class Journal:
    """Finished points, one JSON object per line, appended as they finish.

    The journal file is locked (flock, exclusive, not waiting) while a sweep
    uses it: a second sweep of the same NAME at the same time is refused
    with one line rather than both writing one journal and one CSV. A
    damaged line (not UTF-8, not JSON, not a record, cut short by a kill)
    is reported once as FILE:LINE and skipped; any point it held runs
    again. A journal this sweep created and left empty (refused before any
    point finished) is removed when it closes."""

    def __init__(self, path, fresh=False, name=None):
        self.path = path
        self.done = {}
        self.lines = {}  # id -> its line in the journal (for messages)
        flags = os.O_RDWR | os.O_APPEND | os.O_CLOEXEC
        try:
            self.fd, self.created = os.open(path, flags | os.O_CREAT | os.O_EXCL, 0o666), True
        except FileExistsError:
            self.fd, self.created = os.open(path, flags | os.O_CREAT, 0o666), False
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(self.fd)  # (created: then by the other sweep, which holds it)
            raise ToolError(f"sweep {name or os.path.basename(path)}: another sweep of that NAME is running "
                            f"(its journal {os.path.relpath(path)} is locked); wait for it or give another NAME") from None
        if fresh:
            os.ftruncate(self.fd, 0)
        self._read()

    def _read(self):
        with open(self.fd, "rb", closefd=False) as f:
            f.seek(0)
            data = f.read()
        self.ends_clean = not data or data.endswith(b"\n")
        for n, raw in enumerate(data.split(b"\n"), 1):
            if not raw.strip():
                continue
            rec, why = self._record(raw)
            if rec is None:
                print(f"{self.path}:{n}: {why}; skipped (any point it held runs again)", file=sys.stderr)
            else:
                self.done[rec["id"]] = rec
                self.lines[rec["id"]] = n

    @staticmethod
    def _record(raw):
        """(the record of a journal line, None) or (None, what is wrong with it)."""
        try:
            rec = json.loads(raw.decode("utf-8"))
        except UnicodeDecodeError:
            return None, "not UTF-8 text"
        except json.JSONDecodeError:
            return None, "not a JSON line (cut short by a kill?)"
        except RecursionError:
            return None, "not a journal record (nested too deep)"
        if not isinstance(rec, dict):
            return None, "not a journal record (a JSON object)"
        for field, kind in RECORD_FIELDS.items():
            if not isinstance(rec.get(field), kind) or isinstance(rec.get(field), bool):
                return None, f"not a journal record (no {field!r})"
        if not rec["metrics"]:
            return None, "not a journal record (empty 'metrics')"
        return rec, None

    def add(self, rec):
        """Appends a record with one write (a stop arrives between records,
        not inside one), after a newline if the journal ended in a cut-short
        line, and flushes it to the disk."""
        line = json.dumps(rec, sort_keys=True) + "\n"
        if not self.ends_clean:
            line, self.ends_clean = "\n" + line, True
        os.write(self.fd, line.encode())
        os.fsync(self.fd)
        self.done[rec["id"]] = rec

    def forget(self, point, why):
        """Drops a record whose metrics this sweep cannot use (bad_metrics):
        named FILE:LINE, its point runs again (its new record, appended,
        wins when the journal is read next)."""
        print(f"{self.path}:{self.lines.get(point, '?')}: {why}; skipped (its point runs again)", file=sys.stderr)
        del self.done[point]

    def close(self):
        # Still locked: a journal this sweep made and never wrote goes.
        if self.created and os.fstat(self.fd).st_size == 0:
            try:
                os.remove(self.path)
            except OSError:
                pass
        os.close(self.fd)  # (and with it the lock)


def bad_metrics(metrics, fields=None):
    """What is wrong with a record's metrics for a sweep whose figures are
    `fields` ({column: kind}, kind float for a number, str for text), or
    None if nothing: a journal edited by hand, or written by another
    version of the sweep, must not put 'abc' in a CSV or stop the sweep."""
    for column, kind in (fields or {}).items():
        value = metrics.get(column)
        if kind is float:
            if isinstance(value, bool) or not isinstance(value, (int, float)) or value != value:
                return f"metrics {column!r} is {value!r}, not a number"
        elif not isinstance(value, kind):
            return f"metrics {column!r} is {value!r}, not {kind.__name__}"
    return None


class locked:
    """`with locked(path, fresh, name) as journal:` the journal, locked
    against other processes for the block; this process may hold it again
    inside (a command line that runs a sweep and then writes its CSV)."""

    def __init__(self, path, fresh=False, name=None):
        self.path, self.fresh, self.name = os.path.realpath(path), fresh, name

    def __enter__(self):
        held = _held.get(self.path)
        if held is None:
            held = _held[self.path] = [Journal(self.path, self.fresh, self.name), 0]
        held[1] += 1
        return held[0]

    def __exit__(self, *exc):
        held = _held[self.path]
        held[1] -= 1
        if held[1] == 0:
            held[0].close()
            del _held[self.path]
