"""Tests of scripts/vcd_summary.py (waveforms without a GUI): on a VCD
written here by hand, every share it prints is the one worked out below;
links are ranked by their time busy with a backlog; on a VCD of rtsim's,
each node's busy share over the span is its report's busy time over the
render time; a file that is not a VCD gets one line and a nonzero exit.
Run by ctest as: /usr/bin/python3 test_vcd_summary.py <rtsim binary>."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "vcd_summary.py")
RTSIM = os.path.abspath(sys.argv.pop(1)) if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "build", "rtsim")

# Node busy over [0, 30) and [60, 80) of 0..100 ps; link px's wire over
# [10, 50) with a backlog over [20, 40) and [45, 70); link py's wire over
# [0, 100) with a backlog over [90, 95) only.
HAND = """$timescale 1ps $end
$scope module machine $end
$scope module node_0_0_0 $end
$var wire 1 ! busy $end
$var wire 1 " wait $end
$scope module px $end
$var wire 1 # wire $end
$var integer 32 $ backlog $end
$upscope $end
$scope module py $end
$var wire 1 % wire $end
$var integer 32 & backlog $end
$upscope $end
$upscope $end
$upscope $end
$enddefinitions $end
#0
1!
0"
0#
b0 $
1%
b0 &
#10
1#
#20
b10 $
#30
0!
1"
#40
b0 $
#45
b1 $
#50
0#
#60
1!
0"
#70
b0 $
#80
0!
#90
b1 &
#95
b0 &
#100
"""


def summary(path, *args):
    return subprocess.run(["/usr/bin/python3", SCRIPT, path, *args], capture_output=True, text=True, timeout=120)


class VcdSummary(unittest.TestCase):
    def test_shares_worked_out_by_hand(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "hand.vcd")
            with open(path, "w") as f:
                f.write(HAND)
            p = summary(path, "--windows", "4")
        self.assertEqual(p.returncode, 0, p.stderr)
        lines = p.stdout.splitlines()
        node = next(l for l in lines if l.strip().startswith("node_0_0_0 "))
        # windows of 25 ps: busy 25, 5, 15 (60..75), 5 of each; 50 of 100 in all
        self.assertEqual(node.split(), ["node_0_0_0", "1.00", "0.20", "0.60", "0.20", "|", "0.50"])
        px = next(l for l in lines if l.strip().startswith("node_0_0_0_px"))
        py = next(l for l in lines if l.strip().startswith("node_0_0_0_py"))
        # px: wire 15, 25, 0, 0 of each window; busy 40; backlogged while busy [20, 40) + [45, 50) = 25
        self.assertEqual(px.split(), ["node_0_0_0_px", "0.60", "1.00", "0.00", "0.00", "|", "0.40", "|", "0.25"])
        # py: busy throughout, backlogged 5: ranked after px
        self.assertEqual(py.split()[-3:], ["1.00", "|", "0.05"])
        self.assertLess(lines.index(px), lines.index(py))

    def test_node_busy_over_the_span_is_the_reports(self):
        with tempfile.TemporaryDirectory() as d:
            vcd, rep = os.path.join(d, "r.vcd"), os.path.join(d, "r.json")
            subprocess.run([RTSIM, "--spheres", "200", "--radius", "0.04", "--size", "32x32", "--mesh", "2",
                            "--no-baseline", "-q", "--image", "", "--vcd", vcd, "--report", rep], check=True)
            p = summary(vcd)
            with open(rep) as f:
                r = json.load(f)
        self.assertEqual(p.returncode, 0, p.stderr)
        shown = {l.split()[0]: float(l.split()[-1]) for l in p.stdout.splitlines()
                 if l.strip().startswith("node_") and l.count("|") == 1}
        self.assertEqual(len(shown), 8)
        for n in r["nodes"]:
            name = "node_" + "_".join(str(c) for c in n["node"])
            self.assertAlmostEqual(shown[name], n["busy_ns"] / r["render_time_ns"], delta=0.005)

    def test_not_a_vcd_gets_one_line(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "x.vcd")
            with open(path, "w") as f:
                f.write("hello\n")
            p = summary(path)
            self.assertNotEqual(p.returncode, 0)
            self.assertEqual(len(p.stderr.strip().splitlines()), 1)
            self.assertIn("no $enddefinitions", p.stderr)
            p = summary(os.path.join(d, "missing.vcd"))
            self.assertNotEqual(p.returncode, 0)
            self.assertEqual(len(p.stderr.strip().splitlines()), 1)


if __name__ == "__main__":
    unittest.main()
