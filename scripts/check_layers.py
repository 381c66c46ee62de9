#!/usr/bin/python3
"""Checks that includes and imports flow one way, down the layers, in the
whole tree: sw/ (the tracer) at the bottom, then the folders of models/ in
LAYERS' order, then tb/; and in scripts/, no module imports one that
imports it back, directly or through others.

A C++ file may include from its own folder and from the layers below it,
never from a layer above, and never from another folder of its own layer.
A header and its source count as one unit, and no units include each
other in a loop. doc/machine.md's file table lists the folders of models/
in LAYERS' order (checked too).

  /usr/bin/python3 scripts/check_layers.py      # exit 1 with one line per problem

Standard library only (the suite runs it as the test Layers).
"""
import argparse
import ast
import glob
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import outputs  # noqa: E402
from project import ROOT  # noqa: E402

# models/'s folders, lowest first; folders on one line share a layer and may
# not include each other.
LAYERS = [["base"], ["trace"], ["channel"], ["config"], ["balance", "process"], ["node", "framebuffer"],
          ["machine"], ["analysis"]]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer_of(path):
    """(rank, folder) of a tree path: sw/ below every folder of models/, tb/ above."""
    parts = path.split("/")
    if parts[0] == "sw":
        return -1, "sw"
    if parts[0] == "tb":
        return len(LAYERS), "tb"
    if parts[0] == "models" and len(parts) > 2:
        for rank, folders in enumerate(LAYERS):
            if parts[1] in folders:
                return rank, parts[1]
    return None, parts[0] if len(parts) < 3 else "/".join(parts[:2])


def resolve(include, at):
    """The tree path an include names, or None (a system or generated header)."""
    for base in (os.path.dirname(at), "models", "sw", "tb", "tb/tests"):
        p = os.path.normpath(os.path.join(base, include))
        if os.path.isfile(os.path.join(ROOT, p)):
            return p
    return None


def cpp_graph():
    """{unit: {unit it includes}} over sw/, models/ and tb/: a unit is a path without its extension."""
    graph, problems = {}, []
    for folder in ("sw", "models", "tb"):
        for path in sorted(glob.glob(os.path.join(ROOT, folder, "**", "*.*"), recursive=True)):
            if not path.endswith((".h", ".cpp")):
                continue
            rel = os.path.relpath(path, ROOT)
            with open(path, encoding="utf-8") as f:
                text = f.read()
            unit = os.path.splitext(rel)[0]
            edges = graph.setdefault(unit, set())
            for inc in INCLUDE.findall(text):
                target = resolve(inc, rel)
                if target is None:
                    continue
                problems += layer_problems(rel, target)
                other = os.path.splitext(target)[0]
                if other != unit:
                    edges.add(other)
    return graph, problems


def layer_problems(rel, target):
    (mine, my_folder), (theirs, their_folder) = layer_of(rel), layer_of(target)
    if mine is None:
        return [f"{rel}: in no layer (a folder of models/ that check_layers.py's LAYERS does not list)"]
    if theirs is None:
        return [f"{rel}: includes {target}, in no layer"]
    if their_folder == my_folder or theirs < mine:
        return []
    where = "above it" if theirs > mine else "beside it (its own layer)"
    return [f"{rel}: includes {target}, from {their_folder}/, a layer {where}"]


def py_graph():
    """{module: {module it imports}} over scripts/ (experiments put scripts/ on their path)."""
    paths = glob.glob(os.path.join(ROOT, "scripts", "**", "*.py"), recursive=True)
    names = {os.path.splitext(os.path.basename(p))[0] for p in paths if "experiments" not in p}
    graph = {}
    for path in sorted(paths):
        rel = os.path.relpath(path, ROOT)
        with open(path, encoding="utf-8") as f:
            tree = ast.parse(f.read(), rel)
        edges = graph.setdefault(rel, set())
        for node in ast.walk(tree):  # (imports inside functions count: a lazy import is still a loop)
            mods = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module] if isinstance(node, ast.ImportFrom) and node.module and not node.level else []
            for m in mods:
                top = m.split(".")[0]
                target = os.path.join("scripts", top + ".py")
                if top in names and target != rel:
                    edges.add(target)
    return graph


def cycles(graph):
    """One line per loop found (each loop once), by depth-first search."""
    out, state, stack = [], {}, []

    def visit(u):
        state[u] = 1
        stack.append(u)
        for v in sorted(graph.get(u, ())):
            if state.get(v) == 1:
                loop = stack[stack.index(v):] + [v]
                out.append(" -> ".join(loop))
            elif v not in state:
                visit(v)
        stack.pop()
        state[u] = 2

    for u in sorted(graph):
        if u not in state:
            visit(u)
    return out


def doc_order():
    """Problems with doc/machine.md's file table: its folders in LAYERS' order."""
    with open(os.path.join(ROOT, "doc", "machine.md"), encoding="utf-8") as f:
        shown = re.findall(r"^\| `(\w+)/`:", f.read(), re.M)
    want = [f for folders in LAYERS for f in folders]
    return [] if shown == want else [f"doc/machine.md: the file table's folders {shown}, not LAYERS' {want}"]


def main():
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args()
    graph, problems = cpp_graph()
    problems += [f"include loop: {c}" for c in cycles(graph)]
    problems += [f"import loop: {c}" for c in cycles(py_graph())]
    problems += doc_order()
    for p in problems:
        print(p)
    print(f"check_layers: {len(graph)} C++ units, {len(LAYERS)} layers of models/; {len(problems)} problems",
          file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(outputs.guard("check_layers.py", main))
