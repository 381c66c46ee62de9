"""Sweeps of any scene and any flags from the command line (scripts/sweep.py
NAME --set FLAG=V1,V2 ... -- RTSIM_FLAGS): the grid of points (the product
of the --set lists) over the base flags, each point one rtsim run and, where
asked, its comparison runs (the same flags without balancing; on one
computer), run by the sweep driver (sweep_driver.run: parallel or Dask, journal,
resume, provenance), one CSV row per point. doc/exploration.md, "Sweeps of
your own", shows it at work."""
import argparse
import csv
import hashlib
import itertools
import math
import os
import sys
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
import sweep_driver  # noqa: E402
import sweep_points  # noqa: E402
from outputs import ToolError  # noqa: E402
from project import QUIET, RTSIM  # noqa: E402

SWEEPS = sweep_driver.JOURNALS  # out/sweeps: the CSV beside its journal
MESH = sweep_points.MESH
DRIVER_OWNS, INPUTS = sweep_points.DRIVER_OWNS, sweep_points.INPUTS
flag_names, flag_values = sweep_points.flag_names, sweep_points.flag_values

# The most points one sweep runs: each is an rtsim run of a second or more,
# so more would take weeks, and the grid is built in memory before any runs.
MAX_POINTS = 100_000
MAX_REPEAT = 1000  # runs of one point: a median of more says no more
# Settings of particular nodes and links: not for the one-node run.
PER_NODE = ("--node-speed", "--node-cost", "--link-set", "--trace-nodes", "--trace-links", "--boundaries-from")

EXAMPLES = """examples:
  /usr/bin/python3 scripts/sweep.py links --set link-bandwidth=100MB/s,200MB/s,1GB/s --gain -- \\
      --scene ../shared/scenes/spd/balls-4.nff --size 256x256 --mesh 6
  /usr/bin/python3 scripts/sweep.py sizes --set mesh=2,4,8 --set cost-sphere=10ns,1us --speedup -- --config configs/paper.conf
  /usr/bin/python3 scripts/plot_sweep.py out/sweeps/links.csv --x link-bandwidth --y render_time_ns,time_none_ns

A value list holding commas itself (--eye=1,2,3) is split at semicolons instead: --set 'eye=-1,0.5,0.5;0.5,-1,0.5'."""


def parse_set(text):
    """'FLAG=V1,V2' -> ('--flag', ['V1', 'V2']); a list with a ';' is split there."""
    flag, eq, values = text.partition("=")
    flag = flag.strip().lstrip("-")
    if not eq or not flag or not values:
        raise ValueError(f"--set {text!r}: expected FLAG=V1,V2,... (for example link-bandwidth=100MB/s,1GB/s)")
    vals = [v.strip() for v in values.split(";" if ";" in values else ",")]
    if any(not v for v in vals):
        raise ValueError(f"--set {text!r}: an empty value in the list")
    if len(set(vals)) != len(vals):
        raise ValueError(f"--set {text!r}: a value given twice")
    return "--" + flag, vals


def without(args, flag):
    """`args` without `flag` and its value, in either spelling ('--flag V', '--flag=V')."""
    out, skip = [], False
    for a in args:
        if skip:
            skip = False
        elif a == flag:
            skip = True
        elif not a.startswith(flag + "="):
            out.append(a)
    return out


def base_flags(args):
    """The user's base flags, checked: the quiet flags the driver adds anyway
    are dropped (not recorded twice); outputs the driver owns are refused."""
    args = [a for a in args if a not in QUIET and a != "--quiet"]
    for flag in flag_names(args) & set(DRIVER_OWNS):
        raise ToolError(f"error: {flag} in the rtsim flags: {DRIVER_OWNS[flag]}")
    return args


def settings(sets, base):
    """Every setting a point can get, as (where, flag, value, kind, swept):
    each --set value (kind 'set'), each base flag ('base'), and each line of
    the presets either names (--config, and a report's rerun.flags with
    --rerun; 'preset', swept if a --set names it), the input files checked
    and the presets read (ToolError 'FILE:LINE: why')."""
    out = [(f"--set {flag[2:]}", flag, v, "set", True) for flag, vals in sets for v in vals]
    out += [("the rtsim flags", f, v, "base", False) for f, v in flag_values(base)]
    for where, flag, value, kind, swept in list(out):
        if flag in INPUTS and value is not None:
            outputs.check_input(value, flag)
        if flag == "--config" and value is not None:
            out += [(f"{value}:{n}", "--" + name, v, "preset", swept) for n, name, v in sweep_points.config_lines(value)]
        if flag == "--rerun" and value is not None:  # a report's flags, read as a preset's
            out += [(f"{value}: rerun.flags:{n}", "--" + name, v, "preset", swept)
                    for n, name, v in sweep_points.rerun_lines(value)]
    return out


def check_settings(sets, base, frames, speedup):
    """One line (ToolError) for a setting that would write a file, run
    another value than its row says, or make rows labelled differently the
    same run; before any run. Returns the settings (settings())."""
    swept = {flag for flag, _ in sets}
    given = flag_names(base)
    found = settings(sets, base)
    for where, flag, value, kind, from_swept in found:
        if flag in DRIVER_OWNS:
            raise ToolError(f"{where}: {flag} writes a file: {DRIVER_OWNS[flag]}")
        if flag == "--frames" and frames is not None:
            raise ToolError(f"{where}: --frames, with the driver's --frames {frames}: give one "
                            "(the driver's, before --, or rtsim's)")
        # (A preset's mesh shape, either spelling, is replaced by the point's
        # --mesh or --mesh-dims, as rtsim's command line replaces it.)
        if flag == "--mesh-dims" and "--mesh" in swept and kind == "base":
            raise ToolError("--set mesh: --mesh-dims in the rtsim flags too: give the mesh's shape once")
        if flag == "--mesh" and "--mesh-dims" in swept and kind == "base":
            raise ToolError("--set mesh-dims: --mesh in the rtsim flags too: give the mesh's shape once")
        if kind == "preset" and from_swept and (flag in swept or flag in given):
            raise ToolError(f"{where}: {flag[2:]} in a swept preset, and {flag} on the command line, which wins: "
                            "the preset's value would never run")
        if kind == "preset" and speedup and flag in PER_NODE:
            raise ToolError(f"{where}: {flag[2:]} sets particular nodes, which the one-node run of --speedup "
                            f"cannot leave out of a preset: give {flag} after -- instead")
    return found


def sweep_id(sets, base, frames, gain, speedup, repeat):
    """What makes a sweep the same sweep, whatever values its --set lists
    take (an extended sweep is the same sweep): the swept flags, the base
    flags and the comparisons asked for. Its CSV records it (column sweep)."""
    key = repr(([flag for flag, _ in sets], base, frames, gain, speedup, repeat))
    return hashlib.sha1(key.encode()).hexdigest()[:12]


def check_csv_is_ours(path, ours, shown=None):
    """ToolError if `path` holds the rows of another sweep: two sweeps of
    one NAME (or one --csv) never overwrite each other's rows unasked.
    `shown` names the CSV in messages (default '--csv PATH')."""
    shown = shown or f"--csv {os.path.relpath(path)}"
    if not os.path.exists(path):
        return
    try:
        with open(path, newline="", encoding="utf-8") as f:
            theirs = next(csv.DictReader(f), {}).get("sweep")
    except (OSError, UnicodeDecodeError, csv.Error):
        theirs = None
    if theirs is None:
        raise ToolError(f"{shown}: a file this sweep did not write (no sweep column); give this "
                        "one another NAME or --csv FILE, or remove that file")
    if theirs != ours:
        raise ToolError(f"{shown}: holds the rows of another sweep (other swept flags, base "
                        "flags or comparisons); give this one another NAME or --csv FILE, or remove that file")


def csv_shown(given, name):
    """How messages name the CSV: '--csv PATH' as given, or the default
    said plainly (not as a path relative to the working folder)."""
    return f"--csv {given}" if given else f"the CSV out/sweeps/{name}.csv (the default; --csv names another)"


def check_csv_path(given, name):
    """The CSV's path, checked (outputs.check_output): --csv, or
    out/sweeps/NAME.csv, whose folder is made when the sweep starts."""
    if given:
        return outputs.check_output(given, "--csv")
    path = os.path.join(SWEEPS, name + ".csv")
    if os.path.isdir(SWEEPS):
        return outputs.check_output(path, csv_shown(given, name))
    return path


def grid(sets, base):
    """The points: one per combination of the --set values, in the order
    given (the last --set varies fastest), as (params, rtsim flags)."""
    names = [flag.lstrip("-") for flag, _ in sets]
    clash = flag_names(base) & {flag for flag, _ in sets}
    if clash:
        raise ToolError(f"error: {', '.join(sorted(clash))} is both swept (--set) and in the base flags")
    if len(set(names)) != len(names):
        raise ToolError("error: a flag swept by two --set")
    count = math.prod(len(vals) for _, vals in sets)
    if count > MAX_POINTS:  # (the whole product was built in memory first: 10^9 points filled it)
        raise ToolError(f"error: the --set lists make {count:,} points ({' x '.join(str(len(v)) for _, v in sets)}); "
                        f"a sweep runs at most {MAX_POINTS:,}: split it into several")
    for combo in itertools.product(*(vals for _, vals in sets)):
        params = dict(zip(names, combo))
        args = list(base)
        for (flag, _), v in zip(sets, combo):
            args += [f"{flag}={v}"]
        yield params, args


def runs_of(args, frames, gain, speedup):
    """The rtsim runs one point needs, by role: the point itself; without
    balancing (gain); on one computer (speed-up)."""
    main = args + (["--frames", str(frames)] if frames else [])
    out = {"point": main}
    if gain:
        out["none"] = without(args, "--balance") + ["--balance", "none"]
    if speedup:  # one node with the global settings, as rtsim's own baseline (--as-baseline) runs it
        one = args
        for flag in MESH + PER_NODE:
            one = without(one, flag)
        # (replacing a preset's mesh shape, as the command line does)
        out["one"] = one + ["--mesh-dims", "1x1x1"]
    return out


def extract(report):
    """What a row keeps of a run: its render time (the last frame's), every
    frame's, and the busiest node and link."""
    t = report["render_time_ns"]
    node = max(report["nodes"], key=lambda n: n["busy_ns"])
    link = report["busiest_links"][0] if report.get("busiest_links") else None
    return {"render_time_ns": t,
            "frames_ns": " ".join(f"{f['render_time_ns']:.0f}" for f in report.get("frames", [])) or f"{t:.0f}",
            "busiest_node": "node_" + "_".join(str(c) for c in node["node"]),
            "busiest_node_busy": node["busy_ns"] / t if t > 0 else 0.0,
            "busiest_link": link["name"] if link else "",
            "busiest_link_utilisation": link["utilisation"] if link else 0.0}


# What extract gives, as sweep_driver.bad_metrics checks a journalled record of it.
FIELDS = {"render_time_ns": float, "frames_ns": str, "busiest_node": str, "busiest_node_busy": float,
          "busiest_link": str, "busiest_link_utilisation": float}


def rows_of(points, results, gain, speedup, sweep_of=""):
    """One row per point: the swept values, the point's figures, and its
    comparisons (time_none_ns and balance_ratio = time / time without
    balancing; time_one_ns and speedup = one computer's time / the point's);
    its wall time (with --repeat, the median and the spread), the sweep it
    belongs to (sweep_id) and its provenance."""
    by_args = {tuple(r["args"]): r for r in results}
    rows = []
    for params, runs in points:
        p = by_args[tuple(runs["point"])]
        row = dict(params)
        row.update({k: p[k] for k in ("render_time_ns", "frames_ns", "busiest_node", "busiest_node_busy",
                                      "busiest_link", "busiest_link_utilisation")})
        if gain:
            none = by_args[tuple(runs["none"])]["render_time_ns"]
            row.update({"time_none_ns": none, "balance_ratio": p["render_time_ns"] / none})
        if speedup:
            one = by_args[tuple(runs["one"])]["render_time_ns"]
            row.update({"time_one_ns": one, "speedup": one / p["render_time_ns"]})
        row.update({k: p[k] for k in ("wall_s", "wall_s_min", "wall_s_max") if k in p})
        row.update({"sweep": sweep_of, "version": p["version"], "command": p["command"]})
        rows.append(row)
    return rows


class Parser(argparse.ArgumentParser):
    """argparse, its errors one line (sweep.py: error: ...) and exit 2."""

    def error(self, message):
        raise ToolError(f"error: {message}")


def check_working_folder():
    """ToolError if the working folder is gone (deleted under a shell still
    in it): every relative path would fail later, mid-sweep."""
    try:
        os.getcwd()
    except OSError:
        raise ToolError("error: the working folder is gone (deleted?): cd into a folder that exists") from None


def parser():
    """The command line's flags (--help: EXAMPLES after them)."""
    ap = Parser(
        prog="sweep.py", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=EXAMPLES,
        usage="/usr/bin/python3 scripts/sweep.py NAME --set FLAG=V1,V2,... [--set ...] [options] -- RTSIM_FLAGS...",
        description=textwrap.fill("Runs rtsim over the grid of the --set lists (their product), each point with the rtsim "
                    "flags after --, and writes out/sweeps/NAME.csv: a row per point with the swept values, its "
                    "render time (simulated ns; the last frame's with --frames), each frame's, the busiest node "
                    "(its busy share of the render time) and link (its utilisation), and the comparisons asked "
                    "for. Finished points are journalled (out/sweeps/NAME.jsonl): an interrupted or extended "
                    "sweep reruns nothing; each row records the exact command and the tree's version. Bad input "
                    "(a NAME that is not a name, an output flag, flags that contradict each other) gets one line "
                    "and exit 2, before any run; a point rtsim refuses, exit 1; Ctrl-C or SIGTERM stops at once "
                    "(exit 130; 143 for SIGTERM), every finished point journalled.", 79))
    ap.add_argument("name", help="the sweep's name (letters, digits, '-', '_', '.'; not a path): out/sweeps/NAME.csv "
                                 "and its journal out/sweeps/NAME.jsonl")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="FLAG=V1,V2,...",
                    help="an rtsim flag (without its dashes) and the values it takes; repeat for a grid")
    ap.add_argument("--frames", type=int, default=None,
                    help="frames per point (rtsim --frames); the row's time is the last's. Not with --frames "
                         "in --set, the rtsim flags or a preset")
    ap.add_argument("--gain", action="store_true",
                    help="also run each point without balancing: time_none_ns, balance_ratio = time / that")
    ap.add_argument("--speedup", action="store_true",
                    help="also run each point on one computer (--mesh-dims 1x1x1): time_one_ns, speedup = that / time")
    ap.add_argument("--repeat", "--repeats", dest="repeat", type=int, default=1, metavar="K",
                    help="run each point K times: wall_s is the median, wall_s_min and wall_s_max the spread; "
                         "the K render times must agree (default 1)")
    ap.add_argument("--csv", help="where to write the CSV (default out/sweeps/NAME.csv; not in doc/, not the journal "
                                  "or an input)")
    ap.add_argument("--rtsim", default=RTSIM, help="the rtsim binary (default: build/rtsim, scripts/build.sh); "
                                                   "part of each point's identity in the journal")
    sweep_driver.add_arguments(ap)
    return ap


def check_args(a):
    """One line and exit 2 for a value that cannot make a sweep."""
    outputs.check_name(a.name, "NAME")
    if not a.sets:
        raise ToolError("error: nothing to sweep: give at least one --set FLAG=V1,V2,...")
    if a.frames is not None and a.frames < 1:
        raise ToolError(f"error: --frames {a.frames}: at least 1")
    if not 1 <= a.repeat <= MAX_REPEAT:  # (10^9 ran until killed, saying nothing)
        raise ToolError(f"error: --repeat {a.repeat}: at least 1 and at most {MAX_REPEAT}")
    if a.dask_timeout <= 0:
        raise ToolError(f"error: --dask-timeout {a.dask_timeout:g}: more than 0 seconds")
    if not os.path.isfile(a.rtsim):
        raise ToolError(f"error: --rtsim {a.rtsim}: no rtsim binary there (build it with scripts/build.sh)")
    if not os.access(a.rtsim, os.X_OK):
        raise ToolError(f"error: --rtsim {a.rtsim}: not executable")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    check_working_folder()
    ours, rtsim_flags = (argv[:argv.index("--")], argv[argv.index("--") + 1:]) if "--" in argv else (argv, [])
    ap = parser()
    a = ap.parse_args(ours)
    check_args(a)
    # A bare name (myrtsim) is the file checked here, in the working folder,
    # not a program on PATH: every point runs it by its absolute path.
    a.rtsim = os.path.abspath(a.rtsim)
    try:
        sets = [parse_set(s) for s in a.sets]
    except ValueError as e:
        raise ToolError(f"error: {e}") from None
    base = base_flags(rtsim_flags)
    points = [(params, runs_of(args, a.frames, a.gain, a.speedup)) for params, args in grid(sets, base)]
    found = check_settings(sets, base, a.frames, a.speedup)
    journal = sweep_driver.journal_path(a.name, a, make=False)
    csv_path = check_csv_path(a.csv, a.name)
    if os.path.abspath(csv_path) == os.path.dirname(journal):  # (it ran every point, then wrote into a folder)
        raise ToolError(f"error: --csv {a.csv} and --journal-dir {a.journal_dir}: the same path (the journal's folder)")
    inputs = [(flag, value) for _, flag, value, kind, _ in found if flag in INPUTS and value and kind != "preset"]
    outputs.check_distinct([("--csv", csv_path), ("the journal", journal), ("--rtsim", a.rtsim)] + inputs)
    ours_id = sweep_id(sets, base, a.frames, a.gain, a.speedup, a.repeat)
    shown = csv_shown(a.csv, a.name)
    check_csv_is_ours(csv_path, ours_id, shown)  # (before the journal is made: a refusal leaves nothing)
    seen = sweep_driver.csv_state(csv_path)
    unique = {}
    for params, runs in points:
        for role, args in runs.items():
            unique.setdefault(tuple(args), {"params": {**params, "run": role}, "args": args})
    sweep_driver.connect(a)  # (with --dask: the scheduler answers, or one line before anything is written)
    journal = sweep_driver.journal_path(a.name, a)  # (its folder made)
    counts = {}
    with sweep_driver.locked(journal, a.fresh, a.name):  # held from the first point to the CSV
        os.makedirs(os.path.dirname(csv_path), exist_ok=True)
        results = sweep_driver.run(a.name, list(unique.values()), extract, None, a, repeats=a.repeat, binary=a.rtsim,
                            fields=FIELDS, counts=counts)
        for r, p in zip(results, unique.values()):
            r["args"] = p["args"]
        rows = rows_of(points, results, a.gain, a.speedup, ours_id)
        sweep_driver.write_csv(csv_path, rows, seen, shown)
    where = os.path.relpath(csv_path)
    ran = counts.get("ran", len(unique))
    print(f"{len(rows)} points ({ran} runs{f', {len(unique) - ran} resumed' if ran < len(unique) else ''}) -> "
          f"{csv_path if where.startswith('..') else where}")
    return 0


if __name__ == "__main__":
    sys.exit(outputs.guard("sweep.py", main))
