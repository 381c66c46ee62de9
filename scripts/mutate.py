#!/usr/bin/python3
"""Planted timing bugs: does the test suite notice?

Each mutant (scripts/mutants.py; the balancing's in scripts/mutants_balance.py) is one small, plausible timing bug in models/ (a link's
slot returned at the wrong time, serialisation dropped, a cost not charged,
an override ignored, a message's size wrong). The script copies the tracked
sources to a work directory, checks that the suite passes there unchanged,
then plants the mutants one at a time, rebuilds, runs the suite and
reports which tests failed. A mutant the suite misses is a cost the tests
cannot see; the script exits 1 if there is any.

  /usr/bin/python3 scripts/mutate.py            # every mutant; table to out/results/mutate.md
  /usr/bin/python3 scripts/mutate.py --doc      # to doc/results/mutate.md and doc/robustness.md
  /usr/bin/python3 scripts/mutate.py --only fb-cost-dropped,no-latency   # table to --work only
  /usr/bin/python3 scripts/mutate.py --check    # every mutant still fits the code (a test)

The work directory (--work) is the script's own: it is made with a mark
file, and a folder that holds anything without that mark is refused
rather than emptied."""
import argparse
import os
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from mutants import MUTANTS, ORACLES  # noqa: E402
from project import RESULTS, ROOT, publish_table  # noqa: E402


def run(cmd, cwd, log, env=None):
    """Runs cmd, its output appended to the log; its exit code. The build or
    suite runs in a process group of its own, killed whole if this script is
    stopped (Ctrl-C, SIGTERM: outputs.guard), so that no ctest outlives it."""
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        p = subprocess.Popen(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT, env=env, start_new_session=True)
        try:
            return p.wait()
        except BaseException:
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait()
            raise


def failed_tests(junit):
    """Names of the tests that did not pass, from ctest's JUnit output."""
    if not os.path.exists(junit):
        return ["(no test results)"]
    out = []
    for case in ET.parse(junit).getroot().iter("testcase"):
        if case.get("status") not in (None, "run") or case.find("failure") is not None:
            out.append(case.get("name"))
    return out


def stale(mutants):
    """The mutants whose text to change is not in their file exactly once."""
    out = []
    for name, path, old, _, _ in mutants:
        with open(os.path.join(ROOT, path)) as f:
            n = f.read().count(old)
        if n != 1:
            out.append(f"{name} ({path}: {n} times)")
    return out


MARK = ".rtsim-mutate"  # the file that says a work directory is this script's


def own_work_dir(work):
    """The work directory, made or taken if it is this script's own (empty,
    or holding MARK; a folder of an older mutate.py, without it, is refused
    too: its files cannot be told from anyone's): its src/ is removed at every run, so a folder of
    anyone else's is refused. Not in the repository's tree, but under out/
    (git status stays clean)."""
    work = os.path.abspath(work)
    if outputs.under(work, ROOT) and not outputs.under(work, outputs.OUT):
        raise outputs.ToolError(f"--work {work}: in the repository; a folder elsewhere, or under out/")
    if os.path.lexists(work) and not os.path.isdir(work) or os.path.islink(work):
        raise outputs.ToolError(f"--work {work}: not a folder")
    if os.path.isdir(work) and os.listdir(work) and not os.path.isfile(os.path.join(work, MARK)):
        raise outputs.ToolError(f"--work {work}: a folder that is not mutate.py's (no {MARK} in it); "
                                "name a new or empty one")
    try:
        os.makedirs(work, exist_ok=True)
        open(os.path.join(work, MARK), "a").close()
    except OSError as e:
        raise outputs.ToolError(f"--work {work}: {e.strerror}")
    return work


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", default="/tmp/rtsim-mutate", help="work directory (sources, build, logs)")
    ap.add_argument("--only", default="", help="comma-separated mutant names")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--doc", action="store_true",
                    help="write the table to doc/results/mutate.md and doc/robustness.md (without it: "
                         "out/results/mutate.md; with --only: the work directory)")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--check", action="store_true",
                    help="only check that every mutant's text is in its file exactly once (the suite runs this, "
                         "so a change to models/ that a planted bug no longer fits fails there, not an hour into a run)")
    return ap.parse_args()


def copy_sources(work):
    """The tracked sources copied to work/src/, a repository of their own
    (so the build and the sweeps see a version), configured in
    src/build/ (where the scripts the suite runs look for rtsim, as in a
    clone), the scenes beside them: (src, build, log), or None if cmake
    failed."""
    src, log = (os.path.join(work, d) for d in ("src", "log.txt"))
    build = os.path.join(src, "build")
    if os.path.exists(src):
        shutil.rmtree(src)
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True, capture_output=True).stdout.split(b"\0")
    for f in filter(None, files):
        rel = f.decode()
        os.makedirs(os.path.dirname(os.path.join(src, rel)) or src, exist_ok=True)
        shutil.copy(os.path.join(ROOT, rel), os.path.join(src, rel))  # new times: make rebuilds all
    git = ["git", "-c", "user.name=mutate", "-c", "user.email=mutate@localhost"]
    for cmd in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "mutate.py: the sources under test"]):
        subprocess.run(git + cmd, cwd=src, check=True, capture_output=True)
    open(log, "w").close()
    shared = os.path.join(work, "shared")  # (../shared, as in a clone)
    if not os.path.exists(shared):
        os.symlink(os.path.realpath(os.path.join(ROOT, "..", "shared")), shared)
    if run(["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release"], src, log):
        return None
    return src, build, log


def suite(work, build, src, log, jobs):
    """Builds and runs the suite; the failing tests (None: did not build)."""
    if run(["cmake", "--build", build, "-j", str(jobs)], src, log):
        return None
    junit = os.path.join(work, "junit.xml")
    if os.path.exists(junit):
        os.remove(junit)
    # The tests' temporary folders in one of the run's own, emptied after
    # every suite: a test that a mutant makes hang is killed at the
    # timeout, before its TearDown removes its folder.
    tmp = os.path.join(work, "tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    # (Not MutantsApply: a planted mutant is, by design, text that no longer fits.)
    run(["ctest", "-j", str(jobs), "--timeout", "120", "-E", "^MutantsApply$", "--output-junit", junit], build, log,
        env=dict(os.environ, TMPDIR=tmp))
    shutil.rmtree(tmp, ignore_errors=True)
    return failed_tests(junit)


def plant_each(chosen, src, run_suite):
    """Each mutant planted in turn, the suite run, the file restored: the
    table's rows and the mutants missed (or that did not build)."""
    rows, missed = [], []
    for name, path, old, new, what in chosen:
        p = os.path.join(src, path)
        with open(p) as f:
            text = f.read()
        if text.count(old) != 1:
            raise outputs.ToolError(f"{name}: the text to change occurs {text.count(old)} times in {path}",
                                    outputs.FAILED)
        with open(p, "w") as f:
            f.write(text.replace(old, new))
        try:
            failed = run_suite()
        finally:
            with open(p, "w") as f:
                f.write(text)
        if failed is None:
            verdict, detail = "did not build", ""
            missed.append(name)
        elif failed:
            verdict = f"caught by {len(failed)}"
            detail = ", ".join(sorted(failed)[:3]) + (", ..." if len(failed) > 3 else "")
        else:
            verdict, detail = "**missed**", ""
            missed.append(name)
        others = [t for t in failed or [] if not any(o in t for o in ORACLES)]
        without = f"{len(others)}" if others else "**0: missed**"
        print(f"{name}: {verdict}; without the oracles {len(others)}; {detail}", flush=True)
        rows.append(f"| `{name}` | {what} | {verdict} | {without} | {detail} |")
    return rows, missed


def main():
    args = parse_args()
    if args.list:
        for name, path, _, _, what in MUTANTS:
            print(f"{name:30s} {path:28s} {what}")
        return 0
    chosen = [m for m in MUTANTS if not args.only or m[0] in args.only.split(",")]
    unknown = set(filter(None, args.only.split(","))) - {m[0] for m in MUTANTS}
    if unknown:
        raise outputs.ToolError(f"unknown mutant(s): {', '.join(sorted(unknown))}")
    if args.only and args.doc:
        raise outputs.ToolError("--doc publishes the whole table; it cannot go with --only")
    if args.jobs < 1:
        raise outputs.ToolError(f"--jobs {args.jobs}: at least 1")
    # Every mutant's text must sit exactly once in its file before anything is
    # built: a text that drifted from the code would otherwise stop the run
    # midway, after an hour of building.
    drifted = stale(MUTANTS if args.check else chosen)
    if drifted:
        raise outputs.ToolError(f"the text to change is not found exactly once for: {'; '.join(drifted)}")
    if args.check:
        print(f"mutate.py: all {len(MUTANTS)} mutants' texts found once each")
        return 0

    args.work = own_work_dir(args.work)
    # Where the table goes, checked now rather than after an hour of builds.
    # A partial run (--only) leaves the published table alone: its table goes
    # to the work directory; a whole one to out/results/, or with --doc to
    # doc/results/.
    results = args.work if args.only else RESULTS if args.doc else os.path.dirname(outputs.out_path("results", "x"))
    outputs.check_output(os.path.join(results, "mutate.md"), "the table", doc=args.doc)
    if args.doc:
        outputs.check_output(os.path.join(ROOT, "doc", "robustness.md"), "--doc", doc=True)
    copied = copy_sources(args.work)
    if copied is None:
        raise outputs.ToolError(f"cmake failed (see {os.path.join(args.work, 'log.txt')})", outputs.FAILED)
    src, build, log = copied

    def run_suite():
        return suite(args.work, build, src, log, args.jobs)

    t0 = time.time()
    base = run_suite()
    if base is None or base:
        raise outputs.ToolError(f"the unmutated suite does not pass ({base}); see {log}", outputs.FAILED)
    rows, missed = plant_each(chosen, src, run_suite)
    run_suite()  # leave the work build unmutated
    return publish(args, results, chosen, rows, missed, time.time() - t0)


def publish(args, results, chosen, rows, missed, seconds):
    """The table, to where main checked it may go; 1 if any mutant was missed."""
    lines = [
        "<!-- written by scripts/mutate.py -->",
        f"{len(chosen) - len(missed)} of {len(chosen)} planted timing bugs caught by the suite "
        f"({seconds / 60:.0f} minutes on {args.jobs} jobs).",
        "",
        "| mutant | the planted bug | tests failing | of them not timing oracles | some of them |",
        "|---|---|---|---|---|",
    ] + rows
    publish_table(lines, os.path.join(results, "mutate.md"),
                  os.path.join(ROOT, "doc", "robustness.md") if args.doc else None, "mutate")
    if args.only:
        print(f"mutate.py: --only: table in {os.path.join(results, 'mutate.md')}, doc/results left alone", file=sys.stderr)
    elif not args.doc:
        print(f"mutate.py: table in {os.path.join(results, 'mutate.md')}; --doc publishes it", file=sys.stderr)
    if missed:
        print(f"mutate.py: missed: {', '.join(missed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(outputs.guard("mutate.py", main))
