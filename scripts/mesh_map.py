#!/usr/bin/python3
"""A picture of one run's mesh, from its report: each layer along the
balancing axis as a grid of nodes coloured by load (one colour scale, the
only colour bar, from 0 to a round value at or above the busiest node's
load), the busiest node ringed and named; the links between them in grey,
their width and darkness growing with wire utilisation (within a layer as
lines; towards the next layer as a triangle in the node, pointing up the
axis), saturated links in red (busy with messages waiting for the wire for
at least SATURATED of the frame: the report's links[].saturated_ns); and,
when balancing ran, a second panel with every boundary's position over
time, one colour per column. A mesh of more than MAX_LAYERS layers shows
the MAX_LAYERS layers that hold its busiest nodes (--layers FROM:TO
chooses others), and a mesh more than LABELLED nodes wide shows its loads
as an image and only its saturated links. Usage:
mesh_map.py REPORT.json -o OUT.png [--format png|svg|pdf] [--layers FROM:TO]
[--doc] (the format: the output's extension, unless given; -o under doc/
only with --doc, which rtsim --map passes for the path its user named). Run with
/usr/bin/python3 (Debian's python3-matplotlib). The same report gives the
same file, byte for byte (no dates in it). A report that is not JSON, or
lacks what the picture needs, gets one line naming the file and the line
or the field."""
import argparse
import json
import math
import os
import sys
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from outputs import ToolError, check_distinct, check_input, check_output, guard, one_line_errors, savefig  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import cm, colors  # noqa: E402

AXES = "xyz"
SATURATED = 0.1  # a link busy with a backlog for this share of the frame or more is marked
MAX_LAYERS = 8   # layers drawn at most (the busiest, unless --layers)
LABELLED = 12    # nodes per side up to which each node and link is drawn (wider: loads as an image, saturated links)
LOAD_MAP = cm.Blues  # loads only: white (idle) to dark blue; links are grey or red, never on this scale
BUSIEST = "darkorange"  # the busiest node's ring and name

FORMATS = ("png", "svg", "pdf")
# No date or random id in the file: the same report, the same bytes.
NO_DATES = {"png": {}, "svg": {"Date": None}, "pdf": {"CreationDate": None, "ModDate": None}}


def load_top(busiest):
    """The load scale's top: the smallest of 1, 2, 5 x 10^k at or above the
    busiest node's load (at most 1), so that a mesh of light loads is not
    one colour."""
    if busiest >= 1:
        return max(1.0, busiest)
    top = 1.0
    for k in range(1, 7):
        for m in (5, 2, 1):
            if m * 10.0 ** -k >= busiest:
                top = m * 10.0 ** -k
    return top


def link_grey(u):
    """A link's colour for utilisation u: light grey when idle, black when never idle."""
    g = 0.8 * (1 - min(max(u, 0.0), 1.0))
    return (g, g, g)


def chosen_layers(r, ax, layers, asked):
    """The layers to draw: FROM:TO if asked, else all of them up to
    MAX_LAYERS, else the MAX_LAYERS whose busiest node is busiest, in order."""
    if asked:
        lo, _, hi = asked.partition(":")
        try:
            lo, hi = int(lo), int(hi or lo)
        except ValueError:
            raise ToolError(f"--layers {asked}: expected FROM:TO (layer numbers)")
        if not 0 <= lo <= hi < layers:
            raise ToolError(f"--layers {asked}: the mesh has layers 0..{layers - 1}")
        return list(range(lo, hi + 1))
    if layers <= MAX_LAYERS:
        return list(range(layers))
    top = {}
    for n in r["nodes"]:
        k = n["node"][ax]
        top[k] = max(top.get(k, 0), n["load"])
    return sorted(sorted(top, key=lambda k: (-top[k], k))[:MAX_LAYERS])


class Report:
    """Checks, field by field, what the picture reads from a report: one
    line naming the field for anything missing or of the wrong kind."""

    def __init__(self, path):
        self.path = path

    def fail(self, where, what):
        raise ToolError(f"{self.path}: {where}: {what}")

    def number(self, obj, key, where, optional=False):
        if optional and key not in obj:
            return 0.0
        if key not in obj:
            self.fail(where, f"no '{key}'")
        v = obj[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            self.fail(f"{where}.{key}", f"{str(v)[:30]!r} is not a finite number")
        if v < 0:  # (every figure the picture reads is a time, a load or a share)
            self.fail(f"{where}.{key}", f"{v!r} is below 0")
        return float(v)

    def field(self, obj, key, kind, where):
        if not isinstance(obj, dict) or key not in obj:
            self.fail(where, f"no '{key}' (not an rtsim report?)")
        if not isinstance(obj[key], kind):
            self.fail(f"{where}.{key}" if where else key, f"not a {kind.__name__ if isinstance(kind, type) else 'list'}")
        return obj[key]

    def optional_list(self, obj, key):
        """A list the report may leave out (or null): [] then."""
        v = obj.get(key)
        if v is None:
            return []
        if not isinstance(v, list):  # (enumerate(5) was an internal error)
            self.fail(key, f"{str(v)[:30]!r} is not a list")
        return v

    def coords(self, v, where, dims):
        if (not isinstance(v, list) or len(v) != 3 or
                any(isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < d for c, d in zip(v, dims))):
            self.fail(where, f"{str(v)[:30]} is not a node of the {'x'.join(map(str, dims))} mesh")
        return tuple(v)

    def check(self, r):
        if not isinstance(r, dict):
            self.fail("the top", "not a JSON object (not an rtsim report)")
        for k in ("config", "nodes", "links"):
            if k not in r:
                self.fail("the top", f"no '{k}' (not an rtsim report)")
        cfg = self.field(r, "config", dict, "")
        dims = self.field(cfg, "mesh", list, "config")
        if len(dims) != 3 or any(isinstance(d, bool) or not isinstance(d, int) or d < 1 for d in dims):
            self.fail("config.mesh", f"{str(dims)[:30]} is not three sizes")
        bal = self.field(cfg, "balance", dict, "config")
        if bal.get("axis") not in list(AXES):
            self.fail("config.balance.axis", f"{str(bal.get('axis'))[:20]!r} is not x, y or z")
        if not isinstance(bal.get("policy"), str):
            self.fail("config.balance.policy", "not a name")
        if self.number(r, "render_time_ns", "the top") < 0:
            self.fail("render_time_ns", "below 0")
        self.nodes(r, dims)
        self.links(r, dims)
        self.boundaries(r)
        self.busiest(r)

    def nodes(self, r, dims):
        nodes = self.field(r, "nodes", list, "")
        if len(nodes) != dims[0] * dims[1] * dims[2]:
            self.fail("nodes", f"{len(nodes)} of them; the {'x'.join(map(str, dims))} mesh has "
                               f"{dims[0] * dims[1] * dims[2]}")
        seen = set()
        for i, n in enumerate(nodes):
            where = f"nodes[{i}]"
            if not isinstance(n, dict):
                self.fail(where, "not an object")
            c = self.coords(n.get("node"), where + ".node", dims)
            if c in seen:
                self.fail(where + ".node", f"{list(c)} twice")
            seen.add(c)
            self.number(n, "load", where)
            self.number(n, "busy_ns", where, optional=True)  # the load's source: a damaged one is named too

    def links(self, r, dims):
        for i, link in enumerate(self.field(r, "links", list, "")):
            where = f"links[{i}]"
            if not isinstance(link, dict):
                self.fail(where, "not an object")
            self.coords(link.get("from"), where + ".from", dims)
            if not isinstance(link.get("to"), str):  # +x ... -z, or a port (fb)
                self.fail(where + ".to", f"{str(link.get('to'))[:20]!r} is not a direction")
            self.number(link, "utilisation", where)
            self.number(link, "saturated_ns", where, optional=True)

    def boundaries(self, r):
        for i, b in enumerate(self.optional_list(r, "boundaries")):
            where = f"boundaries[{i}]"
            if not isinstance(b, dict) or not isinstance(b.get("column"), list) or not all(
                    isinstance(c, int) for c in b["column"]):
                self.fail(where, "no column")
            h = b.get("history")
            if not isinstance(h, list) or not h or not all(
                    isinstance(p, list) and len(p) == 2 and all(
                        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in p)
                    for p in h):
                self.fail(where + ".history", "not a list of [time, position] pairs")

    def busiest(self, r):
        for i, x in enumerate(self.optional_list(r, "busiest_links")):
            where = f"busiest_links[{i}]"
            if not isinstance(x, dict) or not isinstance(x.get("name"), str):
                self.fail(where, "no name")
            self.number(x, "utilisation", where)
            self.number(x, "saturated_ns", where, optional=True)


def read_report(path):
    """The report, checked: JSON (bad JSON named by line), and every field
    the picture reads."""
    with open(check_input(path, "report"), "rb") as f:
        data = f.read()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data[:e.start].count(b"\n") + 1
        raise ToolError(f"{path}:{line}: bytes that are not UTF-8 text")
    try:
        r = json.loads(text)
    except json.JSONDecodeError as e:
        raise ToolError(f"{path}:{e.lineno}: not JSON: {e.msg} (a report cut short?)")
    except RecursionError:
        raise ToolError(f"{path}: not a report: nested too deep")
    Report(path).check(r)
    return r


class Layer:
    """One layer's panel: each node coloured by load, its links grey by
    utilisation, the saturated ones red."""

    def __init__(self, a, k, ax, u, v, dims, load, util, saturated, norm):
        self.a, self.k, self.ax, self.u, self.v, self.dims = a, k, ax, u, v, dims
        self.load, self.util, self.saturated, self.norm = load, util, saturated, norm

    def cell(self, i, j):
        c = [0, 0, 0]
        c[self.ax], c[self.u], c[self.v] = self.k, i, j
        return tuple(c)

    def in_layer_links(self, i, j):
        """The links within the layer from node (i, j) along +u and +v, both
        ways: (key, xs, ys) with the two directions side by side."""
        u, v, c = self.u, self.v, self.cell(i, j)
        for axis, di, dj in ((u, 1, 0), (v, 0, 1)):
            if (i + di >= self.dims[u]) or (j + dj >= self.dims[v]):
                continue
            for sign, off in (("+", 0.06), ("-", -0.06)):
                if sign == "+":
                    key = (c, "+" + AXES[axis])
                else:
                    d = list(c)
                    d[axis] += 1
                    key = (tuple(d), "-" + AXES[axis])
                xs, ys = [i, i + di], [j, j + dj]
                if di:
                    ys = [y + off for y in ys]
                else:
                    xs = [x + off for x in xs]
                yield key, xs, ys

    def draw_detailed(self):
        """Every node a square with its load written under it, every link a
        grey line or triangle sized by its utilisation."""
        a = self.a
        for i in range(self.dims[self.u]):
            for j in range(self.dims[self.v]):
                c = self.cell(i, j)
                for key, xs, ys in self.in_layer_links(i, j):
                    w = self.util.get(key, 0)
                    a.plot(xs, ys, color=link_grey(w), lw=0.5 + 4 * w, solid_capstyle="butt", zorder=1)
                    if key in self.saturated:
                        a.plot(xs, ys, color="red", lw=1.5, zorder=1.5)
                a.add_patch(plt.Rectangle((i - 0.3, j - 0.3), 0.6, 0.6, facecolor=LOAD_MAP(self.norm(self.load[c])),
                                          edgecolor="0.5", lw=0.5, zorder=2))
                up = self.util.get((c, "+" + AXES[self.ax]))
                if up is not None:  # towards the next layer
                    mark = (c, "+" + AXES[self.ax]) in self.saturated
                    a.plot([i], [j], marker="^", ms=3 + 6 * up, color=link_grey(up), mec="red" if mark else "white",
                           mew=1.5 if mark else 0.5, zorder=3)
                if (c, "-" + AXES[self.ax]) in self.saturated:  # towards the layer before: drawn only when saturated
                    a.plot([i + 0.2], [j + 0.2], marker="v", ms=6, color="red", zorder=3)
                a.text(i, j - 0.42, f"{self.load[c]:.2f}", ha="center", va="top", fontsize=6, zorder=4)

    def draw_dense(self):
        """A layer too wide to write in: the loads as an image, and only
        the saturated links, in red (lines within the layer, triangles to
        the next layer and back)."""
        nu, nv = self.dims[self.u], self.dims[self.v]
        grid = [[self.load[self.cell(i, j)] for i in range(nu)] for j in range(nv)]
        self.a.imshow(grid, origin="lower", cmap=LOAD_MAP, norm=self.norm, extent=(-0.5, nu - 0.5, -0.5, nv - 0.5),
                      interpolation="nearest", zorder=1)
        for i in range(nu):
            for j in range(nv):
                c = self.cell(i, j)
                for key, xs, ys in self.in_layer_links(i, j):
                    if key in self.saturated:
                        self.a.plot(xs, ys, color="red", lw=1.5, zorder=2)
                for d, mark in (("+", "^"), ("-", "v")):
                    if (c, d + AXES[self.ax]) in self.saturated:
                        self.a.plot([i], [j], marker=mark, ms=4, color="red", zorder=3)

    def ring(self, node, name):
        """The busiest node: a ring around it and its name beside it."""
        i, j = node[self.u], node[self.v]
        self.a.plot([i], [j], marker="o", ms=11 if max(self.dims[self.u], self.dims[self.v]) > LABELLED else 16,
                    mfc="none", mec=BUSIEST, mew=2, zorder=5)
        right = i < self.dims[self.u] / 2
        self.a.annotate(f"busiest: {name}", (i, j), xytext=(12 if right else -12, 10), textcoords="offset points",
                        ha="left" if right else "right", fontsize=7, color=BUSIEST, fontweight="bold", zorder=6,
                        bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8})


def wrap(text, inches, points):
    """`text` broken into lines that fit a figure `inches` wide at a font
    of `points` (a character is about half its size wide)."""
    chars = max(40, int(inches * 72 / (points * 0.55)))
    return "\n".join(textwrap.fill(line, chars) for line in text.split("\n"))


def node_name(c):
    return "node_" + "_".join(str(x) for x in c)


def links_of(r):
    """{(node, dir): utilisation} and the set of the saturated (node, dir)."""
    util, saturated = {}, set()
    for link in r["links"]:
        key = (tuple(link["from"]), link["to"])
        util[key] = link["utilisation"]
        if link.get("saturated_ns", 0) >= SATURATED * r["render_time_ns"] > 0:
            saturated.add(key)
    return util, saturated


def boundaries_panel(fig, cell, r, ax):
    b = fig.add_subplot(cell)
    palette = cm.tab10
    columns = sorted({tuple(h["column"]) for h in r["boundaries"]})
    for h in r["boundaries"]:
        t = [p[0] / 1000 for p in h["history"]] + [r["render_time_ns"] / 1000]
        x = [p[1] for p in h["history"]] + [h["history"][-1][1]]
        b.step(t, x, where="post", color=palette(columns.index(tuple(h["column"])) % 10), lw=1)
    b.set_xlabel("time (us)")
    b.set_ylabel(f"boundary position along {AXES[ax]}")
    b.set_title(f"boundaries over time ({r['config']['balance']['policy']}; a colour per column)", fontsize=9)


def title_of(r, dims, ax, shown, asked, busiest, top_load):
    layers = len(shown)
    which = "" if layers == dims[ax] else (f" (layers {shown[0]}..{shown[-1]} of {dims[ax]})" if asked else
                                           f" (the {layers} of {dims[ax]} layers with the busiest nodes)")
    t = r["render_time_ns"]
    return (f"{dims[0]}x{dims[1]}x{dims[2]} mesh{which}, render time {t / 1000:.1f} us; "
            f"busiest node {node_name(busiest)}, load {top_load:.2f} (ringed)\n"
            f"busiest links: " + (", ".join(f"{x['name']} {100 * x['utilisation']:.0f} %" +
                                           (f" (backlog {100 * x['saturated_ns'] / t:.0f} %)" if "saturated_ns" in x
                                            and t else "") for x in r.get("busiest_links") or []) or "none"))


def draw(r, out, fmt, asked=None):
    fig = figure(r, asked)
    plt.rcParams["svg.hashsalt"] = "rtsim"
    savefig(fig, out, dpi=110, format=fmt, metadata=NO_DATES[fmt])
    plt.close(fig)


def figure(r, asked=None):
    """The picture of a checked report (read_report), as a figure."""
    cfg = r["config"]
    dims = cfg["mesh"]
    ax = AXES.index(cfg["balance"]["axis"])
    u, v = (ax + 1) % 3, (ax + 2) % 3
    shown = chosen_layers(r, ax, dims[ax], asked)
    layers = len(shown)
    load = {tuple(n["node"]): n["load"] for n in r["nodes"]}
    busiest = min(load, key=lambda c: (-load[c], c))
    norm = colors.Normalize(0, load_top(load[busiest]))
    util, saturated = links_of(r)
    balanced = cfg["balance"]["policy"] != "none" and bool(r.get("boundaries"))
    cols = max(1, min(4, int(layers ** 0.5 + 0.999)))
    rows = (layers + cols - 1) // cols
    fig = plt.figure(figsize=(3.3 * cols + 1.5, 3.3 * rows + (3.2 if balanced else 0) + 1.4), layout="constrained")
    grid = fig.add_gridspec(rows + (1 if balanced else 0), cols)
    dense = max(dims[u], dims[v]) > LABELLED
    for slot, k in enumerate(shown):
        a = fig.add_subplot(grid[slot // cols, slot % cols])
        a.set_title(f"layer {AXES[ax]} = {k}", fontsize=9)
        a.set_xlim(-0.6, dims[u] - 0.4)
        a.set_ylim(-0.6, dims[v] - 0.4)
        a.set_aspect("equal")
        su, sv = (max(1, dims[u] // 8), max(1, dims[v] // 8)) if dense else (1, 1)
        a.set_xticks(range(0, dims[u], su))
        a.set_yticks(range(0, dims[v], sv))
        a.set_xlabel(AXES[u], fontsize=8)
        a.set_ylabel(AXES[v], fontsize=8)
        a.tick_params(labelsize=7)
        layer = Layer(a, k, ax, u, v, dims, load, util, saturated, norm)
        (layer.draw_dense if dense else layer.draw_detailed)()
        if busiest[ax] == k:
            layer.ring(busiest, node_name(busiest))
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=LOAD_MAP), ax=list(fig.axes), shrink=0.6, location="right",
                 label=f"node load (busy / render time), 0 to {norm.vmax:g}")
    links = ("links: grey, wider and darker the busier the wire (lines: in the layer; triangles: to the next layer); "
             if not dense else "links: only the saturated, ")
    width = fig.get_figwidth()
    fig.supxlabel(wrap(links + f"red: busy with a backlog >= {SATURATED:.0%} of the frame (red v: towards the layer "
                          f"before); ringed: the busiest node", width, 8), fontsize=8)
    if balanced:
        boundaries_panel(fig, grid[rows, :], r, ax)
    fig.suptitle(wrap(title_of(r, dims, ax, shown, asked, busiest, load[busiest]), width, 10), fontsize=10)
    return fig


def main(argv=None):
    ap = one_line_errors(argparse.ArgumentParser(description=__doc__.split("\n\n")[0]))
    ap.add_argument("report")
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--doc", action="store_true",
                    help="allow -o under doc/ (rtsim --map passes it: its user named the path)")
    ap.add_argument("--format", choices=FORMATS, help="png, svg or pdf (default: the output's extension)")
    ap.add_argument("--layers", metavar="FROM:TO",
                    help=f"the layers along the balancing axis to draw (default: all, or for more than {MAX_LAYERS} "
                         f"the {MAX_LAYERS} with the busiest nodes)")
    a = ap.parse_args(argv)
    fmt = a.format or a.out.rsplit(".", 1)[-1].lower()
    if fmt not in FORMATS:
        raise ToolError(f"{a.out}: the name must end in .png, .svg or .pdf (or give --format)")
    # Into doc/ only with --doc: rtsim --map passes it with the temporary
    # beside the path its user named (scripts/mesh_map_example.sh --doc
    # draws the docs' picture so), after rtsim's own checks of that path.
    out = check_output(a.out, "-o", doc=a.doc)
    check_distinct([("report", a.report), ("-o", out)])
    r = read_report(a.report)
    draw(r, out, fmt, a.layers)
    return 0


if __name__ == "__main__":
    sys.exit(guard("mesh_map", main))
