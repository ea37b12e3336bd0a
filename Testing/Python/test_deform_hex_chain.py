"""The thesis 4.6.2 chain: a block of 10 x 3 x 2 hexahedra (3 mm cells) ->
FEMorph Hex To Tet (type C, fixed mode: the thesis' C+) -> FEMorph Deform
(Distance between the top and the bottom 6 -> 24 mm, without improvement so
the tetrahedra keep their hexahedral grouping) -> FEMorph Tet To Hex, with the
hexahedron volume ratio per Quad Angle as Table 4.3 reports it.

  pvbatch test_deform_hex_chain.py --plugin FEMorph.so

Asserts: the deformed block is 24 mm high (every top node at z = 24), no
inverted cell after Hex To Tet, Deform and Tet To Hex (signed volumes and
scaled Jacobians here, with numpy), the volume 30 x 9 x 24 kept, and a
hexahedron volume ratio that does not drop as Quad Angle grows; prints the
table.
"""
import argparse
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_HEXAHEDRON, vtkCellArray, vtkUnstructuredGrid
from vtkmodules.vtkFiltersSources import vtkCellTypeSource  # noqa: F401


def block(nx=10, ny=3, nz=2, h=3.0):
    """The hexahedral block, VTK node order."""
    ids = lambda i, j, k: (k * (ny + 1) + j) * (nx + 1) + i  # noqa: E731
    pts = np.array([(i * h, j * h, k * h) for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)])
    cells = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                cells.append([ids(i, j, k), ids(i + 1, j, k), ids(i + 1, j + 1, k), ids(i, j + 1, k),
                              ids(i, j, k + 1), ids(i + 1, j, k + 1), ids(i + 1, j + 1, k + 1), ids(i, j + 1, k + 1)])
    grid = vtkUnstructuredGrid()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(pts, deep=True))
    grid.SetPoints(points)
    conn = np.array(cells, dtype=np.int64).ravel()
    offsets = np.arange(0, len(conn) + 1, 8, dtype=np.int64)
    ca = vtkCellArray()
    ca.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True), numpy_to_vtkIdTypeArray(conn, deep=True))
    grid.SetCells(VTK_HEXAHEDRON, ca)
    return grid


def tet_volumes(grid):
    p = vtk_to_numpy(grid.GetPoints().GetData())
    types = vtk_to_numpy(grid.GetCellTypesArray())
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    off = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    tets = np.array([conn[off[c]:off[c + 1]] for c in np.nonzero(types == 10)[0]], dtype=np.int64).reshape(-1, 4)
    if len(tets) == 0:
        return np.zeros(0)
    a, b, c, d = (p[tets[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    args = parser.parse_args()
    LoadPlugin(args.plugin, ns=globals())
    failures = []
    source = TrivialProducer()
    source.GetClientSideObject().SetOutput(block())
    h2t = FEMorphHexToTet(Input=source, Conforming=0, DecompositionType=2)
    seg = FEMorphSegment(Input=h2t)
    deform = FEMorphDeform(Input=seg, DeformationType=0, UseControlPoint=1, ControlPoint=[15, 4.5, 6],
                           TargetValue=24.0, Improve=0)
    deform.UpdatePipeline()
    tets = servermanager.Fetch(h2t)
    out = servermanager.Fetch(deform)
    if out.GetNumberOfCells() == 0:
        print("FAILED: Deform gave no output")
        return 1
    v0, v1 = tet_volumes(tets), tet_volumes(out)
    z = vtk_to_numpy(out.GetPoints().GetData())[:, 2]
    print(f"Hex To Tet: {tets.GetNumberOfCells()} tets (min volume {v0.min():.4g}); "
          f"Deform: {out.GetNumberOfCells()} tets, height {z.max():.6f}, min volume {v1.min():.4g}, "
          f"volume {v1.sum():.6f}")
    if not (v0.min() > 0 and v1.min() > 0):
        failures.append("an inverted tet")
    if abs(z.max() - 24) > 1e-12 or abs(v1.sum() - 30 * 9 * 24) > 1e-9:
        failures.append(f"height {z.max()} or volume {v1.sum()} is not the block's 24 mm / 6480 mm^3")
    # Table 4.3 on the deformed tets (Improve off: the grouping is kept),
    # and, for comparison, on those FEMorph Deform improves (Improve on).
    improved = FEMorphDeform(Input=seg, DeformationType=0, UseControlPoint=1, ControlPoint=[15, 4.5, 6],
                             TargetValue=24.0, Improve=1)
    for name, tetmesh, asserted in (("Improve off", deform, True), ("Improve on", improved, False)):
        print(f"{name}: Quad Angle   hexahedra   hex volume ratio   min scaled Jacobian")
        last = -1
        for angle in (5.0, 10.0, 20.0, 30.0):
            t2h = FEMorphTetToHex(Input=tetmesh, QuadAngle=angle)
            t2h.UpdatePipeline()
            hexes = servermanager.Fetch(t2h)
            fd = hexes.GetFieldData()
            count = fd.GetArray("HexCount").GetValue(0)
            ratio = fd.GetArray("HexVolumeRatio").GetValue(0)
            sj = vtk_to_numpy(hexes.GetCellData().GetArray("ScaledJacobian"))
            print(f"{'':12}{angle:10.0f}   {int(count):9d}   {100 * ratio:15.1f} %   {sj.min():.3f}")
            if sj.min() <= 0:
                failures.append(f"{name}, Quad Angle {angle}: an inverted cell")
            if asserted and ratio < last - 1e-12:
                failures.append(f"Quad Angle {angle}: hex volume ratio fell")
            last = ratio
        if asserted and last < 0.5:
            failures.append(f"hex volume ratio {last:.3f} at 30 degrees")
    for f in failures:
        print("FAILED:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
