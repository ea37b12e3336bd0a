"""FEMorph Adapt's assembly mode through paraview.simple (thesis 3.7.4):
Data/adapt/assembly_crank.vtu holds no space cell, a crank (MaterialId 1)
and a bearing (MaterialId 2) meshed separately (non-conforming); the crank
turns 10 degrees per step about its axis z, 36 steps.

Run with pvpython, the package femorph on PYTHONPATH:
  PYTHONPATH=build/lib/python3.11/dist-packages pvpython test_adapt_assembly.py \
      --plugin FEMorph.so --data Data

Each step is checked by adapt_check.py (numpy, no FEMorph code): (f) the
faces of a crank tet and a bearing tet in exactly one tet of each, (g) no
degenerate tet, (h) their area within 1 % of the bore's polygon's (the
.json's contact_area.discrete); and here: no crank boundary face whose
centroid lies on the bearing's boundary (within 0.05 edge: a contact
left non-conforming), each part's volume (the bearing's to 1e-9, the
crank's to 1 %), and the Steps table's ContactFaces as counted here. The
input itself fails the last check (its contact is not conformal).
"""
import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from paraview.simple import *  # noqa: F401,F403
from vtkmodules.util.numpy_support import vtk_to_numpy

import numpy as np

import adapt_check

STEPS = 36


def volume(mesh, m):
    x = mesh.points[mesh.tets[mesh.material == m]]
    return float(np.einsum("ij,ij->i", x[:, 1] - x[:, 0],
                           np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0])).sum() / 6.0)


def coincident_faces(mesh, moving, other, tol):
    """Boundary faces of `moving` whose centroid lies within tol of a
    boundary face of `other` (their surfaces touch without sharing faces)."""
    n = len(mesh.points)
    tm, _ = adapt_check.boundary_of(mesh.tets[mesh.material == moving], n)
    to, _ = adapt_check.boundary_of(mesh.tets[mesh.material == other], n)
    # A face both parts have is shared, not coincident.
    keys_o = {tuple(sorted(f)) for f in to.tolist()}
    tm = np.array([f for f in tm.tolist() if tuple(sorted(f)) not in keys_o]).reshape(-1, 3)
    if not len(tm) or not len(to):
        return 0
    centroids = mesh.points[tm].mean(axis=1)
    d = adapt_check.surface_distance(mesh.points, to, centroids)
    return int(np.count_nonzero(d < tol))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--data", required=True, help="FEMorph's Data folder")
    args = parser.parse_args()
    LoadPlugin(args.plugin, ns=globals())
    name = os.path.join(args.data, "adapt", "assembly_crank")
    with open(name + ".json") as f:
        case = json.load(f)
    moving, other = case["contact_materials"]
    motion = case["motion_3_7_4"]
    area = case["contact_area"]["discrete"]
    tol = 0.05 * min(case["crank_edge"], case["bearing_edge"])

    inp = adapt_check.read_mesh(name + ".vtu")
    assert not np.any(inp.material == 0), "the case has space cells"
    assert coincident_faces(inp, moving, other, tol) > 0, "the input's contact is conformal already"
    crank0, bearing0 = volume(inp, moving), volume(inp, other)

    reader = XMLUnstructuredGridReader(FileName=[name + ".vtu"])
    adapt = FEMorphAdapt(Input=reader, MovingObject=moving, RotationAxis=motion["rotation_axis"],
                         RotationCenter=motion["rotation_center"],
                         RotationAnglePerStep=motion["rotation_degrees_per_step"], NumberOfSteps=STEPS)
    adapt.UpdatePipelineInformation()
    algorithm = adapt.GetClientSideObject()
    counts = [0]
    failures = []
    for n in range(1, STEPS + 1):
        adapt.UpdatePipeline(float(n))
        grid = algorithm.GetOutputDataObject(0)
        table = algorithm.GetOutputDataObject(1)
        assert grid.GetNumberOfCells() > 0, "step %d: empty output" % n
        mesh = adapt_check.mesh_from_grid(grid, "step %d" % n)
        ok, rows, d = adapt_check.check_contact(mesh, moving, other, area)
        c = coincident_faces(mesh, moving, other, tol)
        rows.append(("f'", "no non-conforming contact", c == 0,
                     "%d crank boundary faces on the bearing's boundary" % c))
        vc, vb = volume(mesh, moving), volume(mesh, other)
        rows.append(("v", "volumes", abs(vc - crank0) <= 0.01 * crank0 and abs(vb - bearing0) <= 1e-9 * bearing0,
                     "crank %.6f (input %.6f), bearing %.9f (input %.9f)" % (vc, crank0, vb, bearing0)))
        counts.append(d["contact_faces"])
        got = vtk_to_numpy(table.GetColumnByName("ContactFaces")).tolist()
        rows.append(("t", "steps table", table.GetNumberOfRows() == n + 1 and got == counts,
                     "ContactFaces %s (checker %s)" % (got[-3:], counts[-3:])))
        if not all(row[2] for row in rows):
            print("step %d:" % n)
            adapt_check.print_rows(rows)
            failures.append(n)
        print("step %d: %d points, %d tets, %d contact faces, area %.5f of %.5f"
              % (n, len(mesh.points), len(mesh.tets), d["contact_faces"], d["contact_area"], area))
    assert not failures, "steps failing the checks: %s" % failures
    print("OK: FEMorph Adapt, assembly mode, %d steps conformal at the contact" % STEPS)
    return 0


if __name__ == "__main__":
    sys.exit(main())
