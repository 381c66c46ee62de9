"""doc/report.md names every field a report has: runs rtsim the way a user
would (balancing over frames with its reference runs; a control lane with
per-node and per-link settings and tracing; a scene file; a rerun) and
checks that each field path of each report (arrays as [], message types as
TYPE, kinds of work as KIND, each kind named too) stands in the page in backquotes. A field added to the report
without a line in the glossary fails here.
Run by ctest as: /usr/bin/python3 test_report_doc.py <rtsim>."""
import json
import os
import re
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RTSIM = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(ROOT, "build", "rtsim")
TYPES = {"ray", "contributions", "credit", "load_report", "slide", "ack", "sample", "planes", "fb_expect", "fb_done"}


# Fields documented as another's set: a node's costs as config.costs, a
# link's settings as config.link.
ALIASES = {"config.node_costs[].costs.": "config.costs.", "config.link_overrides[].link.": "config.link."}


def paths(x, prefix=""):
    """The report's field paths: `a.b`, `a[].b`, a message type (a key of
    messages, bytes or wire_ns) as TYPE; an array of numbers or strings is
    the field itself."""
    if isinstance(x, dict):
        by_type = prefix.rsplit(".", 1)[-1] in ("messages", "bytes", "wire_ns")
        by_kind = prefix.endswith("busy_by_category")
        for k, v in x.items():
            key = "TYPE" if by_type and k in TYPES else "KIND" if by_kind else k
            yield from paths(v, f"{prefix}.{key}" if prefix else key)
    elif isinstance(x, list) and x and all(isinstance(v, (dict, list)) for v in x) and \
            not all(isinstance(v, list) and all(not isinstance(w, (dict, list)) for w in v) for v in x):
        for v in x:
            yield from paths(v, prefix + "[]")
    else:
        yield prefix


class ReportDoc(unittest.TestCase):
    def test_every_field_is_in_the_glossary(self):
        with open(os.path.join(ROOT, "doc", "report.md")) as f:
            doc = f.read()
        named = set(re.findall(r"`([\w.\[\]]+)`", doc))
        scene = os.path.join(os.path.dirname(ROOT), "shared", "scenes", "spd", "balls-1.nff")
        runs = [
            ["--balance", "recommended", "--frames", "2", "--size", "24x24", "--mesh", "3", "--spheres", "80"],
            ["--mesh", "2", "--size", "16x16", "--spheres", "40", "--balance", "slide", "--link-control-depth", "2",
             "--balance-interval", "2us", "--node-speed", "0,0,0=2", "--node-cost", "1,0,0:sphere=20ns",
             "--link-set", "0,0,0,+x:latency=200ns", "--trace-nodes", "0,0,0", "--trace-links", "1,1,1,fb",
             "--vcd", "VCD", "--no-baseline"],
            ["--scene", scene, "--size", "16x16", "--mesh", "2", "--eye-step", "0,0,0.01", "--frames", "2",
             "--no-baseline"],
            # A sequence that reaches sample's trial (frames[].then from frame 3 on: start_forecast_ns).
            ["--config", os.path.join(ROOT, "configs", "paper.conf"), "--spheres", "1000", "--radius", "0.02", "--seed",
             "1", "--size", "256x256", "--mesh", "5", "--concentration", "0.2", "--balance", "sample", "--frames", "4",
             "--no-baseline"],
        ]
        with tempfile.TemporaryDirectory() as d:
            reports = []
            for i, args in enumerate(runs):
                report = os.path.join(d, f"r{i}.json")
                args = [a.replace("VCD", os.path.join(d, "t.vcd")) for a in args]
                subprocess.run([RTSIM, *args, "-q", "--image", "", "--report", report], check=True)
                reports.append(report)
            again = os.path.join(d, "again.json")
            subprocess.run([RTSIM, "--rerun", reports[1], "-q", "--image", "", "--report", again], check=True)
            reports.append(again)
            missing = set()
            for report in reports:
                with open(report) as f:
                    r = json.load(f)
                # Each kind of work (busy_by_category's keys, documented as KIND) has its line too.
                missing |= {k for k in r["totals"]["busy_by_category"] if k not in named}
                for p in paths(r):
                        # (rerun.of holds the rerun report's own rerun fields)
                        if p.startswith("rerun.of."):
                            p = "rerun.of"
                        for alias, documented in ALIASES.items():
                            if p.startswith(alias):
                                p = documented + p[len(alias):]
                        if p not in named:
                            missing.add(p)
        self.assertFalse(missing, f"fields doc/report.md does not name: {sorted(missing)}")


if __name__ == "__main__":
    unittest.main()
