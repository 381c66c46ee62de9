"""scripts/mesh_map.py through rtsim --map: a PNG of the mesh for a run,
with the boundary panel below when balancing ran (a taller picture), the
same picture from the report written by --report (byte for byte, again
and again), one colour bar (loads only, scaled to the busiest) and the
busiest node ringed and named, also at 32 per axis, and a one-line error
for a file that is not a report, bad JSON (with its line), a field the
picture needs gone wrong (named: a load or busy time 'abc' or NaN too) or
a bad flag; -o under doc/ only with --doc, which rtsim --map passes. Usage: test_mesh_map.py RTSIM."""
import json
import os
import struct
import subprocess
import sys
import tempfile
import unittest

RTSIM = None
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SMALL = ["--spheres", "200", "--radius", "0.04", "--size", "32x32", "--mesh", "3", "--no-baseline", "-q", "--image", ""]


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    return struct.unpack(">II", head[16:24])


sys.path.insert(0, os.path.join(ROOT, "scripts"))
import mesh_map  # noqa: E402


MESH_MAP = os.path.join(ROOT, "scripts", "mesh_map.py")


def synthetic(n, busiest, saturated=()):
    """A report of an n x n x n mesh: loads 0.001 * (x + y + z) / n, the
    busiest node at 0.3; every +x link 10 % utilised, the `saturated` ones
    backlogged for half the frame."""
    nodes = [{"node": [x, y, z], "load": 0.3 if [x, y, z] == busiest else 0.001 * (x + y + z) / n}
             for x in range(n) for y in range(n) for z in range(n)]
    links = [{"from": c["node"], "to": "+x", "utilisation": 0.1,
              "saturated_ns": 500.0 if c["node"] in saturated else 0.0} for c in nodes if c["node"][0] < n - 1]
    return {"config": {"mesh": [n, n, n], "balance": {"axis": "x", "policy": "none"}}, "render_time_ns": 1000.0,
            "nodes": nodes, "links": links, "busiest_links": []}


class MeshMap(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name

    def tearDown(self):
        self.dir.cleanup()

    def run_rtsim(self, *args):
        p = subprocess.run([RTSIM, *SMALL, *args], capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)

    def test_a_long_mesh_shows_its_busiest_layers(self):
        # 12 layers along x: the 8 whose busiest node is busiest, in order.
        nodes = [{"node": [k, 0, 0], "load": load} for k, load in
                 enumerate([0.1, 0.9, 0.2, 0.8, 0.3, 0.7, 0.05, 0.6, 0.5, 0.4, 0.01, 0.02])]
        # (by hand: loads 0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2 are layers 1, 3, 5, 7, 8, 9, 4, 2)
        self.assertEqual(mesh_map.chosen_layers({"nodes": nodes}, 0, 12, None), [1, 2, 3, 4, 5, 7, 8, 9])
        self.assertEqual(mesh_map.chosen_layers({"nodes": nodes}, 0, 12, "3:5"), [3, 4, 5])
        self.assertEqual(mesh_map.chosen_layers({"nodes": nodes[:4]}, 0, 4, None), [0, 1, 2, 3])
        # A real run 32 long on the balancing axis and 16 wide: drawn, and a layer range outside it refused.
        report, out = os.path.join(self.d, "long.json"), os.path.join(self.d, "long.png")
        p = subprocess.run([RTSIM, "--spheres", "100", "--size", "16x16", "--mesh-dims", "32x16x2", "--no-baseline",
                            "-q", "--image", "", "--report", report, "--map", out], capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertGreater(png_size(out)[0], 0)
        p = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "mesh_map.py"), report, "-o", out,
                            "--layers", "30:40"], capture_output=True, text=True)
        self.assertNotEqual(p.returncode, 0)
        self.assertEqual(p.stderr.strip(), "mesh_map: --layers 30:40: the mesh has layers 0..31")

    def test_map_of_a_run_with_and_without_balancing(self):
        plain, balanced = os.path.join(self.d, "plain.png"), os.path.join(self.d, "balanced.png")
        self.run_rtsim("--map", plain)
        self.run_rtsim("--balance", "slide", "--map", balanced, "--report", os.path.join(self.d, "b.json"))
        w0, h0 = png_size(plain)
        w1, h1 = png_size(balanced)
        self.assertGreater(w0, 300)
        self.assertGreater(h1, h0)  # the boundaries' panel
        # The script on the report gives the same picture.
        again = os.path.join(self.d, "again.png")
        p = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "mesh_map.py"),
                            os.path.join(self.d, "b.json"), "-o", again], capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(png_size(again), (w1, h1))

    def test_one_colour_bar_and_the_busiest_ringed(self):
        # At 32 per axis (the dense drawing) and at 3: one colour bar, the
        # loads', ending at a round value at or above the busiest load;
        # the busiest node's name on its layer.
        for n, busiest in ((32, [5, 7, 30]), (3, [1, 2, 0])):
            with self.subTest(n=n):
                r = synthetic(n, busiest, saturated=[[0, 0, 0]])
                fig = mesh_map.figure(r)
                bars = [a for a in fig.axes if a.get_label() == "<colorbar>"]
                self.assertEqual(len(bars), 1)
                self.assertIn("node load", bars[0].get_ylabel())
                self.assertEqual(bars[0].get_ylim(), (0.0, 0.5))
                named = [t.get_text() for a in fig.axes for t in a.texts if t.get_text().startswith("busiest")]
                self.assertEqual(named, ["busiest: node_" + "_".join(map(str, busiest))])
                self.assertIn(f"busiest node node_{'_'.join(map(str, busiest))}, load 0.30 (ringed)",
                              fig._suptitle.get_text())
        self.assertEqual([mesh_map.load_top(x) for x in (0.075, 0.3, 0.99, 0.0001, 1.2)], [0.1, 0.5, 1.0, 0.0001, 1.2])

    def test_the_same_report_the_same_bytes(self):
        r = synthetic(3, [1, 1, 1], saturated=[[0, 1, 1]])
        for fmt in ("png", "svg"):
            outs = [os.path.join(self.d, f"m{i}.{fmt}") for i in range(2)]
            for when, out in zip(("0", "1000000000"), outs):  # a date in the file would differ
                os.environ["SOURCE_DATE_EPOCH"] = when
                mesh_map.draw(r, out, fmt)
            del os.environ["SOURCE_DATE_EPOCH"]
            with open(outs[0], "rb") as a, open(outs[1], "rb") as b:
                self.assertEqual(a.read(), b.read(), fmt)

    def test_bad_reports_get_one_line(self):
        good = json.dumps(synthetic(2, [0, 0, 0]), indent=1)
        nodes = synthetic(2, [0, 0, 0])
        nodes["nodes"][1]["load"] = "x"
        fewer = synthetic(2, [0, 0, 0])

        def busy(value):  # nodes[1]'s busy time (the load's source) damaged
            r = synthetic(2, [0, 0, 0])
            r["nodes"][1]["busy_ns"] = value
            return r
        del fewer["nodes"][3]
        cases = {  # name: (text, what stderr says after the path)
            "cut": (good[:len(good) // 2], f":{good[:len(good) // 2].count(chr(10)) + 1}: not JSON"),
            "bytes": (good.replace('"none"', '"n\udcffne"'), f":{good[:good.index('none')].count(chr(10)) + 1}: "
                                                              "bytes that are not UTF-8"),
            "load": (json.dumps(nodes), ": nodes[1].load: 'x' is not a finite number"),
            "fewer": (json.dumps(fewer), ": nodes: 7 of them; the 2x2x2 mesh has 8"),
            "list": ("[1, 2]", ": the top: not a JSON object"),
            "axis": (good.replace('"axis": "x"', '"axis": "w"'), ": config.balance.axis: 'w' is not x, y or z"),
            "busy": (json.dumps(busy("abc")), ": nodes[1].busy_ns: 'abc' is not a finite number"),
            "busy-nan": (json.dumps(busy(float("nan"))), ": nodes[1].busy_ns: 'nan' is not a finite number"),
            "busy-below-0": (json.dumps(busy(-5)), ": nodes[1].busy_ns: -5 is below 0"),
            "load-nan": (json.dumps(nodes).replace('"load": "x"', '"load": NaN'),
                         ": nodes[1].load: 'nan' is not a finite number"),
            # (Not lists, they were an internal error, exit 1.)
            "boundaries": (json.dumps(dict(synthetic(2, [0, 0, 0]), boundaries=5)), ": boundaries: '5' is not a list"),
            "busiest": (json.dumps(dict(synthetic(2, [0, 0, 0]), busiest_links={"a": 1})),
                        ": busiest_links: \"{'a': 1}\" is not a list"),
        }
        for name, (text, said) in cases.items():
            with self.subTest(case=name):
                path, out = os.path.join(self.d, name + ".json"), os.path.join(self.d, name + ".png")
                with open(path, "w", errors="surrogateescape") as f:
                    f.write(text)
                p = subprocess.run(["/usr/bin/python3", MESH_MAP, path, "-o", out], capture_output=True, text=True)
                self.assertEqual(p.returncode, 2, p.stderr)
                self.assertEqual(p.stderr, f"mesh_map: {path}{said}" + p.stderr[len(f"mesh_map: {path}{said}"):])
                self.assertEqual(p.stderr.count("\n"), 1, p.stderr)
                self.assertFalse(os.path.exists(out))
        p = subprocess.run(["/usr/bin/python3", MESH_MAP, path, "-o", os.path.join(self.d, "no", "m.png")],
                           capture_output=True, text=True)
        self.assertEqual(p.returncode, 2)
        self.assertIn("no folder", p.stderr)

    def test_not_a_report(self):
        bad = os.path.join(self.d, "bad.json")
        with open(bad, "w") as f:
            f.write('{"nodes": []}')
        p = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "mesh_map.py"), bad, "-o",
                            os.path.join(self.d, "x.png")], capture_output=True, text=True)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("not an rtsim report", p.stderr)
        self.assertEqual(p.stderr.count("\n"), 1, p.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.d, "x.png")))

    def test_doc_only_with_doc_and_rtsim_passes_it(self):
        # mesh_map.py -o under doc/ without --doc: refused, nothing written
        # (the test writes nothing into doc/ itself).
        report = os.path.join(self.d, "r.json")
        with open(report, "w") as f:
            json.dump(synthetic(2, [0, 0, 0]), f)
        into_doc = os.path.join(ROOT, "doc", "images", "mesh-map-test.png")
        self.addCleanup(lambda: os.path.exists(into_doc) and os.remove(into_doc))  # written only by the bug
        p = subprocess.run(["/usr/bin/python3", MESH_MAP, report, "-o", into_doc], capture_output=True, text=True)
        self.assertEqual((p.returncode, p.stderr),
                         (2, f"mesh_map: -o {into_doc}: in doc/, which changes only with --doc\n"))
        self.assertFalse(os.path.exists(into_doc))
        # rtsim --map passes --doc with the temporary beside the path its
        # user named (rtsim --map doc/images/MAP.png is a choice): the
        # script's arguments, recorded by a sitecustomize of the test's.
        site, args = os.path.join(self.d, "site"), os.path.join(self.d, "args.txt")
        os.mkdir(site)
        with open(os.path.join(site, "sitecustomize.py"), "w") as f:
            f.write("import os, sys\nif sys.argv and sys.argv[0].endswith('mesh_map.py'):\n"
                    "    open(os.environ['MAP_ARGS'], 'w').write('\\n'.join(sys.argv[1:]))\n")
        out = os.path.join(self.d, "m.png")
        p = subprocess.run([RTSIM, *SMALL, "--map", out], capture_output=True, text=True,
                           env=dict(os.environ, PYTHONPATH=site, MAP_ARGS=args))
        self.assertEqual(p.returncode, 0, p.stderr)
        with open(args) as f:
            passed = f.read().split("\n")
        self.assertEqual(passed[1:3], ["-o", passed[2]])
        self.assertTrue(passed[2].startswith(out + ".incomplete-"), passed)
        self.assertIn("--doc", passed)

    def test_argument_errors_in_one_line_and_a_closed_stdout(self):
        p = subprocess.run(["/usr/bin/python3", MESH_MAP, "r.json"], capture_output=True, text=True)
        self.assertEqual((p.returncode, p.stderr),
                         (2, "mesh_map.py: error: the following arguments are required: -o/--out\n"))
        # >&-: it prints nothing, so a closed stdout is no matter.
        report, out = os.path.join(self.d, "r.json"), os.path.join(self.d, "m.png")
        with open(report, "w") as f:
            json.dump(synthetic(2, [0, 0, 0]), f)
        p = subprocess.run(["/usr/bin/python3", MESH_MAP, report, "-o", out], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True, preexec_fn=lambda: os.close(1))
        self.assertEqual((p.returncode, p.stderr), (0, ""))
        self.assertTrue(os.path.exists(out))

if __name__ == "__main__":
    RTSIM = sys.argv.pop(1)
    unittest.main()
