#!/usr/bin/python3
"""Writes the flag reference of doc/usage.md from the programs themselves:
`rtsim --help` and `rtref --help` between the page's generated markers, so
the reference is what the build accepts. With --doc, into doc/usage.md;
without it, the page as it would be to out/usage.md (doc/ unchanged). With
--check, writes nothing and exits 1 if the page is out of date (the suite
runs it as UsageDoc).

  /usr/bin/python3 scripts/usage_doc.py [--build build] [--doc | --check]
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import BUILD, ROOT  # noqa: E402

PAGE = os.path.join(ROOT, "doc", "usage.md")


def help_text(binary, name):
    """The program's --help, its path as the program's name, in a code block."""
    outputs.check_input(binary, "--build")
    p = outputs.run_child([binary, "--help"], timeout=60)
    if p.returncode != 0:
        raise outputs.ToolError(f"{binary} --help: exit {p.returncode}: {p.stderr.strip()}", outputs.FAILED)
    out = p.stdout.replace(f"Usage: {binary} ", f"Usage: {name} ")
    return "```\n" + "\n".join(line.rstrip() for line in out.rstrip("\n").split("\n")) + "\n```"


def with_section(page, name, text):
    """The page's text with its section NAME (between `<!-- begin NAME
    (generated; do not edit) -->` and `<!-- end NAME -->`) replaced by
    `text`; computed in memory, so that --check never writes the page."""
    begin, end = f"<!-- begin {name} (generated; do not edit) -->", f"<!-- end {name} -->"
    if page.count(begin) != 1 or page.count(end) != 1 or page.index(begin) > page.index(end):
        raise outputs.ToolError(f"{os.path.relpath(PAGE, ROOT)}: no section markers for '{name}' (one begin, one end)")
    head, rest = page.split(begin, 1)
    _, tail = rest.split(end, 1)
    return head + begin + "\n" + text.rstrip("\n") + "\n" + end + tail


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=BUILD, help="the build folder whose rtsim and rtref to ask")
    what = ap.add_mutually_exclusive_group()
    what.add_argument("--doc", action="store_true", help="write doc/usage.md (without it: out/usage.md)")
    what.add_argument("--check", action="store_true", help="only check that the page is current; write nothing")
    a = ap.parse_args()
    with open(outputs.check_input(PAGE, "page"), encoding="utf-8") as f:
        before = f.read()
    after = before
    for name in ("rtsim", "rtref"):
        after = with_section(after, f"{name} help", help_text(os.path.join(a.build, name), name))
    if a.check:
        if after != before:
            print("usage_doc: doc/usage.md is not what the programs' --help says; run "
                  "/usr/bin/python3 scripts/usage_doc.py --doc", file=sys.stderr)
            return 1
        return 0
    if a.doc:
        if after != before:
            outputs.write_text(PAGE, after)
        return 0
    out = outputs.out_path("usage.md")
    outputs.write_text(out, after)
    print(f"usage_doc: wrote {out} (doc/usage.md {'is current' if after == before else 'differs'}; "
          "--doc writes doc/usage.md)")
    return 0


if __name__ == "__main__":
    sys.exit(outputs.guard("usage_doc.py", main))
