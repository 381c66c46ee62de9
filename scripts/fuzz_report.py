#!/usr/bin/python3
"""The figures of a scripts/fuzz.sh run, as Markdown: executions, coverage,
corpus and findings (crash, timeout, out-of-memory and leak reproducers).

usage: fuzz_report.py LOG EXIT_STATUS SECONDS OUT_DIR [TARGET [doc]]

TARGET (nff, report or config; default nff) names the table: fuzz.md for
nff, fuzz-TARGET.md for the others, in OUT_DIR; with `doc` (fuzz.sh --doc),
in doc/results/ and its section of doc/robustness.md instead.
"""
import glob
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import ROOT, publish_table  # noqa: E402

USAGE = __doc__.split("\n\n")[1].strip()


def arguments(argv):
    """(log, exit status, seconds, out folder, target, doc) from the command
    line, checked: one line and exit 2 if they are not what fuzz.sh gives."""
    if argv[:1] in (["-h"], ["--help"]):
        print(__doc__.strip())
        sys.exit(0)
    if not 4 <= len(argv) <= 6 or argv[5:6] not in ([], ["doc"]) or argv[4:5] not in ([], ["nff"], ["report"], ["config"]):
        raise outputs.ToolError(USAGE)
    try:
        status, seconds = int(argv[1]), int(argv[2])
    except ValueError:
        raise outputs.ToolError(f"EXIT_STATUS {argv[1]!r}, SECONDS {argv[2]!r}: whole numbers")
    if not os.path.isdir(argv[3]):
        raise outputs.ToolError(f"OUT_DIR {argv[3]}: not a folder")
    return outputs.check_input(argv[0], "LOG"), status, seconds, argv[3], (argv[4:5] or ["nff"])[0], argv[5:6] == ["doc"]


def main():
    log_path, status, seconds, out, target, doc = arguments(sys.argv[1:])
    name = "fuzz" if target == "nff" else "fuzz-" + target
    with open(log_path, errors="replace") as f:
        text = f.read()
    stats = dict(re.findall(r"^stat::(\w+):\s+(\d+)", text, re.M))
    progress = re.findall(r"^#(\d+)\s+\w+\s+cov: (\d+) ft: (\d+) corp: (\d+)/(\S+)", text, re.M)
    findings = sorted(os.path.basename(p) for pattern in ("crash-*", "timeout-*", "oom-*", "leak-*")
                      for p in glob.glob(os.path.join(out, pattern)))
    lines = ["<!-- written by scripts/fuzz.sh; do not edit -->",
             "| figure | value |", "|---|---:|",
             f"| time | {seconds} s |",
             f"| executions | {int(stats.get('number_of_executed_units', 0)):,} |",
             f"| executions per second | {int(stats.get('average_exec_per_sec', 0)):,} |"]
    if progress:
        execs, cov, ft, corp, size = progress[-1]
        lines += [f"| coverage (edges) | {int(cov):,} |", f"| features | {int(ft):,} |",
                  f"| corpus | {int(corp):,} inputs, {size} |"]
    lines += [f"| peak memory | {stats.get('peak_rss_mb', '?')} MB |",
              f"| libFuzzer's exit status | {status} |",
              f"| findings | {len(findings)}{': ' + ', '.join(findings) if findings else ''} |"]
    if doc:
        publish_table(lines, os.path.join(ROOT, "doc", "results", name + ".md"), os.path.join(ROOT, "doc", "robustness.md"), name)
    else:
        publish_table(lines, outputs.check_output(os.path.join(out, name + ".md"), "OUT_DIR"), None, name)


if __name__ == "__main__":
    sys.exit(outputs.guard("fuzz_report.py", main))
