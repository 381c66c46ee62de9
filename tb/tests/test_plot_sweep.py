"""Tests of the chart of a sweep (scripts/plot_sweep.py): the knees are where
a hand computation puts them.
Run by ctest as: /usr/bin/python3 test_plot_sweep.py."""
import csv
import os
import subprocess
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, "..", "..", "scripts")


class PlotSweep(unittest.TestCase):
    def plot(self, rows, *args):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s.csv")
            with open(path, "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=list(rows[0]))
                w.writeheader()
                w.writerows(rows)
            p = subprocess.run(["/usr/bin/python3", os.path.join(SCRIPTS, "plot_sweep.py"), path, *args,
                                "--out", os.path.join(d, "c.png")], capture_output=True, text=True, timeout=120)
            png = open(os.path.join(d, "c.png"), "rb").read(8) if os.path.exists(os.path.join(d, "c.png")) else b""
            return p, png

    def test_knees_where_a_hand_computation_puts_them(self):
        # Best 100 at 16 GB/s; 1.1 x = 110 lies a quarter of the way from
        # 105 (4 GB/s) to 125 (2 GB/s); 1 to 16 GB/s spans more than a
        # decade, so the axis is logarithmic and so is the interpolation:
        # 4 * 2^-0.25 GB/s. 2 x = 200 is reached exactly at 1 GB/s.
        ys = {"1GB/s": 200, "2GB/s": 125, "4GB/s": 105, "8GB/s": 101, "16GB/s": 100}
        p, png = self.plot([{"bw": k, "t": v} for k, v in ys.items()], "--x", "bw", "--y", "t")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(png, b"\x89PNG\r\n\x1a\n")
        self.assertIn(f"x1.1 of it at bw = {4 * 2 ** -0.25:.4g}GB/s", p.stdout)
        self.assertIn("x2 of it at bw = 1GB/s", p.stdout)
        # Within a decade the axis, and the interpolation, are linear: 4 + 0.25 * (2 - 4).
        ys = {"2": 125, "4": 105, "8": 100}
        p, _ = self.plot([{"n": k, "t": v} for k, v in ys.items()], "--x", "n")
        self.assertEqual(p.returncode, 2)  # no render_time_ns column: said, not a traceback
        self.assertIn("no column 'render_time_ns'", p.stderr)
        p, _ = self.plot([{"n": k, "t": v} for k, v in ys.items()], "--x", "n", "--y", "t")
        self.assertIn(f"x1.1 of it at n = {4 + 0.25 * (2 - 4):.4g}", p.stdout)
        self.assertIn("x2 of it at n = not reached", p.stdout)


if __name__ == "__main__":
    unittest.main()
