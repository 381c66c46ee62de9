"""What the project's scripts share: where things are (the repository, its
builds, the SPD scenes, the machine presets), the paper's experiment scene
as rtsim flags, running rtsim and reading its report, the tree's version,
tables written into doc/, and the plotting set-up.

Tools live in scripts/, the studies that make doc/results/ in
scripts/experiments/; both import this module (an experiment puts scripts/
on its path first). Standard library only: matplotlib is imported when a
script asks for pyplot(). Runs on Dask workers too (scripts/sweep.py ships
it by value)."""
import atexit
import glob
import json
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SPD = os.path.join(os.path.dirname(ROOT), "shared", "scenes", "spd")  # Eric Haines' SPD scenes, beside the clone
BUILD = os.path.join(ROOT, "build")            # scripts/build.sh
FAST_BUILD = os.path.join(ROOT, "build-fast")  # scripts/build_fast.sh: what the benchmarks measure
RTSIM = os.path.join(BUILD, "rtsim")
RTREF = os.path.join(BUILD, "rtref")
RESULTS = os.path.join(ROOT, "doc", "results")

# The paper's experiment (section 4; doc/balancing.md, "Fig. 4"): 1,000
# spheres of radius 0.02 placed at random (seed 1) in the unit cube, then
# crowded along the progress axis x into its first f (--concentration f,
# which each experiment adds), rendered at 256x256. Every setting is
# spelled out, so that no experiment's scene depends on rtsim's defaults.
PAPER_SCENE = ["--spheres", "1000", "--radius", "0.02", "--seed", "1", "--axis", "x", "--size", "256x256"]
# Its two views: along the progress axis, and across it (rtsim's default camera).
VIEWS = {
    "along": ["--eye=-1.3,0.5,0.5", "--look-at=0.5,0.5,0.5", "--fov", "50"],
    "across": ["--eye=0.5,-1.6,0.5", "--look-at=0.5,0.5,0.5", "--fov", "40"],
}

# The machine presets (configs/NAME.conf; doc/machine.md, "Machine presets").
PRESETS = ["modern", "transputer-1987", "paper"]


def policy_named(label):
    """A balancing policy's name as a published CSV holds it, in today's
    words: rows run before `--balance default` was retired (it meant
    measured, then the recommended policy) say `default` (or `default@K` for its
    K-th frame)."""
    head, at, frames = label.partition("@")
    return ("measured" if head == "default" else head) + at + frames


def preset_flags(name):
    """The flags that run rtsim on a preset."""
    return ["--config", os.path.join(ROOT, "configs", name + ".conf")]


def variant(preset, tag=""):
    """The suffix that names an experiment's files for a machine: '' for the
    modern preset, '-PRESET' for another, and '-TAG' after it when the run
    is a variant of the preset (its --extra flags, named by --tag)."""
    return "".join("-" + x for x in ([] if preset == "modern" else [preset]) + ([tag] if tag else []))


def add_machine_arguments(ap, preset, script):
    """The experiment scripts' machine: --preset (configs/PRESET.conf), and a
    variant of it, --extra flags named by --tag (their files SCRIPT-PRESET-TAG.*)."""
    ap.add_argument("--preset", default=preset, help="configs/PRESET.conf")
    ap.add_argument("--extra", default="", help="more rtsim flags for every run")
    ap.add_argument("--tag", default="", help=f"name of the --extra variant: its files are {script}-PRESET-TAG.*; "
                                              "ending in 'recommended', the recommended policy's runs on that "
                                              "variant (the best static split is the variant's)")


def check_variant(a):
    """--preset and --tag name files: names, not paths, and the preset one that exists."""
    import outputs
    outputs.check_input(preset_flags(outputs.check_name(a.preset, "--preset"))[1], "--preset")
    if a.tag:
        outputs.check_name(a.tag, "--tag")


def machine(a):
    """The machine's name in titles and table markers: the preset, and the tag of its variant."""
    return a.preset + (f" {a.tag}" if a.tag else "")


def target_factor(a):
    """Issue 61's first-frame target over max(1/N, the best static split):
    1.2 on the paper's machine, 1.3 on the others (and any variant of it)."""
    return 1.2 if a.preset == "paper" and not a.tag else 1.3


def invocation(a):
    """The flags that name the machine, for a table's "written by" line."""
    return f"--preset {a.preset}" + (f" --tag {a.tag} --extra={a.extra!r}" if a.tag else "")


def changed_flags(ap, a, names):
    """The flags among names whose values differ from the parser's
    defaults, as typed (quoted where needed), for a table's "written by"
    line: the line says how to write the table again."""
    def flag(k, v):  # (--k=v where v looks like a flag itself)
        return f"--{k.replace('_', '-')}{'=' if v.startswith('-') else ' '}{shlex.quote(v)}"
    return " ".join(flag(k, str(getattr(a, k))) for k in names if str(getattr(a, k)) != str(ap.get_default(k)))


def machine_tag(tag):
    """The part of a --tag that names a variant of the machine (its --extra
    flags): a tag ending in `recommended` names the recommended policy's
    runs on the machine the rest names (fig4.py --tag recommended,
    sphere-x100-recommended), whose best static split is the machine's."""
    tag = tag or ""
    return tag[:-len("recommended")].rstrip("-") if tag.endswith("recommended") else tag


def best_static(a):
    """The best static split's ratio per (view, N) at f = 1/N, where
    scripts/experiments/partition_search.py has found it for this preset:
    the better of its one set of planes and, where --per-column refined
    it, each column's own: {(view, N): (ratio, its busiest node's busy
    time as a fraction of none's, or None where not recorded)}."""
    return {k: v[:2] for k, v in best_static_splits(a).items()}


def best_static_splits(a):
    """best_static's, with the split's planes: {(view, N): (ratio, busiest
    or None, each column's inner planes in the search's column order where
    they won or None, the one set's or None where the CSV has none)}."""
    from csv_rows import read_csv
    best = {}
    for view in VIEWS:
        stem = "partition_search" + variant(a.preset, machine_tag(a.tag)) + ("" if view == "along" else f"-{view}")
        path = os.path.join(a.out, stem + ".csv")
        if not os.path.exists(path):  # a run under out/ uses the published search
            path = os.path.join(RESULTS, stem + ".csv")
        if os.path.exists(path):
            for r in read_csv(path):  # one set of planes for all columns, or each column's own where refined
                own = r.get("columns_ratio")
                aligned = [float(x) for x in r["planes"].split()] if r.get("planes") else None
                if own and float(own) < float(r["ratio"]):
                    busiest = r.get("columns_max_busy")
                    cols = [[float(x) for x in c.split()] for c in r["columns_planes"].split(";")] if r.get("columns_planes") else None
                    best[(r["view"], int(r["N"]))] = (float(own), float(busiest) if busiest else None, cols, aligned)
                else:
                    best[(r["view"], int(r["N"]))] = (float(r["ratio"]), None, None, aligned)
    return best


def start_boundaries(n, cols):
    """A --boundaries-from report for an n x n x n mesh along x: column
    (i, j)'s inner planes at cols[(i, j)], from time 0."""
    return {"config": {"mesh": [n, n, n], "balance": {"axis": "x"}},
            "boundaries": [{"column": [i, j], "index": k + 1, "history": [[0, p]]}
                           for (i, j), planes in sorted(cols.items()) for k, p in enumerate(planes)]}


def spd_scene(name):
    """The path of an SPD scene: 'balls-4' -> .../shared/scenes/spd/balls-4.nff."""
    return os.path.join(SPD, name + ".nff")


# What every scripted run of rtsim adds to its flags: no reference runs, no summary.
QUIET = ["--no-baseline", "-q"]

# util-linux's setpriv: a child started through it gets SIGKILL when the
# thread that started it dies, however it dies (kill -9 of a sweep too).
SETPRIV = "/usr/bin/setpriv"
REPORTS_PREFIX = "rtsim-reports-"


def dies_with_parent(cmd):
    """`cmd` run through setpriv --pdeathsig KILL where there is one: the
    kernel kills the child when the thread that started it dies, even by
    SIGKILL, which no handler of ours sees. (The signal follows the
    starting thread, not the process: run_rtsim's callers wait for the
    child in that thread, so it lives as long as the child must.)"""
    if os.access(SETPRIV, os.X_OK):
        return [SETPRIV, "--pdeathsig", "KILL", "--"] + cmd
    return cmd


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


_reports = {}  # pid -> this process's folder of temporary reports


def reports_folder():
    """This process's folder of temporary reports, TMPDIR/rtsim-reports-PID,
    made on first use and removed at exit. A process killed with SIGKILL
    cannot remove its folder: the next process to make one removes every
    rtsim-reports-PID whose PID no longer runs. (A PID reused since only
    keeps a dead folder a little longer.)"""
    pid = os.getpid()  # (a forked Dask worker gets a folder of its own)
    # (No lock: the module travels to Dask workers by value, and a lock does
    # not pickle. Threads that ask at once each make it, exist_ok.)
    if pid not in _reports:
        _reports[pid] = _make_reports_folder(pid)
    return _reports[pid]


def _make_reports_folder(pid):
    """reports_folder's first call in a process: the dead processes' folders removed, its own made."""
    tmp = tempfile.gettempdir()
    for old in glob.glob(os.path.join(tmp, REPORTS_PREFIX + "*")):
        tail = os.path.basename(old)[len(REPORTS_PREFIX):]
        if tail.isdigit() and int(tail) != pid and not _alive(int(tail)):
            shutil.rmtree(old, ignore_errors=True)
    folder = os.path.join(tmp, REPORTS_PREFIX + str(pid))
    os.makedirs(folder, 0o700, exist_ok=True)  # (a dead process's with our PID: its files stay till our exit)
    atexit.register(shutil.rmtree, folder, True)
    return folder


def run_rtsim(args, binary=RTSIM, timeout=None, image="", report=None):
    """Runs rtsim quietly (-q, no reference runs) with `args`; returns (its
    report, the process's wall seconds). The report goes to a temporary file
    unless `report` names one (in reports_folder()); the image nowhere
    unless `image` does. rtsim dies with the thread that waits for it
    (dies_with_parent), even if this process is killed by SIGKILL. Raises
    RuntimeError with rtsim's exit code and message if it fails. rtsim runs
    in its own process group (outputs.run_child): a stop (Ctrl-C, SIGTERM)
    kills it and removes the temporary report."""
    try:  # (imported here: a Dask worker, which gets this module by value, may not have it)
        import outputs
        run, register, forget = outputs.run_child, outputs.register_temp, outputs.forget_temp
    except ImportError:
        def run(cmd, timeout):  # noqa: F811
            return subprocess.run(cmd, capture_output=True, text=True, errors="backslashreplace", timeout=timeout)
        register = forget = lambda path: None
    temp = report is None
    if temp:
        fd, report = tempfile.mkstemp(prefix="rtsim-report-", suffix=".json", dir=reports_folder())
        os.close(fd)
        register(report)
    try:
        cmd = [binary] + [str(a) for a in args] + QUIET + ["--image", image, "--report", report]
        t0 = time.perf_counter()
        p = run(dies_with_parent(cmd), timeout=timeout)
        wall = time.perf_counter() - t0
        if p.returncode != 0:
            raise RuntimeError(f"exit {p.returncode}: {p.stderr.strip()}")
        with open(report) as f:
            return json.load(f), wall
    finally:
        if temp:
            try:
                os.remove(report)
            except FileNotFoundError:
                pass  # (a stop removed it already)
            forget(report)


def version():
    """The tree's version: git describe, with -dirty for uncommitted changes."""
    try:
        p = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty", "--abbrev=12"],
                           capture_output=True, text=True, check=True)
        return p.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def update_doc_section(path, name, text):
    """Replaces the text between `<!-- begin NAME -->` and `<!-- end NAME -->`
    in a doc page with `text`, so tables shown in doc/ pages are regenerated
    by the script that computes them, never edited by hand. The markers are
    looked for in `path`, and where they are not there, in the one page of
    doc/ that has them (a section that moved to another page is followed)."""
    begin, end = f"<!-- begin {name} (generated; do not edit) -->", f"<!-- end {name} -->"
    with open(path) as f:
        doc = f.read()
    if begin not in doc or end not in doc:
        pages = {}
        for page in sorted(glob.glob(os.path.join(ROOT, "doc", "*.md"))):
            with open(page) as f:
                other = f.read()  # (not `text`: that is the section's new text)
            if begin in other and end in other:
                pages[page] = other
        if len(pages) != 1:
            raise ValueError(f"{path}: no section markers for '{name}' (nor in one other page of doc/)")
        (path, doc), = pages.items()
    head, rest = doc.split(begin, 1)
    _, tail = rest.split(end, 1)
    import outputs
    outputs.write_text(path, head + begin + "\n" + text.rstrip("\n") + "\n" + end + tail)


def publish_table(lines, md_path, doc_path, section):
    """A generated markdown table (lines[0] a "written by" comment): to its
    results file, to stdout, and into its section of a doc page (if
    doc_path). False, with one line on stderr, where no page has the
    section (a variant no page shows: its table stays in its results file)."""
    import outputs
    outputs.write_text(md_path, "\n".join(lines) + "\n")
    print("\n".join(lines[1:]))
    if doc_path:
        try:
            update_doc_section(doc_path, section, "\n".join(lines[1:]))
        except ValueError as e:
            print(f"{os.path.basename(sys.argv[0])}: {e}; the table is in {os.path.relpath(md_path, ROOT)}",
                  file=sys.stderr)
            return False
    return True


def pyplot():
    """matplotlib's pyplot, drawing to files (no display needed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt
