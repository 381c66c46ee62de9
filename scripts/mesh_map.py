#!/usr/bin/python3
"""A picture of one run's mesh, from its report: each layer along the
balancing axis as a grid of nodes coloured by load, the links between them
drawn by wire utilisation (within a layer as lines; towards the next layer
as a triangle in the node, pointing up the axis), saturated links in red
(busy with messages waiting for the wire for at least SATURATED of the
frame: the report's links[].saturated_ns); and, when balancing ran,
a second panel with every boundary's position over time, one colour per
column. A mesh of more than MAX_LAYERS layers shows the MAX_LAYERS layers
that hold its busiest nodes (--layers FROM:TO chooses others), and a mesh
more than LABELLED nodes wide shows its loads as an image and only its
saturated links. Usage:
mesh_map.py REPORT.json -o OUT.png [--format png|svg|pdf] [--layers FROM:TO]
(the format: the output's extension, unless given). Run with
/usr/bin/python3 (Debian's python3-matplotlib). The same report gives the
same file, byte for byte (no dates in it)."""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import cm, colors  # noqa: E402

AXES = "xyz"
SATURATED = 0.1  # a link busy with a backlog for this share of the frame or more is marked
MAX_LAYERS = 8   # layers drawn at most (the busiest, unless --layers)
LABELLED = 12    # nodes per side up to which each node and link is drawn (wider: loads as an image, saturated links)
LOAD_MAP = cm.viridis
LINK_MAP = cm.inferno_r


FORMATS = ("png", "svg", "pdf")
# No date or random id in the file: the same report, the same bytes.
NO_DATES = {"png": {}, "svg": {"Date": None}, "pdf": {"CreationDate": None, "ModDate": None}}


def chosen_layers(r, ax, layers, asked):
    """The layers to draw: FROM:TO if asked, else all of them up to
    MAX_LAYERS, else the MAX_LAYERS whose busiest node is busiest, in order."""
    if asked:
        lo, _, hi = asked.partition(":")
        try:
            lo, hi = int(lo), int(hi or lo)
        except ValueError:
            raise ValueError(f"--layers {asked}: expected FROM:TO (layer numbers)")
        if not 0 <= lo <= hi < layers:
            raise ValueError(f"--layers {asked}: the mesh has layers 0..{layers - 1}")
        return list(range(lo, hi + 1))
    if layers <= MAX_LAYERS:
        return list(range(layers))
    top = {}
    for n in r["nodes"]:
        k = n["node"][ax]
        top[k] = max(top.get(k, 0), n["load"])
    return sorted(sorted(top, key=lambda k: (-top[k], k))[:MAX_LAYERS])


class Layer:
    """One layer's panel: each node coloured by load, its links by
    utilisation, the saturated ones in red."""

    def __init__(self, a, k, ax, u, v, dims, load, util, saturated):
        self.a, self.k, self.ax, self.u, self.v, self.dims = a, k, ax, u, v, dims
        self.load, self.util, self.saturated = load, util, saturated

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
        line or a triangle sized by its utilisation."""
        a, norm = self.a, colors.Normalize(0, 1)
        for i in range(self.dims[self.u]):
            for j in range(self.dims[self.v]):
                c = self.cell(i, j)
                for key, xs, ys in self.in_layer_links(i, j):
                    w = self.util.get(key, 0)
                    a.plot(xs, ys, color=LINK_MAP(norm(w)), lw=1 + 5 * w, solid_capstyle="butt", zorder=1)
                    if key in self.saturated:
                        a.plot(xs, ys, color="red", lw=1, ls=":", zorder=1.5)
                a.add_patch(plt.Rectangle((i - 0.3, j - 0.3), 0.6, 0.6, color=LOAD_MAP(norm(self.load.get(c, 0))), zorder=2))
                up = self.util.get((c, "+" + AXES[self.ax]))
                if up is not None:  # towards the next layer
                    mark = (c, "+" + AXES[self.ax]) in self.saturated
                    a.plot([i], [j], marker="^", ms=4 + 8 * up, color=LINK_MAP(norm(up)), mec="red" if mark else "white",
                           mew=1.5 if mark else 0.5, zorder=3)
                if (c, "-" + AXES[self.ax]) in self.saturated:  # towards the layer before: drawn only when saturated
                    a.plot([i + 0.2], [j + 0.2], marker="v", ms=6, color="red", zorder=3)
                a.text(i, j - 0.42, f"{self.load.get(c, 0):.2f}", ha="center", va="top", fontsize=6, zorder=4)

    def draw_dense(self):
        """A layer too wide to write in: the loads as an image, and only
        the saturated links, in red (lines within the layer, triangles to
        the next layer and back)."""
        nu, nv = self.dims[self.u], self.dims[self.v]
        grid = [[self.load.get(self.cell(i, j), 0) for i in range(nu)] for j in range(nv)]
        self.a.imshow(grid, origin="lower", cmap=LOAD_MAP, vmin=0, vmax=1, extent=(-0.5, nu - 0.5, -0.5, nv - 0.5),
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


def draw(r, out, fmt, asked=None):
    cfg = r["config"]
    dims = cfg["mesh"]
    ax = AXES.index(cfg["balance"]["axis"])
    u, v = (ax + 1) % 3, (ax + 2) % 3
    shown = chosen_layers(r, ax, dims[ax], asked)
    layers = len(shown)
    load = {tuple(n["node"]): n["load"] for n in r["nodes"]}
    util = {}  # (node, dir) -> utilisation
    saturated = set()  # (node, dir) of the links marked saturated
    for link in r["links"]:
        util[(tuple(link["from"]), link["to"])] = link["utilisation"]
        if link.get("saturated_ns", 0) >= SATURATED * r["render_time_ns"] > 0:
            saturated.add((tuple(link["from"]), link["to"]))
    balanced = cfg["balance"]["policy"] != "none" and bool(r.get("boundaries"))
    cols = max(1, min(4, int(layers ** 0.5 + 0.999)))
    rows = (layers + cols - 1) // cols
    fig = plt.figure(figsize=(3.3 * cols + 1.5, 3.3 * rows + (3.2 if balanced else 0) + 1.2), layout="constrained")
    grid = fig.add_gridspec(rows + (1 if balanced else 0), cols)
    norm = colors.Normalize(0, 1)
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
        layer = Layer(a, k, ax, u, v, dims, load, util, saturated)
        (layer.draw_dense if dense else layer.draw_detailed)()
    layer_axes = list(fig.axes)
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=LOAD_MAP), ax=layer_axes, shrink=0.6, location="right",
                 label="node load (busy / render time)")
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=LINK_MAP), ax=layer_axes, shrink=0.6, location="right",
                 label="link utilisation (lines: in the layer;\ntriangles: to the next layer;\n"
                       f"red: busy with a backlog >= {SATURATED:.0%} of the frame,\nred v: towards the layer before)")
    if balanced:
        b = fig.add_subplot(grid[rows, :])
        palette = cm.tab10
        columns = sorted({tuple(h["column"]) for h in r["boundaries"]})
        for h in r["boundaries"]:
            t = [p[0] / 1000 for p in h["history"]] + [r["render_time_ns"] / 1000]
            x = [p[1] for p in h["history"]] + [h["history"][-1][1]]
            b.step(t, x, where="post", color=palette(columns.index(tuple(h["column"])) % 10), lw=1)
        b.set_xlabel("time (us)")
        b.set_ylabel(f"boundary position along {AXES[ax]}")
        b.set_title(f"boundaries over time ({cfg['balance']['policy']}; a colour per column)", fontsize=9)
    which = "" if layers == dims[ax] else (f" (layers {shown[0]}..{shown[-1]} of {dims[ax]})" if asked else
                                           f" (the {layers} of {dims[ax]} layers with the busiest nodes)")
    title = (f"{dims[0]}x{dims[1]}x{dims[2]} mesh{which}, render time {r['render_time_ns'] / 1000:.1f} us;\n"
             f"busiest: " + ", ".join(f"{x['name']} {100 * x['utilisation']:.0f} %" +
                                      (f" (backlog {100 * x['saturated_ns'] / r['render_time_ns']:.0f} %)"
                                       if "saturated_ns" in x and r["render_time_ns"] else "")
                                      for x in r.get("busiest_links", [])))
    fig.suptitle(title, fontsize=10)
    plt.rcParams["svg.hashsalt"] = "rtsim"
    fig.savefig(out, dpi=110, format=fmt, metadata=NO_DATES[fmt])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("report")
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--format", choices=FORMATS, help="png, svg or pdf (default: the output's extension)")
    ap.add_argument("--layers", metavar="FROM:TO",
                    help=f"the layers along the balancing axis to draw (default: all, or for more than {MAX_LAYERS} "
                         f"the {MAX_LAYERS} with the busiest nodes)")
    a = ap.parse_args()
    fmt = a.format or a.out.rsplit(".", 1)[-1].lower()
    if fmt not in FORMATS:
        sys.exit(f"mesh_map: {a.out}: the name must end in .png, .svg or .pdf (or give --format)")
    try:
        with open(a.report) as f:
            r = json.load(f)
        for k in ("config", "nodes", "links"):
            if k not in r:
                raise ValueError(f"no '{k}' (not an rtsim report)")
    except (OSError, ValueError) as e:
        sys.exit(f"mesh_map: {a.report}: {e}")
    try:
        draw(r, a.out, fmt, a.layers)
    except ValueError as e:
        sys.exit(f"mesh_map: {e}")


if __name__ == "__main__":
    main()
