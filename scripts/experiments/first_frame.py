#!/usr/bin/python3
"""One image, as the paper ran it: the first frame of Fig. 4's experiment at
f = 1/N, for a view along the progress axis and one across it, under each
policy, as a fraction of the unbalanced frame, beside the best static split
that partition_search.py found for the same machine (the better of its one
set of planes and each column's own), 1/N, the paper's 0.2 and the target
(at most 1.2 times max(1/N, the best static split) on the paper's machine,
1.3 on the others). Every point is one rtsim run through the sweep driver,
so it runs locally or on a Dask cluster and a stopped run resumes.

With --doc, writes doc/results/first_frame[-PRESET[-TAG]].{csv,md,png} and
the table into doc/balancing.md. Needs python3-matplotlib (bash
scripts/setup.sh plots); run with /usr/bin/python3."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # scripts/: project, sweep
import project  # noqa: E402
import outputs  # noqa: E402
import sweep_driver as driver  # noqa: E402
from project import PAPER_SCENE, ROOT, VIEWS, preset_flags, publish_table, variant  # noqa: E402

POLICIES = "median,slide,relay,sample+sample-end=generated,sample+sample-end=credit,sample"
PAPER = 0.2


def parse_policy(policy):
    """A policy of --policies, NAME[+FLAG=VALUE...][@K]: (NAME, [(FLAG,
    VALUE)...], K or "") (sample+sample-end=credit@4: sample,
    [(sample-end, credit)], 4)."""
    spec, _, frames = policy.partition("@")
    name, *more = spec.split("+")
    flags = []
    for f in more:
        flag, eq, value = f.partition("=")
        if not flag or not eq:
            raise outputs.ToolError(f"--policies: '{policy}': each +FLAG needs =VALUE (sample+sample-end=credit)")
        flags.append((flag, value))
    return name, flags, frames


def policy_args(policy):
    """Its rtsim flags: --balance NAME --FLAG VALUE ... [--frames K]."""
    name, flags, frames = parse_policy(policy)
    return ["--balance", name] + [x for f, v in flags for x in ("--" + f, v)] + (["--frames", frames] if frames else [])


def label(policy):
    """Its column heading: sample+sample-end=credit is 'sample (sample-end credit)'."""
    name, flags, frames = parse_policy(policy)
    more = ", ".join(f"{f} {v}" for f, v in flags)
    return name + (f" ({more})" if more else "") + (f"@{frames}" if frames else "")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="2,3,4,5,6,7,8")
    ap.add_argument("--policies", default=POLICIES,
                    help="policies compared with none (POLICY@K: its frame K of a sequence, the last one's time; "
                         "POLICY+FLAG=VALUE: with --FLAG VALUE)")
    ap.add_argument("--judged", default="",
                    help="how many of the policies, from the last, the table holds against the target (default: the "
                         "last three, or as many as there are: sample with --sample-end generated, credit and auto)")
    project.add_machine_arguments(ap, "paper", "first_frame")
    driver.add_output_arguments(ap, os.path.join(ROOT, "doc", "balancing.md"))
    driver.add_arguments(ap)
    a = driver.parse_outputs(ap)
    ns = outputs.numbers(a.n, "--n", least=2, most=32)  # (nodes per axis: a column has a plane; rtsim --mesh: at most 32)
    project.check_variant(a)
    policies = a.policies.split(",")
    for p in policies:
        policy_args(p)  # (a malformed one is named before any run)
    a.judged = outputs.numbers(a.judged, "--judged", least=1, most=len(policies))[0] if a.judged else min(3, len(policies))
    stem = "first_frame" + variant(a.preset, a.tag)
    csv_path = os.path.join(a.out, stem + ".csv")
    rows = driver.swept_rows(a, csv_path, lambda: sweep(a, ns, policies))
    for r in rows:
        r["N"] = int(r["N"])
        r["ratio"] = float(r["ratio"])
    best = {k: v[0] for k, v in project.best_static(a).items()}
    plot(a, rows, ns, policies, best, os.path.join(a.out, stem + ".png"))
    table(a, rows, ns, policies, best, os.path.join(a.out, stem + ".md"))


def sweep(a, ns, policies):
    points = []
    for view, cam in VIEWS.items():
        for n in ns:
            for policy in ["none"] + policies:
                points.append({"params": {"view": view, "N": n, "policy": policy},
                               "args": preset_flags(a.preset) + PAPER_SCENE + cam +
                               ["--mesh", n, "--concentration", f"{1 / n:.6f}"] + policy_args(policy) + a.extra.split()})
    runs = driver.run("first_frame" + (variant(a.preset, a.tag) or "-modern"), points, extract, None, a)
    by = {(r["view"], r["N"], r["policy"]): r for r in runs}
    return [{"preset": a.preset, "view": view, "N": n, "policy": p,
             "time_none_ns": by[(view, n, "none")]["render_time_ns"], "time_ns": by[(view, n, p)]["render_time_ns"],
             "ratio": by[(view, n, p)]["render_time_ns"] / by[(view, n, "none")]["render_time_ns"],
             "slides": by[(view, n, p)]["slides"], "version": by[(view, n, p)]["version"],
             "command": by[(view, n, p)]["command"]}
            for view in VIEWS for n in ns for p in policies]


def extract(r):
    return {"render_time_ns": r["render_time_ns"], "slides": r["balance"]["slides"]}


def table(a, rows, ns, policies, best, md_path):
    k = project.target_factor(a)
    inv = project.invocation(a)
    judged = policies[-a.judged:]
    lines = [f"<!-- written by scripts/experiments/first_frame.py {inv}; do not edit -->",
             f"| view | N | {' | '.join(label(p) for p in policies)} | best static split | 1/N | paper | target ({k} x) | "
             + " | ".join(f"{label(p)} / max(1/N, best)" for p in judged) + " |",
             "|---|---:|" + "---:|" * (len(policies) + 4 + len(judged))]
    for view in VIEWS:
        for n in ns:
            ratio = {r["policy"]: r["ratio"] for r in rows if r["view"] == view and r["N"] == n}
            b = best.get((view, n))
            floor = max(1 / n, b) if b else None
            cells = [view, str(n)] + [f"{ratio[p]:.3f}" for p in policies] + [f"{b:.3f}" if b else "-", f"{1 / n:.3f}",
                                                                             str(PAPER)]
            cells += [f"{k * floor:.3f}"] + [f"{ratio[p] / floor:.2f}" for p in judged] if floor else ["-"] * (1 + len(judged))
            lines.append("| " + " | ".join(cells) + " |")
    publish_table(lines, md_path, a.doc, "first frame " + project.machine(a))


def plot(a, rows, ns, policies, best, path):
    plt = project.pyplot()
    fig, axes = plt.subplots(1, len(VIEWS), figsize=(5 * len(VIEWS), 3.6), sharey=True, squeeze=False)
    for col, view in enumerate(VIEWS):
        ax = axes[0][col]
        for p in policies:
            ys = [next(r["ratio"] for r in rows if r["view"] == view and r["N"] == n and r["policy"] == p) for n in ns]
            ax.plot(ns, ys, marker="o", label=label(p))
        known = [(n, best[(view, n)]) for n in ns if (view, n) in best]  # where the search has run
        if known:
            ax.plot([n for n, _ in known], [b for _, b in known], "k--", linewidth=1, label="best static split")
            ax.plot([n for n, _ in known], [project.target_factor(a) * max(1 / n, b) for n, b in known], "r:", linewidth=1,
                    label=f"target: {project.target_factor(a)} x max(1/N, best)")
        ax.plot(ns, [1 / n for n in ns], color="green", linestyle=":", linewidth=1, label="1/N")
        ax.axhline(PAPER, color="grey", linestyle="-.", linewidth=1, label="paper: about 0.2")
        ax.set_ylim(0, 1)
        ax.set_xticks(ns)
        ax.set_xlabel("N")
        ax.set_title(f"view {view}", fontsize=9)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("first frame / unbalanced frame")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8)
    fig.suptitle(f"One image, f = 1/N, preset {project.machine(a)}", fontsize=10)
    fig.tight_layout(rect=(0, 0.12, 1, 0.94))
    outputs.savefig(fig, path, dpi=90)


if __name__ == "__main__":
    sys.exit(outputs.guard("first_frame.py", main))
