"""Tests of the chart of a sweep (scripts/plot_sweep.py): the knees are where
a hand computation puts them, measured from the reference asked for (by
default the fast end of x, not the line's best); NaN and inf are left out
and said; known columns are drawn in words and units, and each line's
reference and best printed in its column's unit; bad input (argparse's
too) gets one line naming the file and line; a title, a column or a group
with '$' is drawn as written; a closed stdout is quiet and a full one one
line; the chart goes under out/, never beside a
CSV in doc/, and into doc/ only with --doc.
Run by ctest as: /usr/bin/python3 test_plot_sweep.py."""
import csv
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCRIPTS = os.path.join(ROOT, "scripts")
SCRIPT = os.path.join(SCRIPTS, "plot_sweep.py")
sys.path.insert(0, SCRIPTS)
import plot_sweep  # noqa: E402


def run(*args):
    return subprocess.run(["/usr/bin/python3", SCRIPT, *args], capture_output=True, text=True, timeout=120)


class PlotSweep(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name

    def tearDown(self):
        self.dir.cleanup()

    def csv(self, rows, name="s.csv"):
        path = os.path.join(self.d, name)
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        return path

    def plot(self, rows, *args):
        out = os.path.join(self.d, "c.png")
        if os.path.exists(out):
            os.remove(out)
        p = run(self.csv(rows), *args, "--out", out)
        png = open(out, "rb").read(8) if os.path.exists(out) else b""
        return p, png

    def one_line(self, p, said):
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertEqual(p.stderr.count("\n"), 1, p.stderr)
        self.assertNotIn("Traceback", p.stderr)
        self.assertIn(said, p.stderr)

    def test_units_are_the_ones_rtsim_takes(self):
        """The chart reads an x value with a unit as rtsim's parsers do
        (models/base/units.cpp): the same units, the same scales (1Tb/s
        was refused, which rtsim takes)."""
        import re
        with open(os.path.join(ROOT, "models", "base", "units.cpp")) as f:
            text = f.read()
        rates = dict(re.findall(r'\{"([A-Za-z]+/s)",\s*([0-9e.]+(?:\s*/\s*[0-9e.]+)?)\}', text))
        times = dict(re.findall(r'unit == "([a-z]+)"\) scale = ([0-9e.]+);', text))
        self.assertEqual(len(rates), 10, rates)
        self.assertEqual(len(times), 5, times)
        theirs = {u: eval(v) for u, v in rates.items()}  # (a number, or a number over 8)
        theirs.update({u: float(v) * 1e-12 for u, v in times.items()})  # (rtsim's times are in ps)
        self.assertEqual(set(plot_sweep.UNITS), set(theirs))
        for u, scale in theirs.items():
            self.assertAlmostEqual(plot_sweep.UNITS[u], scale, delta=scale * 1e-12, msg=u)

    def test_knees_where_a_hand_computation_puts_them(self):
        # Reference 100 at 16 GB/s (the fast end, also the best); 1.1 x = 110
        # lies a quarter of the way from 105 (4 GB/s) to 125 (2 GB/s); 1 to
        # 16 GB/s spans more than a decade, so the axis is logarithmic and
        # so is the interpolation: 4 * 2^-0.25 GB/s. 2 x = 200 is reached
        # exactly at 1 GB/s.
        ys = {"1GB/s": 200, "2GB/s": 125, "4GB/s": 105, "8GB/s": 101, "16GB/s": 100}
        p, png = self.plot([{"bw": k, "t": v} for k, v in ys.items()], "--x", "bw", "--y", "t")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(png, b"\x89PNG\r\n\x1a\n")
        self.assertIn("t: reference 100 at bw=16GB/s (the largest x); best 100 at bw=16GB/s", p.stdout)
        self.assertIn(f"x1.1 of it at bw = {4 * 2 ** -0.25:.4g}GB/s", p.stdout)
        self.assertIn("x2 of it at bw = 1GB/s", p.stdout)
        # Within a decade the axis, and the interpolation, are linear; from
        # the smallest x (a latency sweep's fast end) the walk goes up x.
        ys = {"2": 125, "4": 105, "8": 100}
        p, _ = self.plot([{"n": k, "t": v} for k, v in ys.items()], "--x", "n")
        self.one_line(p, "--y: no column 'render_time_ns'")  # said, not a traceback
        p, _ = self.plot([{"n": k, "t": v} for k, v in ys.items()], "--x", "n", "--y", "t")
        self.assertIn(f"x1.1 of it at n = {4 + 0.25 * (2 - 4):.4g}", p.stdout)
        self.assertIn("x2 of it at n = not reached", p.stdout)
        ys = {"2": 100, "4": 105, "8": 125}
        p, _ = self.plot([{"lat": k, "t": v} for k, v in ys.items()], "--x", "lat", "--y", "t", "--reference", "min-x")
        self.assertIn("reference 100 at lat=2 (the smallest x)", p.stdout)
        self.assertIn(f"x1.1 of it at lat = {4 + 0.25 * (8 - 4):.4g}", p.stdout)

    def test_knees_from_the_fast_end_not_the_best(self):
        # The best, 95, is at 4 GB/s; the fast end, 100, at 16 GB/s. From the
        # fast end 1.1 x = 110 lies 0.6 of the way from 95 (4 GB/s) to 120
        # (2 GB/s), in log x; from the best 104.5 lies 0.38 of the way.
        ys = {"1GB/s": 200, "2GB/s": 120, "4GB/s": 95, "8GB/s": 100, "16GB/s": 100}
        rows = [{"bw": k, "t": v} for k, v in ys.items()]
        p, _ = self.plot(rows, "--x", "bw", "--y", "t")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("t: reference 100 at bw=16GB/s (the largest x); best 95 at bw=4GB/s", p.stdout)
        self.assertIn(f"x1.1 of it at bw = {4 * 2 ** -0.6:.4g}GB/s", p.stdout)
        self.assertIn("x2 of it at bw = 1GB/s", p.stdout)
        p, _ = self.plot(rows, "--x", "bw", "--y", "t", "--reference", "best")
        self.assertIn("t: reference 95 at bw=4GB/s (the best (lowest) value)", p.stdout)
        self.assertIn(f"x1.1 of it at bw = {4 * 2 ** -0.38:.4g}GB/s", p.stdout)
        p, _ = self.plot(rows, "--x", "bw", "--y", "t", "--reference", "8GB/s")
        self.assertIn("t: reference 100 at bw=8GB/s (x = 8GB/s)", p.stdout)
        self.assertIn(f"x1.1 of it at bw = {4 * 2 ** -0.6:.4g}GB/s", p.stdout)
        p, _ = self.plot(rows, "--x", "bw", "--y", "t", "--reference", "3GB/s")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("no point at x = 3GB/s: no knees", p.stdout)
        self.one_line(self.plot(rows, "--x", "bw", "--y", "t", "--reference", "fast")[0], "--reference fast")

    def test_nan_and_inf_are_no_points(self):
        # NaN first and inf next to the fast end: left out of the best and
        # the knees, and said; 1.1 x = 110 then lies between 105 (4 GB/s)
        # and 200 (1 GB/s).
        rows = [{"bw": "2GB/s", "t": "nan"}, {"bw": "1GB/s", "t": "200"}, {"bw": "4GB/s", "t": "105"},
                {"bw": "8GB/s", "t": "inf"}, {"bw": "16GB/s", "t": "100"}, {"bw": "32GB/s", "t": ""}]
        p, png = self.plot(rows, "--x", "bw", "--y", "t")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(png, b"\x89PNG\r\n\x1a\n")
        self.assertNotIn("nan at", p.stdout)
        self.assertIn("t: left out (not a finite number): bw=2GB/s (line 2: t nan); bw=8GB/s (line 5: t inf); "
                      "bw=32GB/s (line 7: t empty)", p.stdout)
        self.assertIn("t: reference 100 at bw=16GB/s (the largest x); best 100 at bw=16GB/s", p.stdout)
        t = (110 - 105) / (200 - 105)
        self.assertIn(f"x1.1 of it at bw = {4 * 4 ** -t:.4g}GB/s", p.stdout)
        # Every value NaN: one line, no chart.
        p, png = self.plot([{"bw": "1GB/s", "t": "nan"}], "--x", "bw", "--y", "t")
        self.one_line(p, "no finite value of t to draw")
        self.assertEqual(png, b"")

    def test_bad_input_gets_one_line(self):
        path = self.csv([{"bw": "1GB/s", "t": "1"}, {"bw": "2GB/s", "t": "2"}])
        with open(path, "a") as f:
            f.write("4GB/s\n")
        self.one_line(run(path, "--x", "bw", "--y", "t", "--out", os.path.join(self.d, "c.png")),
                      f"{path}:4: 1 fields, the header has 2")
        path = self.csv([{"bw": "1GB/s", "t": "1"}, {"bw": "2GB/s", "t": "two"}])
        self.one_line(run(path, "--x", "bw", "--y", "t", "--out", os.path.join(self.d, "c.png")),
                      f"{path}:3: column 't': 'two' is not a number")
        path = self.csv([{"bw": "1GB/s", "t": "1"}, {"bw": "fast", "t": "2"}])
        self.one_line(run(path, "--x", "bw", "--y", "t", "--out", os.path.join(self.d, "c.png")),
                      f"{path}:3: column 'bw' (--x): 'fast' is not a number or quantity")
        with open(path, "wb") as f:
            f.write(b"bw,t\n1GB/s,1\n2GB/s,\xff\n")
        self.one_line(run(path, "--x", "bw", "--y", "t", "--out", os.path.join(self.d, "c.png")),
                      f"{path}:3: bytes that are not UTF-8 text")
        path = self.csv([{"bw": "1GB/s", "t": "1", "g": "a"}])
        self.one_line(run(path, "--x", "bw", "--y", "t", "--where", "g=b", "--out", os.path.join(self.d, "c.png")),
                      "--where g=b: no row has it (g is one of: a)")
        self.one_line(run(os.path.join(self.d, "missing.csv"), "--x", "bw"), "missing.csv: No such file")
        self.one_line(run(self.d, "--x", "bw"), "a folder, not a file")
        p = run(path, "--x", "bw", "--y", "t", "--out", os.path.join(self.d, "no", "c.png"))
        self.one_line(p, "no folder")
        self.assertFalse(os.path.exists(os.path.join(self.d, "no")))
        self.one_line(run(path, "--x", "bw", "--y", "t", "--out", path), "the same file")
        self.assertTrue(open(path).read().startswith("bw,t,g"))  # the CSV untouched

    def test_chart_under_out_and_doc_only_with_doc(self):
        # A CSV in doc/results/: its chart goes to out/plots/, not beside it.
        src = os.path.join(ROOT, "doc", "results", "links_at_scale.csv")
        beside = os.path.join(ROOT, "doc", "results", "links_at_scale-link-bandwidth-render_time_ns.png")
        chart = os.path.join(ROOT, "out", "plots", "links_at_scale-link-bandwidth-render_time_ns.png")
        self.assertFalse(os.path.exists(beside))
        p = run(src, "--x", "link-bandwidth", "--group", "N")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn(f"chart -> {chart}", p.stdout)
        self.assertFalse(os.path.exists(beside))
        with open(chart, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        os.remove(chart)
        # --out in doc/ only with --doc (refused before drawing: nothing written).
        into_doc = os.path.join(ROOT, "doc", "results", "plot-sweep-test.png")
        self.one_line(run(src, "--x", "link-bandwidth", "--out", into_doc), "in doc/, which changes only with --doc")
        self.assertFalse(os.path.exists(into_doc))

    def test_rows_sharing_an_x_are_said(self):
        # Two meshes, no --group: one line through both zigzags; said, with the rows.
        rows = [{"mesh": m, "bw": bw, "t": t} for m, bw, t in
                (("2", "1GB/s", 200), ("2", "2GB/s", 100), ("4", "1GB/s", 120), ("4", "2GB/s", 60))]
        p, _ = self.plot(rows, "--x", "bw", "--y", "t")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("t: more than one row at 2 values of bw (at 1GB/s: lines 2, 4): --group or --where", p.stdout)
        p, _ = self.plot(rows, "--x", "bw", "--y", "t", "--group", "mesh")
        self.assertNotIn("more than one row", p.stdout)
        self.assertIn("mesh=4: reference 60 at bw=2GB/s", p.stdout)

    def test_columns_in_words_and_units(self):
        self.assertEqual(plot_sweep.x_axis("link-bandwidth", "100MB/s"), (1e-6, "link bandwidth (MB/s)"))
        self.assertEqual(plot_sweep.x_axis("link-latency", "2us"), (1e6, "link latency (us)"))
        self.assertEqual(plot_sweep.x_axis("bw", "1GB/s"), (1.0, "bw (B/s)"))  # unknown: as given, in SI
        self.assertEqual(plot_sweep.x_axis("mesh", "4"), (1.0, "nodes per side"))
        self.assertEqual(plot_sweep.y_axis(["render_time_ns", "time_none_ns"]), (1e-3, "us", "render time (us)"))
        self.assertEqual(plot_sweep.y_axis(["wall_s"]), (1.0, "s", "wall time (s)"))
        self.assertEqual(plot_sweep.y_axis(["speedup", "foo"])[2], "speed-up (one node's time / the mesh's), foo")
        self.assertEqual(plot_sweep.words("time_none_ns"), "without balancing")
        # Printed in the axis's unit: 20 us, not 20000 (ns).
        rows = [{"bw": "1GB/s", "render_time_ns": "40000", "time_none_ns": "50000"},
                {"bw": "2GB/s", "render_time_ns": "20000", "time_none_ns": "30000"}]
        p, _ = self.plot(rows, "--x", "bw", "--y", "render_time_ns,time_none_ns")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("render time: reference 20 us at bw=2GB/s", p.stdout)
        self.assertIn("without balancing: reference 30 us at bw=2GB/s", p.stdout)

    def test_each_lines_values_in_its_columns_unit(self):
        # Two y columns of two units: each line's reference and best in its
        # own (us for a time in ns, s for wall time), not raw; a column
        # named in ns that is not known, in us too.
        rows = [{"mesh": "1", "render_time_ns": "8553000", "wall_s": "0.0145", "queue_ns": "2500"},
                {"mesh": "2", "render_time_ns": "4000000", "wall_s": "0.02", "queue_ns": "1500"}]
        p, _ = self.plot(rows, "--x", "mesh", "--y", "render_time_ns,wall_s", "--reference", "min-x")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("render time: reference 8553 us at mesh=1 (the smallest x); best 4000 us at mesh=2", p.stdout)
        self.assertIn("wall time: reference 0.0145 s at mesh=1 (the smallest x); best 0.0145 s at mesh=1", p.stdout)
        p, _ = self.plot(rows, "--x", "mesh", "--y", "queue_ns")
        self.assertIn("queue_ns: reference 1.5 us at mesh=2", p.stdout)

    def test_argument_errors_in_one_line(self):
        path = self.csv([{"bw": "1GB/s", "t": "1"}])
        p = run(path)  # no --x
        self.assertEqual((p.returncode, p.stderr.count("\n")), (2, 1), p.stderr)
        self.assertIn("plot_sweep.py: error: the following arguments are required: --x", p.stderr)
        p = run(path, "--x", "bw", "--bogus")
        self.assertEqual((p.returncode, p.stderr.count("\n")), (2, 1), p.stderr)

    def test_text_is_drawn_as_written(self):
        # matplotlib reads $...$ as mathtext: an unclosed \frac in a title,
        # a column's name or a group's value was a ValueError. Drawn
        # literally, without a word on stderr (glyphs the font lacks too).
        rows = [{"b$w": "1GB/s", "t": "2", "g": "$\\frac{a"}, {"b$w": "2GB/s", "t": "1", "g": "$\\frac{a"}]
        p, png = self.plot(rows, "--x", "b$w", "--y", "t", "--group", "g",
                           "--title", "\u65e5\u672c $\\frac{a}{b " * 20 + "cost $5 and $x^2$")
        self.assertEqual((p.returncode, p.stderr), (0, ""))
        self.assertEqual(png, b"\x89PNG\r\n\x1a\n")
        self.assertEqual(plot_sweep.literal("$x^2$ costs $5"), r"\$x^2\$ costs \$5")

    def test_a_closed_or_full_stdout(self):
        # >&-: the chart is the result, drawn; its printout goes nowhere,
        # quietly. > /dev/full: one line, exit 1, the chart written.
        path = self.csv([{"bw": "1GB/s", "t": "2"}, {"bw": "2GB/s", "t": "1"}])
        out = os.path.join(self.d, "c.png")
        p = subprocess.run(["/usr/bin/python3", SCRIPT, path, "--x", "bw", "--y", "t", "--out", out],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                           timeout=120, preexec_fn=lambda: os.close(1))
        self.assertEqual((p.returncode, p.stderr), (0, ""))
        self.assertTrue(os.path.exists(out))
        os.remove(out)
        with open("/dev/full", "w") as full:
            p = subprocess.run(["/usr/bin/python3", SCRIPT, path, "--x", "bw", "--y", "t", "--out", out],
                               stdout=full, stderr=subprocess.PIPE, text=True, timeout=120)
        self.assertEqual((p.returncode, p.stderr), (1, "plot_sweep: stdout: No space left on device: the chart is "
                                                       "written, its printout is not\n"))
        self.assertTrue(os.path.exists(out))


if __name__ == "__main__":
    unittest.main()
