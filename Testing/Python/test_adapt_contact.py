"""FEMorph Adapt with contact through paraview.simple (thesis 3.7.3): the
cylinder of Data/adapt/cylinder_half_tube.vtu (MaterialId 1) slides 1/4 per
step into the half tube of its radius (MaterialId 2).

Run with pvpython, the package femorph on PYTHONPATH:
  PYTHONPATH=build/lib/python3.11/dist-packages pvpython test_adapt_contact.py \
      --plugin FEMorph.so --data Data

Steps 1..16 (translation s = 0.25 n; the front cap goes from z = -0.5 to
3.5, the tube spans z in [0, 4]) are updated in order and each output is
checked by adapt_check.py (numpy, no FEMorph code): (a) positive tets, (b)
conformity and the outer boundary unchanged, (d) the object's interface,
the cylinder's boundary vertices mapped back by the inverse pose on its
initial surface (radius r up to the polygon's chord sag, or a cap plane),
(f) contact faces in exactly one tet of each object, (g) no degenerate tet,
(h) the contact area within 1 % of the discrete one for s. The Steps table
(output 1) has one row per step, its ContactFaces the faces shared by the
two objects. Step 5 asked again after step 16 comes from the cache (no step
computed) and equals the first computation.
"""
import argparse
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from paraview.simple import *  # noqa: F401,F403
from vtkmodules.util.numpy_support import vtk_to_numpy

import numpy as np

import adapt_check

STEP = 0.25
STEPS = 16
SCRUB = 5


def expected_area(case, s):
    """3.7.3's discrete contact area at translation s: the half polygon's
    n_theta / 2 chords of 2 r sin(pi / n_theta) times the overlap of the
    cylinder's z span (moved by s) with the tube's (Data/README.md)."""
    lo, hi = case["cylinder"]["z"]
    t_lo, t_hi = case["half_tube"]["z"]
    overlap = max(0.0, min(hi + s, t_hi) - max(lo + s, t_lo))
    n_half = case["n_theta"] // 2
    return n_half * 2 * case["r"] * math.sin(math.pi / (2 * n_half)) * overlap


def check_cylinder_surface(case, mesh, moving, t):
    """The moving object's boundary vertices mapped back by the inverse pose
    (a translation t) lie on its initial surface: the side (radius in
    [r - sag, r], sag the chord sag of the n_theta-gon) within its z span,
    or a cap plane within radius r. Returns (ok, text)."""
    tol = 1e-9 * float(np.linalg.norm(mesh.points.max(axis=0) - mesh.points.min(axis=0)))
    tris, _ = adapt_check.boundary_of(mesh.tets[mesh.material == moving], len(mesh.points))
    x = mesh.points[np.unique(tris)] - np.asarray(t)
    r = case["r"]
    sag = r * (1 - math.cos(math.pi / case["n_theta"]))
    lo, hi = case["cylinder"]["z"]
    rho = np.hypot(x[:, 0], x[:, 1])
    side = (rho <= r + tol) & (rho >= r - sag - tol) & (x[:, 2] >= lo - tol) & (x[:, 2] <= hi + tol)
    cap = ((np.abs(x[:, 2] - lo) <= tol) | (np.abs(x[:, 2] - hi) <= tol)) & (rho <= r + tol)
    off = int(np.count_nonzero(~(side | cap)))
    return off == 0, "%d of %d cylinder boundary vertices off its initial surface" % (off, len(x))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--data", required=True, help="FEMorph's Data folder")
    args = parser.parse_args()
    LoadPlugin(args.plugin, ns=globals())
    name = os.path.join(args.data, "adapt", "cylinder_half_tube")
    with open(name + ".json") as f:
        case = json.load(f)
    moving, other = case["contact_materials"]
    assert moving == case["object"]["material_id"] == 1
    # The area formula against the .json's own (1 per step).
    for n, a in enumerate(case["contact_area"]["discrete"]):
        assert abs(expected_area(case, float(n)) - a) <= 1e-12 * max(a, 1), (n, a)

    reader = XMLUnstructuredGridReader(FileName=[name + ".vtu"])
    adapt = FEMorphAdapt(Input=reader, MovingObject=moving, TranslationPerStep=[0, 0, STEP],
                         NumberOfSteps=STEPS)
    adapt.UpdatePipelineInformation()
    assert list(adapt.TimestepValues) == [float(n) for n in range(STEPS + 1)], list(adapt.TimestepValues)
    import femorph  # noqa: F401  (the filter's own methods: GetComputedSteps)
    algorithm = adapt.GetClientSideObject()
    inp = adapt_check.read_mesh(name + ".vtu")

    counts = [0]          # ContactFaces per step, from the checker
    kept = None           # step SCRUB's mesh
    failures = []
    for n in range(1, STEPS + 1):
        adapt.UpdatePipeline(float(n))
        grid = algorithm.GetOutputDataObject(0)
        table = algorithm.GetOutputDataObject(1)
        assert grid.GetNumberOfCells() > 0, "step %d: empty output" % n
        mesh = adapt_check.mesh_from_grid(grid, "step %d" % n)
        R, t = adapt_check.motion_pose(n, (0, 0, STEP))
        ok, rows, _ = adapt_check.check(inp, mesh, R, t, moving)
        # (c) asks for the input's object mesh; the contact re-meshes the
        # cylinder's side (3.5.4), checked against its analytic surface.
        rows = [row for row in rows if row[0] != "c"]
        ok_s, text = check_cylinder_surface(case, mesh, moving, t)
        rows.append(("c'", "cylinder on its surface", ok_s, text))
        area = expected_area(case, STEP * n)
        ok_c, rows_c, d = adapt_check.check_contact(mesh, moving, other, area)
        rows += rows_c
        faces, _ = adapt_check.contact_faces(mesh.points, mesh.tets, mesh.material, moving, other)
        counts.append(len(faces))
        if area > 0 and not len(faces):
            rows.append(("h'", "contact faces", False, "no contact face where the area is %g" % area))

        # The Steps table: rows 0..n, ContactFaces as counted here.
        column = table.GetColumnByName("ContactFaces")
        steps = table.GetColumnByName("Step")
        if column is None or steps is None:
            rows.append(("t", "steps table", False, "no Step or ContactFaces column"))
        else:
            got_steps = vtk_to_numpy(steps).tolist()
            got = vtk_to_numpy(column).tolist()
            ok_t = table.GetNumberOfRows() == n + 1 and got_steps == list(range(n + 1)) and got == counts
            rows.append(("t", "steps table", ok_t, "Step %s, ContactFaces %s (checker %s)"
                         % (got_steps[-3:], got[-3:], counts[-3:])))
        if not all(row[2] for row in rows):
            print("step %d (s = %g):" % (n, STEP * n))
            adapt_check.print_rows(rows)
            failures.append(n)
        print("step %d: s %.2f, %d tets, %d contact faces, area %.5f of %.5f"
              % (n, STEP * n, len(mesh.tets), len(faces), d["contact_area"], area))
        if n == SCRUB:
            kept = mesh
    assert not failures, "steps failing the checks: %s" % failures
    assert algorithm.GetComputedSteps() == STEPS, algorithm.GetComputedSteps()

    # Back to step SCRUB: from the cache, the same mesh and table.
    adapt.UpdatePipeline(float(SCRUB))
    again = adapt_check.mesh_from_grid(algorithm.GetOutputDataObject(0))
    assert algorithm.GetComputedSteps() == STEPS, "step %d recomputed" % SCRUB
    assert np.array_equal(again.points, kept.points), "step %d: other points" % SCRUB
    assert np.array_equal(again.tets, kept.tets), "step %d: other tets" % SCRUB
    assert np.array_equal(again.material, kept.material), "step %d: other materials" % SCRUB
    table = algorithm.GetOutputDataObject(1)
    assert table.GetNumberOfRows() == SCRUB + 1, table.GetNumberOfRows()
    assert vtk_to_numpy(table.GetColumnByName("ContactFaces")).tolist() == counts[:SCRUB + 1]
    print("OK: FEMorph Adapt with contact, %d steps, contact faces %s" % (STEPS, counts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
