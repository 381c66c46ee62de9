#!/usr/bin/python3
"""Writes the flag reference of doc/usage.md from the programs themselves:
`rtsim --help` and `rtref --help` between the page's generated markers, so
the reference is what the build accepts. With --check, changes nothing and
exits 1 if the page is out of date (the suite runs it as UsageDoc).

  /usr/bin/python3 scripts/usage_doc.py [--build build] [--check]
"""
import argparse
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from project import BUILD, ROOT, update_doc_section  # noqa: E402

PAGE = os.path.join(ROOT, "doc", "usage.md")


def help_text(binary, name):
    """The program's --help, its path as the program's name, in a code block."""
    out = subprocess.run([binary, "--help"], capture_output=True, text=True, check=True).stdout
    out = out.replace(f"Usage: {binary} ", f"Usage: {name} ")
    return "```\n" + "\n".join(line.rstrip() for line in out.rstrip("\n").split("\n")) + "\n```"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=BUILD, help="the build folder whose rtsim and rtref to ask")
    ap.add_argument("--check", action="store_true", help="only check that the page is current")
    a = ap.parse_args()
    sections = {name: help_text(os.path.join(a.build, name), name) for name in ("rtsim", "rtref")}
    with open(PAGE) as f:
        before = f.read()
    for name, text in sections.items():
        update_doc_section(PAGE, f"{name} help", text)
    if a.check:
        with open(PAGE) as f:
            after = f.read()
        with open(PAGE, "w") as f:
            f.write(before)
        if after != before:
            print("usage_doc: doc/usage.md is not what the programs' --help says; run "
                  "/usr/bin/python3 scripts/usage_doc.py", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
