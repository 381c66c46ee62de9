"""The output policy every tool in scripts/ shares: the same promises rtsim
keeps at its edges (sw/output_file.h; ../shared/doc/architecture.md,
invariant 7), for Python.

- A NAME is a name: letters, digits, '-', '_' and '.', not starting with a
  dot; never a path (check_name).
- Outputs go under out/ unless a flag names a path (out_path); nothing is
  written into doc/ without --doc (check_output(..., doc=False)).
- An output is absent or a regular file: folders, devices, FIFOs, sockets
  and symbolic links are refused before any work, and so is an output that
  names an input or another output (check_output, check_distinct).
- Inputs are regular files (check_input): a FIFO or /dev/zero would block
  or never end.
- Every output is written to a temporary beside it, NAME.incomplete-XXXX,
  and renamed over its path when complete (atomic, savefig): a kill while
  writing never leaves half a file that looks like a result.
- A stop (Ctrl-C, SIGTERM, SIGHUP) ends the tool at once: its children
  (run_child) are killed, its temporaries removed, exit 128 + the signal's
  number, as rtsim's: 130 for Ctrl-C, 143 for SIGTERM (stop_handlers).
- Bad input ends the tool with one line naming the tool, the file and the
  line, and exit 2; never a traceback (guard).

Standard library only."""
import contextlib
import os
import re
import signal
import stat
import subprocess
import sys
import tempfile
import threading

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "out")
DOC = os.path.join(ROOT, "doc")
NAME_RE = re.compile(r"[A-Za-z0-9_-][A-Za-z0-9_.-]*")
NAME_MAX = 100

BAD_INPUT, FAILED, STOPPED = 2, 1, 130  # (STOPPED: Ctrl-C's; a stop exits 128 + its signal)


class ToolError(Exception):
    """Bad input: one line, exit 2 (or `code`)."""

    def __init__(self, message, code=BAD_INPUT):
        super().__init__(message)
        self.code = code


def check_name(name, what="NAME"):
    """`name` if it is a name (letters, digits, '-', '_', '.'; no separator,
    not starting with a dot, at most NAME_MAX characters), else ToolError."""
    if not isinstance(name, str) or not NAME_RE.fullmatch(name) or len(name) > NAME_MAX or ".." in name:
        raise ToolError(f"{what} '{one_line(name)}': a name, not a path: letters, digits, '-', '_' and '.' "
                        f"(not first), at most {NAME_MAX} characters")
    return name


def one_line_errors(ap):
    """An argparse parser's errors in one line, 'PROG: error: why' and exit
    2, without the usage (--help shows it). Returns the parser."""
    def error(message):
        print(f"{ap.prog}: error: {one_line(message)}", file=sys.stderr)
        sys.exit(BAD_INPUT)
    ap.error = error
    return ap


def _kind(mode):
    for test, word in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a device"),
                       (stat.S_ISBLK, "a device"), (stat.S_ISSOCK, "a socket"), (stat.S_ISLNK, "a symbolic link")):
        if test(mode):
            return word
    return None


def under(path, folder):
    """Whether `path` (resolved) lies in `folder` (resolved)."""
    p, f = os.path.realpath(path), os.path.realpath(folder)
    return p == f or p.startswith(f + os.sep)


def check_output(path, flag="output", doc=False):
    """The absolute path of an output, checked before any work: absent or a
    regular file (not a folder, device, FIFO, socket or symbolic link), in
    a folder that exists and takes a new file (proved by making and removing
    a temporary there: /proc or a read-only mount passes access() yet takes
    none); under doc/ only with doc=True."""
    if not path:
        raise ToolError(f"{flag}: an empty path")
    try:
        full = os.path.abspath(path)
    except OSError:  # (getcwd: the working folder was deleted)
        raise ToolError(f"{flag} {path}: the working folder is gone (deleted?): cd into one that exists") from None
    try:
        st = os.lstat(full)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise ToolError(f"{flag} {path}: {e.strerror}")
    if st is not None and _kind(st.st_mode):
        raise ToolError(f"{flag} {path}: {_kind(st.st_mode)}, not a file (an output is a new or regular file)")
    folder = os.path.dirname(full)
    if not os.path.isdir(folder):
        raise ToolError(f"{flag} {path}: no folder {folder}")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ToolError(f"{flag} {path}: the folder {folder} takes no new file")
    if not doc and under(full, DOC):
        raise ToolError(f"{flag} {path}: in doc/, which changes only with --doc")
    _takes_a_file(full, flag, path)
    return full


def _takes_a_file(full, flag, path):
    """ToolError unless a temporary can be made (and is removed at once)
    beside `full`: the rename that writes the output needs one there."""
    folder, base = os.path.split(full)
    try:
        fd, temp = tempfile.mkstemp(dir=folder, prefix=base[:NAME_MAX] + ".incomplete-")
    except OSError as e:
        raise ToolError(f"{flag} {path}: the folder {folder} takes no new file ({e.strerror})") from None
    os.close(fd)
    os.remove(temp)


def check_input(path, flag="input"):
    """The path of an input, checked: an existing regular file (a FIFO or a
    device would block or never end), readable."""
    if not path:
        raise ToolError(f"{flag}: an empty path")
    try:
        st = os.stat(path)
    except OSError as e:
        raise ToolError(f"{flag} {path}: {e.strerror}")
    if not stat.S_ISREG(st.st_mode):
        raise ToolError(f"{flag} {path}: {_kind(st.st_mode) or 'not a regular file'}, not a file")
    if not os.access(path, os.R_OK):
        raise ToolError(f"{flag} {path}: not readable")
    return path


def same_file(a, b):
    """Whether two paths name one file (by path, or by device and inode)."""
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def check_distinct(files):
    """files: [(flag, path)]: ToolError if two name the same file."""
    for i, (fa, a) in enumerate(files):
        for fb, b in files[i + 1:]:
            if a and b and same_file(a, b):
                raise ToolError(f"{fa} {a} and {fb} {b}: the same file")


def out_path(*parts):
    """A default output under out/ (its folders made; a failed run's clean_up removes them while empty)."""
    path = os.path.join(OUT, *parts)
    folder, missing = os.path.dirname(path), []
    while folder and not os.path.isdir(folder):
        missing.append(folder)  # (deepest first)
        folder = os.path.dirname(folder)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with _lock:
        _made.extend(missing)
    return path


# The temporaries and children a stop must clean up.
_temps = set()
_children = set()
_made = []  # folders out_path made, deepest first
_lock = threading.Lock()


def _register(temp):
    with _lock:
        _temps.add(temp)


def _forget(temp):
    with _lock:
        _temps.discard(temp)


def _temp_beside(path):
    folder, base = os.path.split(os.path.abspath(path))
    fd, temp = tempfile.mkstemp(dir=folder, prefix=base + ".incomplete-")
    _register(temp)
    return fd, temp


def _commit(temp, path):
    # The temporary takes the usual mode of a new file, not mkstemp's 0600.
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(temp, 0o666 & ~umask)
    os.replace(temp, path)
    _forget(temp)


@contextlib.contextmanager
def atomic(path, mode="w", **kw):
    """Opens a temporary beside `path` for writing; renames it over `path`
    when the block ends without an exception, else removes it."""
    fd, temp = _temp_beside(path)
    try:
        with os.fdopen(fd, mode, **kw) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        _commit(temp, path)
    finally:
        if os.path.exists(temp) and temp in _temps:
            os.remove(temp)
            _forget(temp)


def write_text(path, text):
    with atomic(path) as f:
        f.write(text)


def savefig(fig, path, **kw):
    """matplotlib's savefig through a temporary (its format from `path`'s
    extension unless given)."""
    kw.setdefault("format", os.path.splitext(path)[1].lstrip(".").lower() or "png")
    with atomic(path, "wb") as f:
        fig.savefig(f, **kw)


def run_child(cmd, timeout=None, capture=True, **kw):
    """Like subprocess.run(cmd, capture_output=True, text=True), for a child
    a stop must end: registered while it runs, in its own process group so
    that a stop kills all of it; a timeout kills its whole group and raises
    subprocess.TimeoutExpired. capture=False: its output is the tool's."""
    kw.setdefault("errors", "backslashreplace")  # (a scene's stray bytes quoted in a child's message)
    pipe = subprocess.PIPE if capture else None
    p = subprocess.Popen(cmd, start_new_session=True, stdout=pipe, stderr=pipe, text=True, **kw)
    with _lock:
        _children.add(p)
        late = _stopping
    if late:  # started by a thread that had not heard of the stop: the stop's clean_up missed it
        _kill(p)
    try:
        try:
            out, err = p.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            _kill(p)
            p.communicate()
            raise
    finally:
        with _lock:
            _children.discard(p)
    return subprocess.CompletedProcess(cmd, p.returncode, out, err)


def _kill(p):
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def register_temp(path):
    """A temporary of the caller's own (a report a child writes) that a
    stop must remove; forget_temp when it is gone."""
    _register(path)


def forget_temp(path):
    _forget(path)


def clean_up():
    """Kills every registered child (and its group), removes every
    registered temporary and the folders out_path made that are still
    empty. Safe to call more than once."""
    with _lock:
        children, temps, made = list(_children), list(_temps), list(_made)
        _children.clear()
        _temps.clear()
        _made.clear()
    for p in children:
        _kill(p)
    for t in temps:
        try:
            os.remove(t)
        except OSError:
            pass
    for d in made:
        try:
            os.rmdir(d)  # (only while empty)
        except OSError:
            pass


class Stopped(BaseException):
    """A stop signal (SIGINT, SIGTERM, SIGHUP) arrived."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


# Set by a stop signal before it kills the children: a child that a worker
# thread starts after that, not yet knowing of the stop (stress.py's pool:
# its run just killed, it goes on to the next), is killed as soon as it is
# registered, rather than run to its end while the stop waits for the thread.
_stopping = False


def _on_signal(signum, frame):
    global _stopping
    _stopping = True
    clean_up()
    raise Stopped(signum)


def stop_handlers():
    """SIGINT, SIGTERM and SIGHUP raise Stopped in the main thread after
    killing the children and removing the temporaries (guard turns it into
    one line and exit 128 + the signal: 130, 143, 129)."""
    for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, _on_signal)


def one_line(text):
    """`text` as one printable line: control characters, bytes of a damaged
    file (a NUL, a newline in a quoted CSV field) and of an argument that
    was not UTF-8 (surrogateescape's U+DC80-U+DCFF: \\xff, not \\udcff) escaped."""
    return "".join(c if c.isprintable() else f"\\x{ord(c) - 0xDC00:02x}" if 0xDC80 <= ord(c) <= 0xDCFF
                   else c.encode("unicode_escape", "backslashreplace").decode("ascii") for c in str(text))


def deliver(text, lost):
    """A tool's printout onto stdout, whole at the end: a write that fails
    (> /dev/full) is one line saying what is `lost`, exit 1; a reader gone
    (| head) is left to guard (a quiet exit)."""
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except BrokenPipeError:
        raise
    except OSError as e:
        # What is left in the buffer goes nowhere: the interpreter's own
        # flush at exit would fail again and print its complaint.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        raise ToolError(f"stdout: {e.strerror or e}: {lost}", code=1)


# Whether a progress line on stderr waits for its end (a stop's line then
# starts on a new one).
line_open = False
# Whether the tool started with no stdout (>&-); guard gives it /dev/null.
stdout_closed = False


def guard(tool, main, argv=None):
    """Runs main(argv) as a tool's command line: ToolError -> 'tool: message'
    and its code; a stop -> 'tool: stopped (SIGINT)', exit 128 + the signal (130); a closed
    stdout (| head) -> a quiet exit; any other error -> one line naming it,
    exit 1 (RTSIM_TRACEBACK=1 shows the traceback); a failed write to
    stdout (> /dev/full) -> one line, exit 1; no stdout at all (>&-) -> what
    the tool prints goes to /dev/null (stdout_closed says so). Returns the
    exit code."""
    global stdout_closed
    stop_handlers()
    if sys.stdout is None:  # >&-: Python gives no stdout; what a tool prints goes nowhere
        stdout_closed, sys.stdout = True, open(os.devnull, "w")
    try:
        code = main(argv) if argv is not None else main()
        sys.stdout.flush()
        return code or 0
    except ToolError as e:
        clean_up()
        print(f"{tool}: {one_line(e)}", file=sys.stderr)
        return e.code
    except (Stopped, KeyboardInterrupt) as e:
        clean_up()
        name = e.args[0] if isinstance(e, Stopped) else "SIGINT"
        print(("\n" if line_open else "") + f"{tool}: stopped ({name})", file=sys.stderr)
        return 128 + e.signum if isinstance(e, Stopped) else STOPPED
    except BrokenPipeError:
        clean_up()
        # The reader went away (| head): no more output, and no complaint
        # from the interpreter's own flush at exit.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except OSError as e:
        clean_up()
        if e.filename is None and sys.stdout is not None:  # stdout's own write (> /dev/full)
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # (nor again at exit)
            print(f"{tool}: stdout: {e.strerror or e}", file=sys.stderr)
        else:
            print(f"{tool}: {one_line(e.filename) if e.filename else ''}: {e.strerror or one_line(e)}", file=sys.stderr)
        return FAILED
    except Exception as e:  # noqa: BLE001 - the promise is one line, never a traceback
        clean_up()
        if os.environ.get("RTSIM_TRACEBACK"):
            raise
        print(f"{tool}: internal error: {type(e).__name__}: {one_line(e)} (RTSIM_TRACEBACK=1 shows where)",
              file=sys.stderr)
        return FAILED


def numbers(text, flag, kind=int, least=None, most=None):
    """A flag's comma-separated list of numbers (whole ones for kind=int,
    as in --n 2,4,8), each within [least, most] where given, or ToolError
    naming the flag: one line, not a ValueError's traceback."""
    try:
        values = [kind(x) for x in text.split(",")]
    except (ValueError, TypeError, AttributeError):
        values = None
    if not values or any(v != v or v in (float("inf"), float("-inf")) for v in values):
        what = "whole numbers" if kind is int else "numbers"
        raise ToolError(f"{flag} {text!r}: a comma-separated list of {what}")
    out = [v for v in values if (least is not None and v < least) or (most is not None and v > most)]
    if out:
        bounds = " and ".join(b for b in (f"at least {least}" if least is not None else "",
                                          f"at most {most}" if most is not None else "") if b)
        raise ToolError(f"{flag} {text!r}: {out[0]}, where each must be {bounds}")
    return values


def image_size(text, flag="--size"):
    """An image size WxH as rtsim takes it (W and H in 1..65536), or
    ToolError naming the flag: checked before a sweep starts, not in every
    run it makes ("--size 128" failed 40 runs, one after another)."""
    m = re.fullmatch(r"([0-9]+)x([0-9]+)", text or "")
    if not m or not all(1 <= int(v) <= 65536 for v in m.groups()):
        raise ToolError(f"{flag} {text!r}: WxH, with W and H in 1..65536 (such as 256x256)")
    return text


def mesh_shapes(text, flag="--shapes"):
    """A comma-separated list of mesh shapes WxHxD (each at least 1), or
    ToolError naming the flag."""
    shapes = (text or "").split(",")
    for d in shapes:
        m = re.fullmatch(r"([0-9]+)x([0-9]+)x([0-9]+)", d)
        if not m or not all(int(v) >= 1 for v in m.groups()):
            raise ToolError(f"{flag} {text!r}: {d!r} is not a mesh shape WxHxD, each at least 1 (such as 64x1x1)")
    return shapes
