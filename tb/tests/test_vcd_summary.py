"""Tests of scripts/vcd_summary.py (waveforms without a GUI): on a VCD
written here by hand, every share it prints is the one worked out below;
links are ranked by their time busy with a backlog; on a VCD of rtsim's,
each node's busy share over the span is its report's busy time over the
render time; times are read in the VCD's $timescale and printed in real
units; a zero-length trace window, a VCD with no value change, another tool's
VCD (multi-line $comment/$date, vectors, reals), an extra $upscope, bytes
that are not text, a folder, a bad flag, a closed or full stdout and a
reader gone (| head) each get one line (or none) and no traceback; a VCD
all on one line reads as the same on many.
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

    def test_times_in_the_vcds_timescale(self):
        # The same 100 ticks: 100 ps, 100 ns, 1 ns (10 ps ticks), 100 us; the shares do not change.
        for scale, header in (("1ps", "100 ps traced (0 to 100 ps), 4 windows of 25 ps"),
                              ("1 ns", "100 ns traced (0 to 100 ns), 4 windows of 25 ns"),
                              ("10 ps", "1 ns traced (0 to 1 ns), 4 windows of 250 ps"),
                              ("100us", "10 ms traced (0 to 10 ms), 4 windows of 2.5 ms")):
            with self.subTest(scale=scale), tempfile.TemporaryDirectory() as d:
                path = os.path.join(d, "hand.vcd")
                with open(path, "w") as f:
                    f.write(HAND.replace("$timescale 1ps $end", f"$timescale {scale} $end"))
                p = summary(path, "--windows", "4")
                self.assertEqual(p.returncode, 0, p.stderr)
                self.assertIn(f"hand.vcd: {header};", p.stdout.splitlines()[0])
                self.assertIn(" 1.00 0.20 0.60 0.20 | 0.50", p.stdout)
        # Without a $timescale the times are said to be ticks, not taken for picoseconds.
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "hand.vcd")
            with open(path, "w") as f:
                f.write(HAND.replace("$timescale 1ps $end\n", ""))
            p = summary(path, "--windows", "4")
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("100 ticks traced", p.stdout)
            self.assertIn("no $timescale", p.stdout)

    def test_another_tools_vcd(self):
        # Multi-line $date and $comment, a vector and a real among the
        # signals, $dumpvars: read. Busy over [0, 40) of 0..100 ns.
        other = """$date
   Sat Nov 28 2026
$end
$version other tool 1.0 $end
$comment a comment
 on two lines $end
$timescale 1ns $end
$scope module top $end
$scope module node_0_0_0 $end
$var wire 1 ! busy $end
$var wire 8 # data [7:0] $end
$var real 64 % load $end
$upscope $end
$upscope $end
$enddefinitions $end
#0
$dumpvars
1!
b1010x01z #
r1.5 %
$end
#40
0!
b00000001 #
r0 %
#100
"""
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "other.vcd")
            with open(path, "w") as f:
                f.write(other)
            p = summary(path, "--windows", "2")
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("other.vcd: 100 ns traced", p.stdout)
            self.assertEqual(next(l for l in p.stdout.splitlines() if "node_0_0_0" in l).split(),
                             ["node_0_0_0", "0.80", "0.00", "|", "0.40"])

    def test_bad_vcds_get_one_line_with_file_and_line(self):
        cases = {  # name: (text, the line's first words, what stderr says after FILE:LINE)
            "upscope": (HAND.replace("$enddefinitions", "$upscope $end\n$enddefinitions"), "$upscope $end\n$end",
                        "$upscope without a $scope to close"),
            "bytes": (HAND.replace("#30\n", "#30\n\udcff\n"), "\udcff", "bytes that are not text"),
            "backwards": (HAND.replace("#45\n", "#35\n"), "#35", "time #35 after #40"),
            "undeclared": (HAND.replace("#90\n", "#90\n1?\n"), "1?", "a change of '?'"),
            "timescale": (HAND.replace("1ps", "3 ps"), "$timescale", "$timescale '3 ps'"),
            "cut": (HAND[:HAND.index("$enddefinitions")] + "$var wire 1 ( busy", "$var wire 1 (",
                    "the file ends inside $var"),
            # Times that were an internal error, exit 1: a digit int() does not
            # take, one that overflowed the windows' width, one past Python's
            # 4,300 digits.
            "superscript": (HAND.replace("#90\n", "#\u00b2\n"), "#\u00b2", "'#\u00b2': not a time"),
            "huge": (HAND.replace("#90\n", "#1" + "0" * 400 + "\n"), "#1000", "'#1" + "0" * 38 + "': not a time (# and a whole number below 2^63)"),
            "huger": (HAND.replace("#90\n", "#" + "9" * 5000 + "\n"), "#999", "'#" + "9" * 39 + "': not a time"),
        }
        with tempfile.TemporaryDirectory() as d:
            for name, (text, words, said) in cases.items():
                with self.subTest(case=name):
                    path = os.path.join(d, name + ".vcd")
                    with open(path, "w", errors="surrogateescape") as f:
                        f.write(text)
                    p = summary(path)
                    line = text[:text.index(words)].count("\n") + 1
                    self.assertEqual(p.returncode, 2, p.stderr)
                    self.assertEqual(p.stderr.count("\n"), 1, p.stderr)
                    self.assertIn(f"{path}:{line}: {said}", p.stderr)
            p = summary(d)
            self.assertEqual((p.returncode, p.stderr), (2, f"vcd_summary: VCD {d}: a folder, not a file\n"))
            # Another tool's signal names: said, in one line.
            path = os.path.join(d, "names.vcd")
            with open(path, "w") as f:
                f.write(HAND.replace(" busy ", " clk ").replace(" wait ", " en ").replace(" wire ", " data ")
                        .replace(" backlog ", " count "))
            p = summary(path)
            self.assertEqual((p.returncode, p.stderr), (2, f"vcd_summary: {path}: no busy, wait, wire or backlog "
                                                           "signal changes in it (not an rtsim VCD?)\n"))

    def test_a_closed_stdout_is_a_quiet_exit(self):
        # | head: the reader is gone before the summary is written.
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "hand.vcd")
            with open(path, "w") as f:
                f.write(HAND)
            p = subprocess.Popen(["/usr/bin/python3", SCRIPT, path], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            p.stdout.close()
            _, err = p.communicate(timeout=60)
        self.assertEqual((p.returncode, err), (0, b""))

    def test_a_trace_window_of_no_length(self):
        # rtsim writes one VCD state for --trace-window T,T: said in one line, not divided by.
        with tempfile.TemporaryDirectory() as d:
            vcd = os.path.join(d, "w.vcd")
            subprocess.run([RTSIM, "--spheres", "50", "--radius", "0.04", "--size", "16x16", "--mesh", "2",
                            "--no-baseline", "-q", "--image", "", "--vcd", vcd, "--trace-window", "5us,5us"],
                           check=True)
            p = summary(vcd)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(p.stdout, f"{vcd}: the traced span is empty (from 5 us to 5 us): no shares to give\n")

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
            self.assertIn("x.vcd:1: 'hello' in the declarations", p.stderr)
            with open(path, "w") as f:
                f.write("$timescale 1ps $end\n")
            p = summary(path)
            self.assertEqual(p.returncode, 2)
            self.assertIn("no $enddefinitions", p.stderr)
            p = summary(os.path.join(d, "missing.vcd"))
            self.assertNotEqual(p.returncode, 0)
            self.assertEqual(len(p.stderr.strip().splitlines()), 1)

    def test_no_value_change_and_all_on_one_line(self):
        # The declarations alone (rtsim writes them for a --trace-window
        # after the run's end): said in one line, exit 0. A VCD all on one
        # line: the changes after $enddefinitions on it are read.
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "h.vcd")
            with open(path, "w") as f:
                f.write(HAND[:HAND.index("#0")])
            p = summary(path)
            self.assertEqual((p.returncode, p.stderr), (0, ""))
            self.assertEqual(p.stdout, f"{path}: no time and no value change after the declarations: nothing was "
                                       "traced (a --trace-window after the run's end?)\n")
            with open(path, "w") as f:
                f.write(HAND.replace("\n", " "))
            p = summary(path, "--windows", "4")
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn(" 1.00 0.20 0.60 0.20 | 0.50", p.stdout)

    def test_argument_errors_in_one_line(self):
        p = summary(os.path.join(HERE, "corpus", "tiny.vcd"), "--windows", "abc")
        self.assertEqual((p.returncode, p.stderr),
                         (2, "vcd_summary.py: error: argument --windows: invalid int value: 'abc'\n"))

    def test_a_closed_or_full_stdout_is_one_line(self):
        # >&-: nowhere to print, said before reading; > /dev/full: the
        # write fails, said, exit 1; never an internal error.
        tiny = os.path.join(HERE, "corpus", "tiny.vcd")
        p = subprocess.run(["/usr/bin/python3", SCRIPT, tiny], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                           text=True, timeout=120, preexec_fn=lambda: os.close(1))
        self.assertEqual((p.returncode, p.stderr), (2, "vcd_summary: stdout is closed: nowhere to print the summary\n"))
        with open("/dev/full", "w") as full:
            p = subprocess.run(["/usr/bin/python3", SCRIPT, tiny], stdout=full, stderr=subprocess.PIPE, text=True,
                               timeout=120)
        self.assertEqual((p.returncode, p.stderr),
                         (1, "vcd_summary: stdout: No space left on device: the summary is not written\n"))


if __name__ == "__main__":
    unittest.main()
