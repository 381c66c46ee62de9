#!/usr/bin/python3
"""Checks that the docs lead somewhere: in README.md and every page under
doc/ (and the code's comments, for the file paths and cited sections),
each relative link (and image) names a file that exists, and a link
to a section names a heading of that page; each file path the text names
(models/x.h, scripts/y.py, ...; a bare `x.cpp` in backquotes too) exists;
a section cited by name (page.md, "Section") is a heading of that page
(its start will do); doc/machine.md's file table names every file in
models/; and the README is at most 150 lines, its first command within its
first 30.

  /usr/bin/python3 scripts/check_docs.py     # exit 1 and one line per problem

Anchors follow GitHub's rule: the heading in lower case, punctuation but
hyphens and underscores dropped, spaces as hyphens. Standard library only
(the suite runs it as the test DocLinks).
"""
import argparse
import glob
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import ROOT  # noqa: E402

LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
PATH = re.compile(r"(?<![\w/.-])((?:\.\./shared|models|sw|tb|scripts|doc|configs|waveforms|\.ci)/[\w./{},-]*[\w}])")
CITE = re.compile(r"([\w./-]+\.md)(?:\]\([^)]*\))?,\s+\"([^\"]+)\"")
SELF = re.compile(r"\b(?:below|above),\s+\"([^\"]+)\"")  # (below, "Section"): one of this page's
BARE = re.compile(r"`(?![A-Z]{2})([\w-]+\.(?:h|cpp|py|sh|conf|gtkw|cmake))`")  # (FILE.gtkw: a placeholder)
FENCE = re.compile(r"^(```|~~~)")


def pages():
    return [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "doc", "**", "*.md"), recursive=True))


def sources():
    """The code, whose comments cite doc pages and name files too."""
    out = []
    for folder in ("models", "sw", "tb", "scripts"):
        for ext in ("h", "cpp", "py", "sh"):
            out += glob.glob(os.path.join(ROOT, folder, "**", "*." + ext), recursive=True)
    return sorted(p for p in out if not p.endswith("check_docs.py"))  # (its examples are no files)


def slug(heading):
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def headings(path):
    """The page's headings, as text without markup, in lower case."""
    out, fence = [], False
    with open(path) as f:
        for line in f:
            if FENCE.match(line):
                fence = not fence
            if not fence and line.startswith("#"):
                out.append(re.sub(r"[`*]", "", line.lstrip("#")).strip().lower())
    return out


def anchors(path):
    out, fence = set(), False
    with open(path) as f:
        for line in f:
            if FENCE.match(line):
                fence = not fence
            if not fence and line.startswith("#"):
                s = slug(line.lstrip("#"))
                n, base = 1, s
                while s in out:  # a repeated heading gets -1, -2, ...
                    s, n = f"{base}-{n}", n + 1
                out.add(s)
    return out


def expand(path):
    """models/a.{h,cpp} -> models/a.h, models/a.cpp."""
    m = re.search(r"\{([^{}]*)\}", path)
    if not m:
        return [path]
    return [x for part in m.group(1).split(",") for x in expand(path[:m.start()] + part + path[m.end():])]


def prose(path):
    """The page's text with its code blocks blanked (their lines kept); of
    a source file, its text with the comment markers that continue a line
    taken out, so that a citation broken over two lines reads whole."""
    out, fence = [], False
    with open(path) as f:
        if not path.endswith(".md"):
            return re.sub(r"\n[ \t]*(?://|#)[ \t]?", "\n", f.read())
        for line in f:
            if FENCE.match(line):
                fence = not fence
                out.append("\n")
            else:
                out.append("\n" if fence else line)
    return "".join(out)


def check_page(path, names, problems):
    here = os.path.dirname(path)
    rel = os.path.relpath(path, ROOT)
    text = prose(path)

    def at(m):
        return f"{rel}:{text.count(chr(10), 0, m.start()) + 1}"

    for m in LINK.finditer(text):
        target = m.group(1)
        if re.match(r"^[a-z]+:", target):
            continue  # http:, https:, mailto:
        file, _, anchor = target.partition("#")
        full = os.path.normpath(os.path.join(here, file)) if file else path
        if not os.path.exists(full):
            problems.append(f"{at(m)}: link to a missing file: {target}")
        elif anchor and full.endswith(".md") and anchor not in anchors(full):
            problems.append(f"{at(m)}: link to a missing section: {target}")
    for m in PATH.finditer(text):
        mention = m.group(1)
        if "*" in mention or re.search(r"[A-Z]{3,}", mention):
            continue  # a pattern (fig4[-PRESET].csv, out/NAME) rather than a file
        for p in expand(mention.rstrip(".,")):
            full = os.path.join(ROOT, p)
            # (a stem stands for its files: models/channel/link for link.h and link.cpp)
            if not os.path.exists(full) and not glob.glob(full + ".*") and not glob.glob(full + "-*"):
                problems.append(f"{at(m)}: names a missing file: {p}")
    for m in CITE.finditer(text):
        page, section = m.group(1), " ".join(m.group(2).split())
        target = next((t for t in (os.path.join(here, page), os.path.join(ROOT, page), os.path.join(ROOT, "doc", page))
                       if os.path.exists(t)), None)
        name = section.lower().rstrip(".,")
        if target and not any(h.startswith(name) for h in headings(target)):
            problems.append(f"{at(m)}: cites a section that is no heading of {page}: \"{section}\"")
    for m in SELF.finditer(text):
        name = " ".join(m.group(1).split()).lower().rstrip(".,")
        if not any(h.startswith(name) for h in headings(path)):
            problems.append(f"{at(m)}: cites a section that is no heading of this page: \"{m.group(1)}\"")
    for m in BARE.finditer(text):
        if m.group(1) not in names:
            problems.append(f"{at(m)}: names a file that is nowhere in the tree: {m.group(1)}")


def main():
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args()
    names = set()
    for dirpath, dirnames, files in os.walk(ROOT):
        dirnames[:] = [d for d in dirnames if not d.startswith(("build", ".", "out"))]
        names.update(files)
    problems = []
    for path in pages() + sources():
        check_page(path, names, problems)
    machine = open(os.path.join(ROOT, "doc", "machine.md")).read()
    for path in sorted(glob.glob(os.path.join(ROOT, "models", "**", "*.*"), recursive=True)):
        f = os.path.basename(path)
        if f.endswith((".h", ".cpp")) and f"`{f}`" not in machine:
            problems.append(f"doc/machine.md: the file table does not name {os.path.relpath(path, ROOT)}")
    with open(os.path.join(ROOT, "README.md")) as f:
        readme = f.read().split("\n")
    first = next((n for n, line in enumerate(readme, 1) if line.startswith("    bash ")), None)
    if len(readme) > 150:
        problems.append(f"README.md: {len(readme)} lines (at most 150)")
    if first is None or first > 30:
        problems.append(f"README.md: its first command is at line {first} (within the first 30)")
    for p in problems:
        print(p)
    print(f"check_docs: {len(pages())} pages, {len(problems)} problems", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(outputs.guard("check_docs.py", main))
