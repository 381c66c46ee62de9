#!/usr/bin/python3
"""A picture of one run's mesh, from its report: each layer along the
balancing axis as a grid of nodes coloured by load, the links between them
drawn by wire utilisation (within a layer as lines; towards the next layer
as a triangle in the node, pointing up the axis), saturated links in red
(busy with messages waiting for the wire for at least SATURATED of the
frame: the report's links[].saturated_ns); and, when balancing ran,
a second panel with every boundary's position over time, one colour per
column. Usage: mesh_map.py REPORT.json -o OUT.png [--format png|svg|pdf]
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


FORMATS = ("png", "svg", "pdf")
# No date or random id in the file: the same report, the same bytes.
NO_DATES = {"png": {}, "svg": {"Date": None}, "pdf": {"CreationDate": None, "ModDate": None}}


def draw(r, out, fmt):
    cfg = r["config"]
    dims = cfg["mesh"]
    ax = AXES.index(cfg["balance"]["axis"])
    u, v = (ax + 1) % 3, (ax + 2) % 3
    layers = dims[ax]
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
    load_map = cm.viridis
    link_map = cm.inferno_r
    norm = colors.Normalize(0, 1)
    for k in range(layers):
        a = fig.add_subplot(grid[k // cols, k % cols])
        a.set_title(f"layer {AXES[ax]} = {k}", fontsize=9)
        a.set_xlim(-0.6, dims[u] - 0.4)
        a.set_ylim(-0.6, dims[v] - 0.4)
        a.set_aspect("equal")
        a.set_xticks(range(dims[u]))
        a.set_yticks(range(dims[v]))
        a.set_xlabel(AXES[u], fontsize=8)
        a.set_ylabel(AXES[v], fontsize=8)
        a.tick_params(labelsize=7)
        for i in range(dims[u]):
            for j in range(dims[v]):
                c = [0, 0, 0]
                c[ax], c[u], c[v] = k, i, j
                c = tuple(c)
                # Links within the layer: +u and +v from this node (the two
                # directions drawn side by side).
                for axis, di, dj in ((u, 1, 0), (v, 0, 1)):
                    if (i + di >= dims[u]) or (j + dj >= dims[v]):
                        continue
                    for sign, off in (("+", 0.06), ("-", -0.06)):
                        if sign == "+":
                            key = (c, "+" + AXES[axis])
                        else:
                            d = list(c)
                            d[axis] += 1
                            key = (tuple(d), "-" + AXES[axis])
                        w = util.get(key, 0)
                        xs = [i, i + di]
                        ys = [j, j + dj]
                        if di:
                            ys = [y + off for y in ys]
                        else:
                            xs = [x + off for x in xs]
                        a.plot(xs, ys, color=link_map(norm(w)), lw=1 + 5 * w, solid_capstyle="butt", zorder=1)
                        if key in saturated:
                            a.plot(xs, ys, color="red", lw=1, ls=":", zorder=1.5)
                a.add_patch(plt.Rectangle((i - 0.3, j - 0.3), 0.6, 0.6, color=load_map(norm(load.get(c, 0))), zorder=2))
                up = util.get((c, "+" + AXES[ax]))
                if up is not None:  # towards the next layer
                    mark = (c, "+" + AXES[ax]) in saturated
                    a.plot([i], [j], marker="^", ms=4 + 8 * up, color=link_map(norm(up)), mec="red" if mark else "white",
                           mew=1.5 if mark else 0.5, zorder=3)
                if (c, "-" + AXES[ax]) in saturated:  # towards the layer before: drawn only when saturated
                    a.plot([i + 0.2], [j + 0.2], marker="v", ms=6, color="red", zorder=3)
                a.text(i, j - 0.42, f"{load.get(c, 0):.2f}", ha="center", va="top", fontsize=6, zorder=4)
    layer_axes = list(fig.axes)
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=load_map), ax=layer_axes, shrink=0.6, location="right",
                 label="node load (busy / render time)")
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=link_map), ax=layer_axes, shrink=0.6, location="right",
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
    title = (f"{dims[0]}x{dims[1]}x{dims[2]} mesh, render time {r['render_time_ns'] / 1000:.1f} us; "
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
    draw(r, a.out, fmt)


if __name__ == "__main__":
    main()
