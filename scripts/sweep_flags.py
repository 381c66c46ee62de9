"""The flags every sweep script shares (the sweep driver's, scripts/
sweep_driver.py, and where a script writes), each value checked as it is
read: a bad one is one line and exit 2 (outputs.one_line_errors).

Standard library only."""
import argparse
import os
import re
import shlex
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
import project  # noqa: E402
from outputs import ToolError  # noqa: E402
from project import ROOT  # noqa: E402
from sweep_journal import JOURNALS  # noqa: E402
from sweep_points import flag_names  # noqa: E402

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


one_line_errors = outputs.one_line_errors


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
    for flag in ("out", "journal_dir"):  # (an empty one is no folder: not "the default")
        if getattr(a, flag, None) == "":
            ap.error(f"--{flag.replace('_', '-')} '': an empty folder name")
    publish = bool(getattr(a, "doc", False))
    a.out = a.out or (project.RESULTS if publish else os.path.join(ROOT, "out", "results"))
    a.doc = a.doc_page if publish else None
    try:
        check_out_folder(a.out, publish)
    except ToolError as e:
        ap.error(str(e))
    return a


def extra_flags(text, flag, own):
    """An experiment's more rtsim flags for every point (--extra, --flags),
    split as a shell would; ToolError naming `flag`, before any run, for
    text that does not split or a flag of `own`, which the experiment sets
    on each point itself (given again, its rows would name one value and
    rtsim run another). The driver checks the points' flags whole
    (sweep_points.check_point)."""
    try:
        args = shlex.split(text)
    except ValueError as e:
        raise ToolError(f"{flag} {text!r}: {e} (the flags are split as a shell would)")
    for f in sorted(flag_names(args) & set(own)):
        raise ToolError(f"{flag}: {f} is the experiment's own: it sets it on each point ({', '.join(own)})")
    return args
