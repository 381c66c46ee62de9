#!/usr/bin/python3
"""The order of the primary rays (--primary-order scan or spread) and what
it does to a frame: the unbalanced frame on SPD scenes, and the
recommended policy's steady state (its frame 14, once sample's polish has
spent its tries: between_frames.h, "Polish") at the 24 points where issue
61 holds it against the best static split (Fig. 4's f = 1/N, N = 4, 5
and 8, both views, the modern, 1987 and paper machines and sphere tests
x100).

The steady state depends on where the sequence of re-split frames starts:
the same 24 points under scan with `measured` (its first frame at the
unbalanced split, re-split from frame 2 on) beside the recommended
policy (`sample`'s balanced first frame), and the better of the two.
Then what the polish adds: the recommended policy's frame 6 (some frames
then still trying moves) and frame 14, beside its frame 6 without the
polish (--polish-tries 0, the recommended policy before the polish was
its default).

A node generates its primary rays row by row (scan) or in a stride
through its pixels (spread); the image is the same. Under scan a box
gets its work one part of the image after another, and waits between
them; the forecast that places the planes counts busy time, not that
waiting. The best static split was searched under scan
(partition_search.py); its planes are also run under spread, which no
search has done: a best static split under spread is at most that time,
so the spread gap beside it is a lower bound.

With --doc, writes doc/results/primary_order.{csv,md} and the table
into doc/balancing.md. Run with /usr/bin/python3."""
import argparse
import json
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, RESULTS, ROOT, VIEWS, best_static_splits, preset_flags, publish_table, spd_scene, start_boundaries  # noqa: E402,E501
from csv_rows import read_csv  # noqa: E402

ORDERS = ["scan", "spread"]
# (name, preset, --tag of its partition search, extra flags)
MACHINES = [("modern", "modern", "", []), ("1987", "transputer-1987", "", []), ("paper", "paper", "", []),
            ("sphere tests x100", "modern", "sphere-x100", ["--cost-sphere", "1us"])]
NS = [4, 5, 8]
FRAMES = 14  # the steady state: sample holds by frame 6, then polishes 8 frames
EARLY = 6  # the steady state before the polish (--polish-tries 0)
SCENES = ["balls-4", "gears-2", "tetra-3", "rings-2"]
SCENE_NS = [4, 8]


def boundaries_file(folder, name, n, cols, aligned):
    """A --boundaries-from file holding every column's inner planes along x
    (each column's own where given, else the one set)."""
    keys = [(i, j) for i in range(n) for j in range(n)]
    path = os.path.join(folder, name + ".json")
    with open(path, "w") as fh:
        json.dump(start_boundaries(n, dict(zip(keys, cols)) if cols else {k: aligned for k in keys}), fh)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    csv_path = os.path.join(a.out, "primary_order.csv")
    if a.plot_only:
        outputs.check_input(csv_path, "--plot-only: the CSV")
    else:
        with tempfile.TemporaryDirectory() as folder:
            rows = sweep(a, folder)
        driver.write_csv(csv_path, rows)
    table(a, read_csv(csv_path))


def sweep(a, folder):
    points = []
    for scene in SCENES:
        for n in SCENE_NS:
            for order in ORDERS:
                points.append({"params": {"part": "scene", "machine": scene, "view": "", "N": n, "order": order, "run": "none"},
                               "args": ["--scene", spd_scene(scene), "--size", "128x128", "--mesh", n,
                                        "--primary-order", order]})
    for name, preset, tag, extra in MACHINES:
        best = best_static_splits(argparse.Namespace(preset=preset, tag=tag, out=RESULTS))
        for view, cam in VIEWS.items():
            for n in NS:
                base = preset_flags(preset) + PAPER_SCENE + cam + ["--mesh", n, "--concentration", f"{1 / n:.6f}"] + extra
                if (view, n) not in best:
                    raise SystemExit(f"primary_order.py: no searched split for {preset} {tag} {view} N = {n}")
                _, _, cols, aligned = best[(view, n)]
                split = boundaries_file(folder, f"{preset}-{tag}-{view}-{n}", n, cols, aligned)
                for order in ORDERS:
                    o = ["--primary-order", order]
                    runs = [("none", ["--balance", "none"]),
                            ("recommended", ["--balance", "recommended", "--frames", str(FRAMES)]),
                            ("split", ["--balance", "none", "--boundaries-from", split])]
                    if order == "scan":  # the sequence from the unbalanced first frame, and without the polish
                        runs.append(("measured", ["--balance", "measured", "--frames", str(FRAMES)]))
                        runs.append(("unpolished", ["--balance", "recommended", "--polish-tries", "0",
                                                    "--frames", str(EARLY)]))
                    for run, flags in runs:
                        points.append({"params": {"part": "steady", "machine": name, "view": view, "N": n, "order": order,
                                                  "run": run},
                                       "args": base + flags + o})
    runs = driver.run("primary_order", points, extract, None, a)
    return [dict(r) for r in runs]


def extract(r):
    frames = r.get("frames", [])
    return {"render_time_ns": r["render_time_ns"], "max_busy_ns": max(n["busy_ns"] for n in r["nodes"]),
            "frames_ns": " ".join(f"{f['render_time_ns']:.0f}" for f in frames),
            # (whether the last frame still tried a move of the polish: the frame before chose it)
            "last_tried": int(len(frames) > 1 and frames[-2].get("then", {}).get("next") == "a move tried")}


def table(a, rows):
    by = {(r["machine"], r["view"], int(r["N"]), r["order"], r["run"]): r for r in rows}
    t = lambda *k: float(by[k]["render_time_ns"])  # noqa: E731
    lines = ["<!-- written by scripts/experiments/primary_order.py; do not edit -->",
             "The unbalanced frame (`--balance none`, 128x128) under each order, and its busiest node's busy time "
             "as a share of the frame (the rest is waiting):", "",
             "| scene | N | scan | busy share | spread | busy share | spread / scan |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for scene in SCENES:
        for n in SCENE_NS:
            s, p = by[(scene, "", n, "scan", "none")], by[(scene, "", n, "spread", "none")]
            ts, tp = float(s["render_time_ns"]), float(p["render_time_ns"])
            lines.append(f"| {scene} | {n} | {ts / 1e3:,.1f} us | {float(s['max_busy_ns']) / ts:.3f} | {tp / 1e3:,.1f} us | "
                         f"{float(p['max_busy_ns']) / tp:.3f} | {tp / ts:.3f} |")
    lines += ["", f"The recommended policy's frame {FRAMES} at the 24 points of the steady-state target, as a share of the "
              "unbalanced frame of its own order, and over max(1/N, the best static split): under scan the split "
              "searched under scan; under spread the same planes run under spread (not searched under spread: "
              "a lower bound of the gap).", "",
              f"| machine | view | N | scan: frame {FRAMES} | busy share | best split | busy share | gap | "
              f"spread: unbalanced / scan's | frame {FRAMES} | busy share | the split | busy share | gap (at least) |",
              "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    gaps = {o: [] for o in ORDERS}
    for name, *_ in MACHINES:
        for view in VIEWS:
            for n in NS:
                cells = []
                for o in ORDERS:
                    none = t(name, view, n, o, "none")
                    last = frame_shares(by, (name, view, n, o, "recommended"))[-1]
                    split = t(name, view, n, o, "split") / none
                    gap = last / bound(by, name, view, n, o)
                    gaps[o].append(gap)
                    share = lambda run: float(by[(name, view, n, o, run)]["max_busy_ns"]) / (  # noqa: E731
                        float(by[(name, view, n, o, run)]["frames_ns"].split()[-1]) if run == "recommended" else t(name, view, n, o, run))
                    cells.append((none, last, share("recommended"), split, share("split"), gap))
                (_, l0, b0, s0, c0, g0), (n1, l1, b1, s1, c1, g1) = cells
                lines.append(f"| {name} | {view} | {n} | {l0:.4f} | {b0:.3f} | {s0:.4f} | {c0:.3f} | {g0:.4f} | "
                             f"{n1 / t(name, view, n, 'scan', 'none'):.3f} | {l1:.4f} | {b1:.3f} | {s1:.4f} | {c1:.3f} | {g1:.4f} |")
    tried = sum(int(r["last_tried"]) for r in rows if r["run"] == "recommended")
    lines += ["", " ".join(f"{o}: gap median {statistics.median(g):.4f}, worst {max(g):.4f}" + (";" if o == "scan" else ".")
                           for o, g in gaps.items()) + f" Frame {FRAMES} still tried a move of the polish in {tried} of "
              f"the {len(gaps['scan']) * len(ORDERS)} runs."]
    lines += starts_table(by) + polish_table(by)
    publish_table(lines, os.path.join(a.out, "primary_order.md"), a.doc, "primary_order table")


def frame_shares(by, key):
    """Each frame of run `key` as a share of the unbalanced frame of its order."""
    none = float(by[key[:4] + ("none",)]["render_time_ns"])
    return [float(x) / none for x in by[key]["frames_ns"].split()]


def bound(by, name, view, n, order):
    """max(1/N, the best static split's frame as a share of the unbalanced one): a gap's denominator."""
    none = float(by[(name, view, n, order, "none")]["render_time_ns"])
    return max(1 / n, float(by[(name, view, n, order, "split")]["render_time_ns"]) / none)


def starts_table(by):
    """The steady-state frame under scan from the two starts: `measured` (frame 1
    the unbalanced split) and the recommended policy (frame 1 `sample`'s),
    each over max(1/N, the best static split), and the better of the two."""
    lines = ["", f"Where the sequence starts, under scan: frame {FRAMES} over max(1/N, the best static split) after "
             "`measured`'s first frame (the unbalanced split, measured) and after the recommended policy's "
             "(`sample`'s, balanced within the frame), and the better of the two:", "",
             f"| machine | view | N | measured: frame 1 | frame 2 | frame {FRAMES} | gap | recommended: frame 1 | "
             f"frame {FRAMES} | gap | the better |", "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]

    def row(name, view, n, b):
        fm = frame_shares(by, (name, view, n, "scan", "measured"))
        fr = frame_shares(by, (name, view, n, "scan", "recommended"))
        gm, gr = fm[-1] / b, fr[-1] / b
        return (f"{fm[0]:.4f} | {fm[1]:.4f} | {fm[-1]:.4f} | {gm:.4f} | {fr[0]:.4f} | {fr[-1]:.4f} | {gr:.4f} | "
                f"{min(gm, gr):.4f}"), (gm, gr, min(gm, gr))
    lines += gap_rows(by, ["measured", "recommended", "the better"], row)
    return lines


def gap_rows(by, keys, row):
    """A row per point of the steady-state target, from row(machine, view,
    N, max(1/N, the best static split)) -> (its cells after N, its gaps,
    one per key), then each key's median and worst gap."""
    gaps = {k: [] for k in keys}
    lines = []
    for name, *_ in MACHINES:
        for view in VIEWS:
            for n in NS:
                cells, got = row(name, view, n, bound(by, name, view, n, "scan"))
                for k, g in zip(keys, got):
                    gaps[k].append(g)
                lines.append(f"| {name} | {view} | {n} | {cells} |")
    return lines + ["", "; ".join(f"{k}: gap median {statistics.median(g):.4f}, worst {max(g):.4f}" for k, g in gaps.items()) + "."]


def polish_table(by):
    """What the polish adds, under scan: the recommended policy's frame 6
    without it (--polish-tries 0) and with it, and frame 14, over
    max(1/N, the best static split); and the slowest of its frames after
    the first over the unbalanced frame."""
    lines = ["", f"What the polish adds (under scan): frame {EARLY} without it (`--polish-tries 0`) and with it, "
             f"and frame {FRAMES}, over max(1/N, the best static split); and the slowest frame after frame 1 (a "
             "move tried or not) as a share of the unbalanced frame:", "",
             f"| machine | view | N | no polish: frame {EARLY} gap | frame {EARLY} gap | frame {FRAMES} | gap | "
             "slowest frame after frame 1 |", "|---|---|---:|---:|---:|---:|---:|---:|"]

    def row(name, view, n, b):
        fu = frame_shares(by, (name, view, n, "scan", "unpolished"))
        fr = frame_shares(by, (name, view, n, "scan", "recommended"))
        gu, g6, gp = fu[-1] / b, fr[EARLY - 1] / b, fr[-1] / b
        return f"{gu:.4f} | {g6:.4f} | {fr[-1]:.4f} | {gp:.4f} | {max(fr[1:]):.4f}", (gu, g6, gp)
    lines += gap_rows(by, [f"no polish, frame {EARLY}", f"frame {EARLY}", f"frame {FRAMES}"], row)
    return lines


if __name__ == "__main__":
    sys.exit(outputs.guard("primary_order.py", main))
