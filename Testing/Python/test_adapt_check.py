#!/usr/bin/python3
"""Self-test of adapt_check.py (the checker of FEMorph Adapt's steps) before
any Adapt output exists: on a small case made by Data/generate_adapt_cases.py
(in a temporary folder) the checker must pass the mesh against itself (step
0), a step whose object alone moved rigidly by a small pose (by the motion
and by --pose), and fail each corrupted copy in the check that should catch
it: one tet inverted, one tet removed (a hole), one tet detached (a crack),
an object vertex off its rigid position, an outer boundary vertex moved off
the box, the object detached from space (non-conformal interface), the
wrong step number. And the contact checks (thesis 3.7.3, (f)-(h)): two
objects sharing a face pass; touching along a face with a layer of
zero-volume space tets in between (a non-conformal contact), or with a face
in three tets, they fail; the committed 3.7.3 case
Data/adapt/cylinder_half_tube.vtu passes at step 0 (contact area 0).

    /usr/bin/python3 Testing/Python/test_adapt_check.py [-v]

Exit 0 passed, 1 failed.
"""

import importlib.util
import json
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


# -- contact (thesis 3.7.3) ---------------------------------------------------

CASE_373 = os.path.join(DATA, "adapt", "cylinder_half_tube.vtu")


def two_objects(layer):
    """Tet A (material 1) and tet B (material 2) on the two sides of the
    triangle p1 p2 p3. layer False: they share it (a conformal contact);
    True: B has its own copies q1 q2 q3 of the triangle's corners and three
    zero-volume space tets fill the flat prism between the two triangles
    (touching, not sharing: a non-conformal contact)."""
    p = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.3, 1.0],
                  [0.3, 0.2, -1.0]])
    a = [0, 1, 2, 3]                       # above z = 0 ... (p0 p1 p2) is the contact
    if not layer:
        b = [0, 2, 1, 4]
        tets, material = [a, b], [1, 2]
    else:
        p = np.vstack([p, p[:3]])          # q0 q1 q2 = 5 6 7
        b = [5, 7, 6, 4]
        flat = [[0, 1, 2, 5], [1, 2, 5, 6], [2, 5, 6, 7]]
        tets, material = [a, b] + flat, [1, 2, 0, 0, 0]
    m = ac.Mesh(p, np.array(tets), np.array(material))
    assert ac.signed_volumes(m.points, m.tets[:2]).min() > 0
    return m


class ContactCheckTest(unittest.TestCase):
    TRIANGLE = 0.5                          # area of (0,0,0) (1,0,0) (0,1,0)

    def test_conformal_contact_passes(self):
        m = two_objects(layer=False)
        faces, area = ac.contact_faces(m.points, m.tets, m.material, 1, 2)
        self.assertEqual(sorted(faces[0].tolist()), [0, 1, 2])
        self.assertAlmostEqual(area, self.TRIANGLE, places=15)
        ok, rows, d = ac.check_contact(m, 1, 2, self.TRIANGLE)
        self.assertTrue(ok, rows)
        self.assertEqual(d["contact_faces"], 1)
        # The area check fails 2 % off, passes 0.5 % off.
        self.assertFalse(ac.check_contact_area(area, 1.02 * self.TRIANGLE)[0])
        self.assertTrue(ac.check_contact_area(area, 1.005 * self.TRIANGLE)[0])
        self.assertFalse(ac.check_contact_area(area, 0.0)[0])

    def test_nonconformal_contact_fails(self):
        m = two_objects(layer=True)
        self.assertTrue(np.all(np.abs(ac.signed_volumes(m.points, m.tets[2:])) == 0))
        faces, area = ac.contact_faces(m.points, m.tets, m.material, 1, 2)
        self.assertEqual(len(faces), 0)
        ok, rows, d = ac.check_contact(m, 1, 2, self.TRIANGLE)
        self.assertFalse(ok)
        self.assertEqual(failed(rows), {"f", "g", "h"}, rows)
        self.assertEqual(d["coincident_not_shared"], 1)
        self.assertEqual(d["degenerate_ratio_min"], 0.0)
        self.assertEqual(d["degenerate_tets"], 3)
        self.assertEqual(d["contact_area"], 0.0)

    def test_face_in_three_tets_fails(self):
        m = two_objects(layer=False)
        m.points = np.vstack([m.points, [[0.1, 0.1, -2.0]]])
        m.tets = np.vstack([m.tets, [0, 2, 1, 5]])       # a second B tet on the contact face
        m.material = np.append(m.material, 2)
        ok, text, d = ac.check_contact_conformity(m.points, m.tets, m.material)
        self.assertFalse(ok, text)
        self.assertEqual(d["faces_in_more_than_two"], 1)
        self.assertEqual(d["object_faces_not_one_each"], 1)

    def test_inverted_tet_is_degenerate(self):
        m = two_objects(layer=False)
        m.tets[1] = m.tets[1][[1, 0, 2, 3]]
        ok, text, d = ac.check_degenerate(m.points, m.tets)
        self.assertFalse(ok, text)
        self.assertLess(d["degenerate_ratio_min"], 0)
        self.assertEqual(d["degenerate_worst_tet"], 1)

    def test_cylinder_half_tube_step_0(self):
        if not os.path.exists(CASE_373):
            self.skipTest(f"{CASE_373} not found")
        with open(os.path.splitext(CASE_373)[0] + ".json") as f:
            info = json.load(f)
        m = ac.read_mesh(CASE_373)
        self.assertEqual(sorted(np.unique(m.material).tolist()), [0, 1, 2])
        self.assertEqual(info["contact_materials"], [1, 2])
        self.assertEqual(info["contact_area"]["discrete"][0], 0.0)
        # Both objects' volumes are the polygon prisms of the .json.
        vol = ac.signed_volumes(m.points, m.tets)
        for key, mat in (("cylinder", 1), ("half_tube", 2)):
            self.assertAlmostEqual(vol[m.material == mat].sum() / info[key]["volume"], 1.0, places=9)
        # No shared vertex between the objects at step 0, no contact face.
        shared = np.intersect1d(m.tets[m.material == 1], m.tets[m.material == 2])
        self.assertEqual(len(shared), 0)
        ok, rows, d = ac.check_contact(m, 1, 2, info["contact_area"]["discrete"][0])
        self.assertTrue(ok, rows)
        self.assertEqual(d["contact_faces"], 0)
        self.assertGreater(d["degenerate_ratio_min"], ac.DEGENERATE_FLOOR)
        # The full step check against itself, and a wrong expected area
        # (step 3's) caught.
        ok, rows, _ = ac.check(m, m, moving_id=1)
        self.assertTrue(ok, rows)
        ok, rows, _ = ac.check_contact(m, 1, 2, info["contact_area"]["discrete"][3])
        self.assertEqual(failed(rows), {"h"}, rows)
        # The command line reads the contact from the .json.
        script = os.path.join(here, "adapt_check.py")
        r = subprocess.run([sys.executable, script, CASE_373, CASE_373, "--case",
                            os.path.splitext(CASE_373)[0] + ".json"], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("(h) contact area", r.stdout)
        r = subprocess.run([sys.executable, script, CASE_373, CASE_373, "--contact", "1", "2",
                            "--contact-area", "1.0"], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)


if __name__ == "__main__":
    unittest.main()
