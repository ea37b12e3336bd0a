#!/usr/bin/python3
"""Self-test of adapt_check.py (the checker of FEMorph Adapt's steps) before
any Adapt output exists: on a small case made by Data/generate_adapt_cases.py
(in a temporary folder) the checker must pass the mesh against itself (step
0), a step whose object alone moved rigidly by a small pose (by the motion
and by --pose), and fail each corrupted copy in the check that should catch
it: one tet inverted, one tet removed (a hole), one tet detached (a crack),
an object vertex off its rigid position, an outer boundary vertex moved off
the box, the object detached from space (non-conformal interface), the
wrong step number.

    /usr/bin/python3 Testing/Python/test_adapt_check.py [-v]

Exit 0 passed, 1 failed.
"""

import importlib.util
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
import adapt_check as ac  # noqa: E402

DATA = os.path.join(os.path.dirname(os.path.dirname(here)), "Data")


def load_generator():
    spec = importlib.util.spec_from_file_location(
        "generate_adapt_cases", os.path.join(DATA, "generate_adapt_cases.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


GEN = load_generator()
# A small case and a small motion: 0.02 edges along z, 0.5 degree about x.
CASE = GEN.build_case(cells=(5, 5, 6), obj=(2, 3, 1), seed=3)
INFO = CASE["info"]
MOTION = {"translation": (0.0, 0.0, 0.02), "axis": (1.0, 0.0, 0.0),
          "center": INFO["object"]["center"], "degrees": 0.5}


def base_mesh():
    return ac.Mesh(CASE["points"].copy(), CASE["tets"].copy(), CASE["material"].copy())


def moved_mesh(step=1):
    """The input with the object's vertices (only) at the pose of `step`."""
    m = base_mesh()
    R, t = ac.motion_pose(step, **MOTION)
    ids = np.unique(m.tets[m.material == 1])
    m.points[ids] = m.points[ids] @ R.T + t
    return m


def failed(rows):
    return {key for key, _, ok, _ in rows if not ok}


class AdaptCheckTest(unittest.TestCase):

    def run_check(self, mesh, step=0, **kwargs):
        R, t = ac.motion_pose(step, **MOTION)
        ok, rows, details = ac.check(base_mesh(), mesh, R, t, **kwargs)
        return ok, rows, details

    def assert_caught(self, mesh, keys, step=0):
        ok, rows, _ = self.run_check(mesh, step)
        self.assertFalse(ok)
        for key in keys:
            self.assertIn(key, failed(rows), f"check ({key}) did not fail: {rows}")

    # -- passes --------------------------------------------------------------

    def test_generated_case(self):
        m = base_mesh()
        self.assertEqual(len(m.tets), 12 * 5 * 5 * 6)
        self.assertTrue(np.all(ac.signed_volumes(m.points, m.tets) > 0))
        self.assertEqual(int(np.count_nonzero(m.material == 1)), 12 * 2 * 3)
        self.assertAlmostEqual(INFO["volume"], 150.0, places=9)
        # Jittered: not the grid any more, but the box and block planes kept.
        self.assertGreater(INFO["quality"]["grid_stretch_min"], INFO["quality"]["stretch_min"])

    def test_identity(self):
        ok, rows, d = self.run_check(base_mesh(), 0)
        self.assertTrue(ok, rows)
        self.assertEqual(d["vertex_drift_percent"], 0.0)
        self.assertTrue(d["boundary_is_box"])

    def test_rigid_step(self):
        m = moved_mesh(1)
        self.assertTrue(np.all(ac.signed_volumes(m.points, m.tets) > 0))
        ok, rows, _ = self.run_check(m, 1)
        self.assertTrue(ok, rows)
        ok, rows, _ = self.run_check(m, 1, object_remeshed=True)
        self.assertTrue(ok, rows)

    def test_pose_matrix(self):
        R, t = ac.motion_pose(1, **MOTION)
        m = np.eye(4)
        m[:3, :3], m[:3, 3] = R, t
        R2, t2 = ac.matrix_pose(m.ravel())
        ok, rows, _ = ac.check(base_mesh(), moved_mesh(1), R2, t2)
        self.assertTrue(ok, rows)
        bad = m.copy()
        bad[0, 1] += 0.1
        with self.assertRaises(ValueError):
            ac.matrix_pose(bad.ravel())

    # -- failures ------------------------------------------------------------

    def test_wrong_step(self):
        self.assert_caught(moved_mesh(1), ["c"], step=2)
        self.assert_caught(moved_mesh(1), ["c"], step=0)

    def test_inverted_tet(self):
        m = base_mesh()
        m.tets[7] = m.tets[7][[0, 2, 1, 3]]
        self.assert_caught(m, ["a", "b"])

    def test_removed_tet(self):
        m = base_mesh()
        inner = self.inner_space_tet(m)
        m.tets = np.delete(m.tets, inner, axis=0)
        m.material = np.delete(m.material, inner)
        m.cell_types = m.cell_types[1:]
        _, rows, d = self.run_check(m)
        self.assertIn("b", failed(rows))
        self.assertGreater(d["boundary_distance_max"], 0.1)

    def test_removed_boundary_tet(self):
        m = base_mesh()
        tris, slots = ac.boundary_of(m.tets, len(m.points))
        tet = int(slots[0] // 4)
        m.tets = np.delete(m.tets, tet, axis=0)
        m.material = np.delete(m.material, tet)
        m.cell_types = m.cell_types[1:]
        self.assert_caught(m, ["b"])

    def test_crack(self):
        # One space tet detached from its neighbours: its vertices duplicated.
        m = base_mesh()
        inner = self.inner_space_tet(m)
        n = len(m.points)
        m.points = np.vstack([m.points, m.points[m.tets[inner]]])
        m.tets[inner] = n + np.arange(4)
        m.cell_types = m.cell_types.copy()
        self.assert_caught(m, ["b"])

    def test_object_vertex_moved(self):
        m = moved_mesh(1)
        obj = np.unique(m.tets[m.material == 1])
        tris, _ = ac.boundary_of(m.tets[m.material == 1], len(m.points))
        inner = np.setdiff1d(obj, np.unique(tris))
        self.assertTrue(len(inner))
        m.points[inner[0]] += [0.0, 0.01, 0.0]          # inside the block still
        self.assert_caught(m, ["c"], step=1)
        m = moved_mesh(1)
        corner = np.unique(tris)[0]
        m.points[corner] += [1e-6, 0.0, 0.0]            # a block boundary vertex
        self.assert_caught(m, ["c"], step=1)

    def test_outer_boundary_vertex_moved(self):
        m = base_mesh()
        lo, hi = m.points.min(axis=0), m.points.max(axis=0)
        # A vertex on the face x = 0 only (not on an edge of the box).
        on_x0 = np.nonzero((m.points[:, 0] == lo[0]) & np.all(m.points[:, 1:] > lo[1:], axis=1)
                           & np.all(m.points[:, 1:] < hi[1:], axis=1))[0]
        v = on_x0[0]
        slid = base_mesh()
        slid.points[v] += [0.0, 1e-3, 0.0]               # within the face: allowed
        ok, rows, _ = self.run_check(slid)
        self.assertTrue(ok, rows)
        m.points[v] += [1e-3, 0.0, 0.0]                  # off the face, inwards
        self.assert_caught(m, ["b"])
        m = base_mesh()
        m.points[v] += [-1e-7, 0.0, 0.0]                 # outwards, slightly
        self.assert_caught(m, ["b"])

    def test_interface_detached(self):
        # The object's tets get copies of their vertices: object and space
        # no longer share faces.
        m = base_mesh()
        sel = m.material == 1
        ids = np.unique(m.tets[sel])
        new = np.full(len(m.points), -1)
        new[ids] = len(m.points) + np.arange(len(ids))
        m.points = np.vstack([m.points, m.points[ids]])
        m.tets[sel] = new[m.tets[sel]]
        self.assert_caught(m, ["b", "d"])

    def test_material_missing(self):
        m = base_mesh()
        m.material = None
        self.assert_caught(m, ["c", "d"])

    def test_drift_limit(self):
        m = base_mesh()
        m.points = np.vstack([m.points, [[1.0, 1.0, 1.0]]])   # one unused point
        ok, rows, d = self.run_check(m, max_drift=0.01)
        self.assertIn("e", failed(rows))
        self.assertIn("a", failed(rows))
        self.assertGreater(d["vertex_drift_percent"], 0.0)

    # -- the command line ----------------------------------------------------

    def test_command_line(self):
        with tempfile.TemporaryDirectory(prefix="adapt_check_") as tmp:
            inp = os.path.join(tmp, "case.vtu")
            GEN.generate(inp, "test", cells=(5, 5, 6), obj=(2, 3, 1), seed=3)
            m = moved_mesh(1)
            step = os.path.join(tmp, "step1.vtu")
            GEN.write_vtu(step, m.points, m.tets, m.material)
            script = os.path.join(here, "adapt_check.py")
            motion = ["--translation", "0", "0", "0.02", "--axis", "1", "0", "0",
                      "--center"] + [repr(c) for c in MOTION["center"]] + ["--angle", "0.5"]

            def run(*args):
                return subprocess.run([sys.executable, script, *args], capture_output=True,
                                      text=True)

            r = run(inp, inp, "--case", os.path.splitext(inp)[0] + ".json")
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            r = run(inp, step, "--step", "1", *motion)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            self.assertEqual(r.stdout.count("\n("), 5, r.stdout)
            R, t = ac.motion_pose(1, **MOTION)
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = R, t
            r = run(inp, step, "--pose", *[repr(float(x)) for x in pose.ravel()])
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            r = run(inp, step, "--step", "3", *motion)
            self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
            self.assertIn("(c) rigid object", r.stdout)
            self.assertIn("FAILED", r.stdout)

    # -- helpers -------------------------------------------------------------

    @staticmethod
    def inner_space_tet(m):
        """A space tet with no vertex on the box or the object."""
        tris, _ = ac.boundary_of(m.tets, len(m.points))
        otris, _ = ac.boundary_of(m.tets[m.material == 1], len(m.points))
        near = np.zeros(len(m.points), dtype=bool)
        near[np.unique(tris)] = True
        near[np.unique(otris)] = True
        cand = np.nonzero((m.material == 0) & ~near[m.tets].any(axis=1))[0]
        return int(cand[0])


if __name__ == "__main__":
    unittest.main()
