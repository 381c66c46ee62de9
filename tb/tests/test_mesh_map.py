"""scripts/mesh_map.py through rtsim --map: a PNG of the mesh for a run,
with the boundary panel below when balancing ran (a taller picture), the
same picture from the report written by --report, and a one-line error for
a file that is not a report. Usage: test_mesh_map.py RTSIM."""
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


if __name__ == "__main__":
    RTSIM = sys.argv.pop(1)
    unittest.main()
