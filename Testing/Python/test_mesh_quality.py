"""pvbatch test of FEMorph Mesh Quality through the plugin.

Loads the plugin, runs FEMorphMeshQuality on Data/ parts and checks every
cell array and the field-data summary against an independent numpy
computation, in this file, from the part's points and connectivity (read
with VTK's own reader, not through the filter):
  stretch, thesis Eq. 1.1:   6 sqrt(6) V / (L_max A)
  scaled Jacobian, Eq. 4.2:  min over corners of e1 . (e2 x e3) / (|e1||e2||e3|)
  dihedral angles:           pi - angle between the outward normals of two faces

With --realparts DIR, also the real parts in Medit format there, read by a
small parser here, to check the filter on meshes made by someone else. An
input asked for but missing (no .mesh file in DIR) makes the script exit with
SKIP_CODE after checking the rest, so that ctest reports the test skipped.

Usage: pvbatch test_mesh_quality.py --plugin FEMorph.so [--data Data/*.vtu] [--realparts DIR]
"""
import argparse
import math
import os
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import LoadPlugin, XMLUnstructuredGridReader
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_TETRA, vtkCellArray, vtkUnstructuredGrid
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

RTOL = 1e-9
SKIP_CODE = 77  # the tests' SKIP_RETURN_CODE
CELL_ARRAYS = ["Stretch", "ScaledJacobian", "MinDihedralAngle", "MaxDihedralAngle", "Inverted"]


def reference_quality(points, tets):
    """Quality of every tet, computed here without the filter or the core."""
    p = points[tets]  # (T, 4, 3)
    a, b, c, d = p[:, 0], p[:, 1], p[:, 2], p[:, 3]
    det = np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))  # 6 V, signed
    volume = det / 6.0
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    lengths = np.stack([np.linalg.norm(p[:, j] - p[:, i], axis=1) for i, j in pairs], axis=1)
    faces = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]  # face f opposite vertex f
    area = sum(
        0.5 * np.linalg.norm(np.cross(p[:, j] - p[:, i], p[:, k] - p[:, i]), axis=1)
        for i, j, k in faces)
    stretch = 6.0 * math.sqrt(6.0) * volume / (lengths.max(axis=1) * area)

    # Eq. 4.2 at each corner with its neighbours in an even permutation of
    # (0, 1, 2, 3), so a positive tet is positive at every corner.
    corners = [(0, 1, 2, 3), (1, 0, 3, 2), (2, 0, 1, 3), (3, 0, 2, 1)]
    jac = []
    for i, j1, j2, j3 in corners:
        e1, e2, e3 = p[:, j1] - p[:, i], p[:, j2] - p[:, i], p[:, j3] - p[:, i]
        num = np.einsum("ij,ij->i", e1, np.cross(e2, e3))
        den = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(e3, axis=1)
        jac.append(num / den)
    scaled_jacobian = np.min(np.stack(jac, axis=1), axis=1)

    # Outward unit normal of each face, from the unsigned geometry: flip the
    # normals that point towards the opposite vertex.
    normals = []
    for f, (i, j, k) in enumerate(faces):
        n = np.cross(p[:, j] - p[:, i], p[:, k] - p[:, i])
        towards = np.einsum("ij,ij->i", n, p[:, f] - p[:, i]) > 0
        n[towards] *= -1
        normals.append(n / np.linalg.norm(n, axis=1)[:, None])
    angles = []
    for i, j in pairs:  # the edge (i, j) joins the faces opposite the other two
        k, l = [v for v in range(4) if v not in (i, j)]
        cosine = np.clip(-np.einsum("ij,ij->i", normals[k], normals[l]), -1.0, 1.0)
        angles.append(np.degrees(np.arccos(cosine)))
    angles = np.stack(angles, axis=1)
    return {
        "Stretch": stretch,
        "ScaledJacobian": scaled_jacobian,
        "MinDihedralAngle": angles.min(axis=1),
        "MaxDihedralAngle": angles.max(axis=1),
        "Inverted": (det < 0).astype(float),
    }


def read_vtu(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def tets_of(grid):
    types = vtk_to_numpy(grid.GetCellTypesArray())
    assert (types == VTK_TETRA).all(), "the test part must be all tets"
    return vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)


def field(grid, name):
    array = grid.GetFieldData().GetArray(name)
    assert array is not None, "field data %s missing" % name
    assert array.GetNumberOfTuples() == 1
    return array.GetTuple1(0)


def check_close(name, actual, expected, atol=0.0):
    bad = ~np.isclose(actual, expected, rtol=RTOL, atol=atol)
    assert not bad.any(), "%s differs in %d cells, first %d: %r != %r" % (
        name, bad.sum(), np.argmax(bad), actual[bad][0], expected[bad][0])


def check_quality(source, points, tets, threshold, input_arrays):
    """Runs the filter on `source` (a proxy) and checks everything."""
    quality = FEMorphMeshQuality(Input=source)  # noqa: F821 (defined by LoadPlugin)
    assert abs(quality.StretchThreshold - 0.05) < 1e-15, quality.StretchThreshold
    quality.StretchThreshold = threshold
    quality.UpdatePipeline()
    out = servermanager.Fetch(quality)
    assert out.GetNumberOfCells() == len(tets), (out.GetNumberOfCells(), len(tets))
    assert out.GetNumberOfPoints() == len(points)

    ref = reference_quality(points, tets)
    cd = out.GetCellData()
    for name in CELL_ARRAYS:
        array = cd.GetArray(name)
        assert array is not None, "cell array %s missing" % name
        # Angles in degrees: an absolute floor for the values near 0.
        check_close(name, vtk_to_numpy(array).astype(float), ref[name],
                    atol=1e-9 if "Angle" in name else 1e-12)
    for name in input_arrays:  # passed through
        assert (cd.GetArray(name) or out.GetPointData().GetArray(name)) is not None, name

    s, j = ref["Stretch"], ref["ScaledJacobian"]
    summary = {
        "StretchMin": s.min(), "StretchMean": s.mean(), "StretchMax": s.max(),
        "ScaledJacobianMin": j.min(), "ScaledJacobianMean": j.mean(),
        "ScaledJacobianMax": j.max(),
        "MinDihedralAngleMin": ref["MinDihedralAngle"].min(),
        "MinDihedralAngleMean": ref["MinDihedralAngle"].mean(),
        "MaxDihedralAngleMean": ref["MaxDihedralAngle"].mean(),
        "MaxDihedralAngleMax": ref["MaxDihedralAngle"].max(),
        "StretchThreshold": threshold,
    }
    for name, expected in summary.items():
        actual = field(out, name)
        assert math.isclose(actual, expected, rel_tol=RTOL, abs_tol=1e-9), (name, actual, expected)
    counts = {
        "InvertedCount": int(ref["Inverted"].sum()),
        "BelowThresholdCount": int((s < threshold).sum()),
        "TetraCount": len(tets), "PyramidCount": 0, "WedgeCount": 0, "HexahedronCount": 0,
        "SkippedCellCount": 0,
    }
    for name, expected in counts.items():
        assert field(out, name) == expected, (name, field(out, name), expected)
    print("  %d tets: stretch %.4f / %.4f / %.4f, %d below %.2f, %d inverted" % (
        len(tets), s.min(), s.mean(), s.max(), counts["BelowThresholdCount"], threshold,
        counts["InvertedCount"]))
    return out


def read_medit(path):
    """Points and tets (0-based, as in the file) of an ASCII Medit .mesh."""
    with open(path) as f:
        tokens = [line.split("#")[0] for line in f]
    words = " ".join(tokens).split()
    points = tets = None
    i = 0
    while i < len(words):
        key = words[i].lower()
        if key == "vertices":
            n = int(words[i + 1])
            data = np.array(words[i + 2:i + 2 + 4 * n], dtype=float).reshape(n, 4)
            points, i = data[:, :3], i + 2 + 4 * n
        elif key == "tetrahedra":
            n = int(words[i + 1])
            data = np.array(words[i + 2:i + 2 + 5 * n], dtype=np.int64).reshape(n, 5)
            tets, i = data[:, :4] - 1, i + 2 + 5 * n
        else:
            i += 1
    return points, tets


def grid_from(points, tets):
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=True))
    grid.SetPoints(pts)
    cells = vtkCellArray()
    offsets = numpy_to_vtk(np.arange(0, 4 * len(tets) + 1, 4, dtype=np.int64), deep=True)
    conn = numpy_to_vtk(np.ascontiguousarray(tets.ravel(), dtype=np.int64), deep=True)
    cells.SetData(offsets, conn)
    grid.SetCells(VTK_TETRA, cells)
    return grid


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True, help="path of FEMorph.so")
    parser.add_argument("--data", nargs="*", default=[], help="tet .vtu files from Data/")
    parser.add_argument("--realparts", help="folder with Medit .mesh parts")
    args = parser.parse_args()
    if not args.data and not args.realparts:
        parser.error("nothing to check: give --data or --realparts")

    LoadPlugin(args.plugin, ns=globals())

    for path in args.data:
        print("%s:" % os.path.basename(path))
        grid = read_vtu(path)
        points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
        tets = tets_of(grid)
        reader = XMLUnstructuredGridReader(FileName=[path])
        arrays = [grid.GetCellData().GetArrayName(i)
                  for i in range(grid.GetCellData().GetNumberOfArrays())]
        arrays += [grid.GetPointData().GetArrayName(i)
                   for i in range(grid.GetPointData().GetNumberOfArrays())]
        for threshold in (0.05, 0.3):
            check_quality(reader, points, tets, threshold, arrays)

    if args.realparts:
        names = sorted(name for name in os.listdir(args.realparts)
                       if name.endswith(".mesh")) if os.path.isdir(args.realparts) else []
        if not names:
            print("SKIPPED: no Medit .mesh part in %s" % args.realparts)
            sys.exit(SKIP_CODE)
        for name in names:
            print("%s:" % name)
            points, tets = read_medit(os.path.join(args.realparts, name))
            producer = servermanager.sources.PVTrivialProducer()
            producer.GetClientSideObject().SetOutput(grid_from(points, tets))
            check_quality(producer, points, tets, 0.05, [])
    print("OK")


if __name__ == "__main__":
    main()
