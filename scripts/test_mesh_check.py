#!/usr/bin/env python3
"""Tests of scripts/mesh_check.py (python3 -m unittest scripts/test_mesh_check.py)."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mesh_check  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))

# A tetrahedron wound outward.
TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TET_T = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def write_obj(path, v, t):
    with open(path, "w") as f:
        for p in v:
            f.write(f"v {float(p[0])!r} {float(p[1])!r} {float(p[2])!r}\n")
        for tri in t:
            f.write(f"f {tri[0] + 1} {tri[1] + 1} {tri[2] + 1}\n")


class Topology(unittest.TestCase):
    def test_closed_tetrahedron(self):
        r = mesh_check.topology(TET_V, TET_T)
        self.assertTrue(r["watertight"] and r["manifold"])
        self.assertEqual((r["euler"], r["components"], r["degenerate"]), (2, 1, 0))
        self.assertEqual(mesh_check.self_intersections(TET_V, TET_T), 0)

    def test_hole_and_flip(self):
        r = mesh_check.topology(TET_V, TET_T[:3])
        self.assertEqual(r["boundary_edges"], 3)
        self.assertFalse(r["watertight"])
        flipped = TET_T.copy()
        flipped[3] = flipped[3][::-1]
        r = mesh_check.topology(TET_V, flipped)
        self.assertEqual(r["misoriented_edges"], 3)
        self.assertFalse(r["manifold"])

    def test_pinched_vertex(self):
        # Two tetrahedra sharing only vertex 0: watertight, not vertex-manifold.
        v = np.vstack([TET_V, -TET_V[1:]])
        t2 = np.where(TET_T == 0, 0, TET_T + 3)[:, ::-1]
        r = mesh_check.topology(v, np.vstack([TET_T, t2]))
        self.assertTrue(r["watertight"])
        self.assertEqual(r["non_manifold_vertices"], 1)
        self.assertFalse(r["manifold"])
        self.assertEqual(r["components"], 1)

    def test_non_manifold_edge(self):
        # Three triangles on one edge.
        v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], float)
        r = mesh_check.topology(v, np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]]))
        self.assertEqual(r["non_manifold_edges"], 1)


class SelfIntersections(unittest.TestCase):
    def test_crossing_pair_and_shared_vertex(self):
        v = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0],        # in z = 0
                      [0, 0, -1], [0.2, 0, 1], [0, 0.3, 1],      # pierces it
                      [5, 5, 5], [6, 5, 5], [5, 6, 5]], float)   # far away
        t = np.array([[0, 1, 2], [3, 4, 5], [6, 7, 8]])
        self.assertEqual(mesh_check.self_intersections(v, t), 1)
        # Sharing vertex 0 and folding through the first triangle: counted.
        v2 = np.vstack([v, [[0.5, 0.5, -1], [0.5, 0.5, 1]]])
        t2 = np.array([[0, 1, 2], [0, 9, 10]])
        self.assertEqual(mesh_check.self_intersections(v2, t2), 1)
        # Coplanar and overlapping, sharing vertex 0: not counted (rounding decides
        # the signs there, as on a flat face of a mesh).
        v4 = np.array([[-0.05520982, 0.7007874, 0.1924], [-0.03943304, 0.68503937, 0.19623548],
                       [-0.05520982, 0.68503937, 0.1924]], float)
        v4 = np.vstack([v4, v4[0] + 0.8 * (v4[1] - v4[0]) + 0.5 * (v4[2] - v4[0])])
        self.assertEqual(mesh_check.self_intersections(v4, np.array([[0, 1, 2], [0, 3, 2]])), 0)
        # Sharing an edge, or a vertex only: not counted.
        t3 = np.array([[0, 1, 2], [0, 1, 3], [2, 6, 7]])
        self.assertEqual(mesh_check.self_intersections(v, t3), 0)


class Files(unittest.TestCase):
    def run_check(self, *args):
        return subprocess.run([sys.executable, os.path.join(HERE, "mesh_check.py"), *args],
                              capture_output=True, text=True)

    def test_obj_and_distance(self):
        with tempfile.TemporaryDirectory() as d:
            # A unit sphere's octahedron: vertices on the sphere, distance 0.
            v = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
            t = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4],
                          [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
            write_obj(f"{d}/o.obj", v, t)
            with open(f"{d}/s.vm", "w") as f:
                f.write("# sphere of radius 0.5\n_x var-x\n_y var-y\n_z var-z\n_a square _x\n"
                        "_b square _y\n_c square _z\n_s add _a _b\n_t add _s _c\n"
                        "_r sqrt _t\n_h const 0.5\n_f sub _r _h\n")
            r = self.run_check(f"{d}/o.obj", "--vm", f"{d}/s.vm", "--cell", "0.25")
            self.assertEqual(r.returncode, 0, r.stderr)
            j = json.loads(r.stdout)
            self.assertTrue(j["manifold"])
            self.assertEqual((j["triangles"], j["euler"], j["self_intersections"]), (8, 2, 0))
            self.assertAlmostEqual(j["max_distance"], 0.5, places=5)
            self.assertAlmostEqual(j["max_distance_cells"], 2.0, places=4)
            # Clipped to x <= 0.9: the vertex at x = 1 is 0.1 outside the box.
            r = self.run_check(f"{d}/o.obj", "--vm", f"{d}/s.vm", "--clip=-2,-2,-2,0.9,2,2")
            self.assertAlmostEqual(json.loads(r.stdout)["max_distance"], 0.5, places=5)

    def test_exact_sample_agrees(self):
        v = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0], [0, 0, -1], [0.2, 0, 1],
                      [0, 0.3, 1], [0.5, 0.5, -1], [0.5, 0.5, 1], [5, 5, 5]], float)
        t = np.array([[0, 1, 2], [3, 4, 5], [0, 6, 7], [6, 7, 8]])
        with tempfile.TemporaryDirectory() as d:
            write_obj(f"{d}/x.obj", v, t)
            r = subprocess.run([sys.executable, os.path.join(HERE, "mesh_check_exact.py"),
                                f"{d}/x.obj"], capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            # [3, 4, 5] also pierces [0, 6, 7] (plane x = y) near (0.06, 0.06, 0).
            self.assertIn("2 crossing pairs sharing no vertex", r.stdout)
            self.assertIn("1 crossing pairs sharing one vertex", r.stdout)

    def test_bad_input_is_one_line(self):
        with tempfile.TemporaryDirectory() as d:
            with open(f"{d}/m.obj", "w") as f:
                f.write("v 0 0 0\nf 1 2 3\n")
            for args in ([f"{d}/m.obj"], [f"{d}/none.ply"], [f"{d}/m.off"],
                         [f"{d}/m.obj", "--clip", "1,2"]):
                r = self.run_check(*args)
                self.assertEqual(r.returncode, 2, args)
                self.assertIn("error", r.stderr.strip().splitlines()[-1], args)
                self.assertNotIn("Traceback", r.stderr, args)


if __name__ == "__main__":
    unittest.main()
