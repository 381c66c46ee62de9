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
from project import ROOT, publish_table  # noqa: E402


def main():
    log_path, status, seconds, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    target = sys.argv[5] if len(sys.argv) > 5 else "nff"
    name = "fuzz" if target == "nff" else "fuzz-" + target
    text = open(log_path, errors="replace").read()
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
    if sys.argv[6:7] == ["doc"]:
        publish_table(lines, os.path.join(ROOT, "doc", "results", name + ".md"), os.path.join(ROOT, "doc", "robustness.md"), name)
    else:
        publish_table(lines, os.path.join(out, name + ".md"), None, name)


if __name__ == "__main__":
    main()
