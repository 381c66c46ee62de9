#!/usr/bin/python3
"""Checks that the sources stay readable: no source file in models/, tb/,
sw/ or scripts/ (tests aside) over 450 lines, no function there over 60.

  /usr/bin/python3 scripts/check_sizes.py            # the limits; exit 1 if any is passed
  /usr/bin/python3 scripts/check_sizes.py --top 15   # also the longest files and functions

In C++ a function is a brace-delimited body at namespace or class scope whose
opening brace follows a parameter list (lambdas and local classes count
towards the function that holds them); its length runs from the line of
its name to its closing brace. Comments and string literals are skipped.
In Python a function is a def, from its line to its last; nested defs
count towards the def that holds them.
Standard library only (the suite runs it as the test SourceSizes).
"""
import argparse
import ast
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import ROOT  # noqa: E402

FOLDERS = ("models", "tb", "sw", "scripts")
MAX_FILE, MAX_FUNCTION = 450, 60
# What may stand between a parameter list and a function body.
TRAILER = re.compile(r"\)\s*(const|override|final|noexcept|mutable|&|->\s*[\w:<>,\s*&]+|\s)*$")
TRAILER_INIT = re.compile(r"\)\s*(noexcept\s*)?:\s*[\w:]+\s*[({].*$", re.S)


def sources():
    for folder in FOLDERS:
        for dirpath, dirnames, files in os.walk(os.path.join(ROOT, folder)):
            dirnames[:] = sorted(d for d in dirnames if d not in ("tests", "__pycache__"))
            for f in sorted(files):
                if f.endswith((".cpp", ".h", ".py")):
                    yield os.path.relpath(os.path.join(dirpath, f), ROOT)


def strip(text):
    """The text with comments and literals blanked, newlines kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of each function body in C++ text."""
    code = strip(text)
    found, scopes, start = [], [], 0  # scopes: for each open brace, the function it opens or None
    for i, c in enumerate(code):
        if c in ";{}":
            head = code[start:i]
            if c == "{":
                in_function = any(s is not None for s in scopes)
                flat = " ".join(head.split())
                is_function = not in_function and (TRAILER.search(flat) or TRAILER_INIT.search(flat)) \
                    and not re.match(r"^(if|for|while|switch|catch|do)\b", flat)
                if is_function:
                    m = re.search(r"([~\w:]+)\s*\(", flat.split("(")[0] + "(")
                    name = m.group(1) if m else flat[:40]
                    first = code.count("\n", 0, start + len(head) - len(head.lstrip())) + 1
                    scopes.append((name, first))
                else:
                    scopes.append(None)
            elif c == "}" and scopes:
                s = scopes.pop()
                if s is not None:
                    found.append((s[0], s[1], code.count("\n", 0, i) + 1))
            start = i + 1
    return found


def python_functions(text):
    """(name, first line, last line) of each outermost def in Python text."""
    found = []

    def visit(node):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                found.append((child.name, child.lineno, child.end_lineno))
            else:
                visit(child)
    visit(ast.parse(text))
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--top", type=int, default=0, help="also list the N longest files and functions")
    a = ap.parse_args()
    files, funcs = [], []
    for path in sources():
        with open(os.path.join(ROOT, path)) as f:
            text = f.read()
        files.append((text.count("\n"), path))
        found = python_functions(text) if path.endswith(".py") else functions(text)
        funcs += [(last - first + 1, f"{path}:{first} {name}") for name, first, last in found]
    bad = [f"{path}: {n} lines (at most {MAX_FILE})" for n, path in files if n > MAX_FILE]
    bad += [f"{where}: {n} lines (at most {MAX_FUNCTION})" for n, where in funcs if n > MAX_FUNCTION]
    if a.top:
        print("longest files:", *(f"  {n:5d} {p}" for n, p in sorted(files, reverse=True)[:a.top]), sep="\n")
        print("longest functions:", *(f"  {n:5d} {w}" for n, w in sorted(funcs, reverse=True)[:a.top]), sep="\n")
    for b in bad:
        print(f"check_sizes: {b}", file=sys.stderr)
    print(f"check_sizes: {len(files)} files, {len(funcs)} functions in {', '.join(FOLDERS)} (tests aside); "
          f"{len(bad)} over the limits")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(outputs.guard("check_sizes.py", main))
