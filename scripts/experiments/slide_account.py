#!/usr/bin/python3
"""Where the paper's rule (`slide`, and its relaying reading `relay`) spends
its one frame, on the paper's machine: Fig. 4's scene at f = 1/N along the
progress axis, one frame. Per policy and N:
the frame against the unbalanced one; how many layers of a column worked
most of the frame (a layer: the nodes of one index along the columns; it
worked when its nodes were busy half the frame or more, on average); the
rounds of load reports each boundary had, and what the guard refused (a slide that costs more than
it returns, on loads too old, hops too slow, a busy link); how far the
first plane and the last one moved from where they started, against the
best static split's; and when the last slide came, as a share of the
frame. With --doc, writes doc/results/slide_account[-PRESET].{csv,md} and
the table into doc/balancing.md. Run with /usr/bin/python3."""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import project  # noqa: E402
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, VIEWS, preset_flags, publish_table, variant  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="4,8")
    ap.add_argument("--policies", default="slide,relay",
                    help="the in-frame policies taken apart (relay: the paper's rule read so that work travels)")
    project.add_machine_arguments(ap, "paper", "slide_account")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    ns = outputs.numbers(a.n, "--n", least=2, most=32)  # (nodes per axis: a column has a plane; rtsim --mesh: at most 32)
    project.check_variant(a)
    policies = [p for p in a.policies.split(",") if p]
    if not policies:
        raise outputs.ToolError("--policies: name at least one policy")
    stem = "slide_account" + variant(a.preset, a.tag)
    rows = driver.swept_rows(a, os.path.join(a.out, stem + ".csv"), lambda: sweep(a, ns, policies))
    table(a, rows, os.path.join(a.out, stem + ".md"))


def sweep(a, ns, policies):
    points = [{"params": {"N": n, "policy": p},
               "args": preset_flags(a.preset) + PAPER_SCENE + VIEWS["along"] +
               ["--mesh", n, "--concentration", f"{1 / n:.6f}", "--balance", p] + a.extra.split()}
              for n in ns for p in ["none"] + policies]
    runs = driver.run("slide_account" + (variant(a.preset, a.tag) or "-modern"), points, extract, None, a)
    by = {(r["N"], r["policy"]): r for r in runs}
    best = project.best_static(a)
    rows = []
    for p in policies:
        for n in ns:
            r = dict(by[(n, p)])
            r["ratio"] = r["render_time_ns"] / by[(n, "none")]["render_time_ns"]
            b = best.get(("along", n))
            r["best_static"] = b[0] if b else ""
            rows.append(r)
    return rows


def extract(r):
    """The frame's account from one report (its own figures, not the nodes')."""
    end = r["render_time_ns"]
    n = r["config"]["mesh"][0]
    layers = {}
    for node in r["nodes"]:
        layers.setdefault(node["node"][0], []).append(node["busy_ns"] / end)
    b = r["balance"]
    moves = {}  # boundary index -> (first position, last position, time of the last move)
    for h in r["boundaries"]:
        first, last = h["history"][0][1], h["history"][-1][1]
        moves.setdefault(h["index"], []).append((last - first, h["history"][-1][0] if len(h["history"]) > 1 else 0))
    last_slide = max((t for v in moves.values() for _, t in v), default=0)
    columns = len(r["nodes"]) // n
    return {"render_time_ns": end, "slides": b["slides"], "decisions": b["decisions"],
            "rounds": b["decisions"] / (2 * columns * (n - 1)),  # per boundary: each of its two nodes decides once a round
            "layers_working": sum(statistics.mean(v) >= 0.5 for v in layers.values()),
            "layer_busy": " ".join(f"{statistics.mean(layers[k]):.2f}" for k in sorted(layers)),
            "refused_cost": b["guard_cost"], "refused_stale": b["guard_stale"], "refused_latency": b["guard_latency"],
            "refused_busy_link": b["guard_busy_link"],
            "first_plane_moved": statistics.median(d for d, _ in moves.get(1, [(0, 0)])),
            "last_plane_moved": statistics.median(d for d, _ in moves.get(n - 1, [(0, 0)])),
            "last_slide_share": last_slide / end}


def table(a, rows, md_path):
    lines = [f"<!-- written by scripts/experiments/slide_account.py {project.invocation(a)}; do not edit -->",
             "| policy | N | frame / none | best static split | layers working (of N) | each layer's busy share | rounds per "
             "boundary | slides | refused: cost | stale | hop | busy link | plane 1 moved (median) | plane N-1 moved | last slide "
             "(share of the frame) |",
             "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        best = f"{float(r['best_static']):.3f}" if r["best_static"] not in ("", None) else "-"
        lines.append(f"| {r['policy']} | {r['N']} | {float(r['ratio']):.3f} | {best} | {r['layers_working']} | {r['layer_busy']} | "
                     f"{float(r['rounds']):.0f} | {r['slides']} | {r['refused_cost']} | {r['refused_stale']} | "
                     f"{r['refused_latency']} | {r['refused_busy_link']} | {float(r['first_plane_moved']):+.4f} | "
                     f"{float(r['last_plane_moved']):+.4f} | {float(r['last_slide_share']):.2f} |")
    publish_table(lines, md_path, a.doc, "slide account " + project.machine(a))


if __name__ == "__main__":
    sys.exit(outputs.guard("slide_account.py", main))
