#!/usr/bin/python3
"""Reruns every generated table under doc/results/ that a change touches:
those whose CSV holds a point whose rtsim command matches --touching (by
default `--balance sample` or `--balance recommended`, every table a
change of the recommended policy moves). Each table's page names the
script and flags that wrote it (its "written by" line); each such command
runs once, with --fresh (its journal forgotten: a rebuilt policy gives
other figures for the same flags), one after another, its own progress on
stderr. With --doc they publish into doc/ as each script does with --doc;
without it, into out/results/. --list prints the commands and runs none.

A command that fails is named at the end (exit 1); the others still run.
A stop (Ctrl-C) ends the running script and the rest.

    /usr/bin/python3 scripts/rerun_tables.py --list
    /usr/bin/python3 scripts/rerun_tables.py --doc
    /usr/bin/python3 scripts/rerun_tables.py --touching 'balance slide' --doc

Standard library only."""
import argparse
import glob
import os
import re
import shlex
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from csv_rows import read_csv  # noqa: E402
from outputs import ToolError, guard  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "doc", "results")
DEFAULT_TOUCHING = r"--balance (sample|recommended)\b"
WRITTEN_BY = re.compile(r"<!-- written by (scripts/experiments/[A-Za-z0-9_]+\.py)([^;]*); do not edit -->")


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    outputs.one_line_errors(ap)
    ap.add_argument("--touching", default=DEFAULT_TOUCHING, metavar="REGEX",
                    help="rerun the tables with a point whose command matches this Python regular expression "
                         f"(default {DEFAULT_TOUCHING!r})")
    ap.add_argument("--list", action="store_true", help="print the commands, one a line, and run none")
    ap.add_argument("--doc", action="store_true", help="publish: each script with --doc (into doc/)")
    a = ap.parse_args(argv)
    try:
        a.pattern = re.compile(a.touching)
    except re.error as e:
        raise ToolError(f"--touching {a.touching!r}: not a regular expression ({e})", code=outputs.BAD_INPUT)
    return a


def tables(pattern):
    """[(script, its flags as a list, the tables it writes that match)], in
    the order of the pages' names, each command once."""
    found = {}
    for page in sorted(glob.glob(os.path.join(RESULTS, "*.md"))):
        with open(page, encoding="utf-8", errors="replace") as f:
            m = WRITTEN_BY.search(f.read(4096))
        csv_path = page[:-3] + ".csv"
        if not m or not os.path.isfile(csv_path):
            continue
        rows = read_csv(csv_path)
        if not any(pattern.search(r.get("command") or "") for r in rows):
            continue
        script, flags = m.group(1), m.group(2).strip()
        try:
            args = shlex.split(flags)
        except ValueError as e:
            raise ToolError(f"{os.path.relpath(page, ROOT)}: its 'written by' line does not parse ({e})")
        found.setdefault((script, tuple(args)), []).append(os.path.basename(csv_path))
    return [(script, list(args), names) for (script, args), names in found.items()]


def main(argv=None):
    a = parse_args(argv)
    todo = tables(a.pattern)
    if not todo:
        raise ToolError(f"no table under doc/results/ has a point matching {a.touching!r}")
    commands = [[sys.executable, script] + args + ["--fresh"] + (["--doc"] if a.doc else []) for script, args, _ in todo]
    if a.list:
        text = "".join(shlex.join(c[1:]) + f"  # {', '.join(names)}\n" for c, (_, _, names) in zip(commands, todo))
        outputs.deliver(text, "the list")
        return 0
    failed = []
    for i, (cmd, (_, _, names)) in enumerate(zip(commands, todo), 1):
        print(f"rerun_tables: [{i}/{len(commands)}] {shlex.join(cmd[1:])} ({', '.join(names)})", file=sys.stderr, flush=True)
        start = time.monotonic()
        code = outputs.run_child(cmd, capture=False, cwd=ROOT).returncode  # (its progress on the tool's stderr)
        print(f"rerun_tables: [{i}/{len(commands)}] exit {code}, {time.monotonic() - start:.0f} s", file=sys.stderr, flush=True)
        if code:
            failed.append(shlex.join(cmd[1:]))
    if failed:
        raise ToolError(f"{len(failed)} of {len(commands)} failed: " + "; ".join(failed), code=outputs.FAILED)
    return 0


if __name__ == "__main__":
    sys.exit(guard("rerun_tables", main))
