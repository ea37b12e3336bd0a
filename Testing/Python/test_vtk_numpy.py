"""FEMorph's filters on numpy data, their outputs read back as numpy arrays.

Run with pvpython or the Python ParaView was built for, PYTHONPATH holding the
folder of the package femorph:

  PYTHONPATH=build/lib/python3.11/dist-packages \\
    pvpython|python3 test_vtk_numpy.py --data Data/cone_sphere_torus.vtu

Uses vtkmodules.numpy_interface.dataset_adapter (dsa) and
vtkmodules.util.numpy_support both ways, and checks against numpy, here:
  - a grid made from numpy arrays (the part's points and tets, three tets
    turned inside out by swapping two vertices, a point array `Height`):
    vtkFEMorphMeshQuality's Stretch equals thesis Eq. 1.1 (signed) within
    1e-9, Inverted is 1 exactly on the three, InvertedCount is 3 and
    StretchMin the numpy minimum;
  - vtkFEMorphSegment on the part made from numpy: `Height` carried through
    unchanged; FaceRegion on exactly the boundary faces; each region's Area
    and TriangleCount (the Regions table, output 2) equal to the numpy sums
    over its faces; the boundary vertices of every plane, cylinder and sphere
    on the fitted surface (Normal/Point, Axis/Center/Radius, Center/Radius)
    within 1e-6 of the part's size; the Surface output's points are the
    mesh points its MeshPointId names.
"""
import argparse
import math
import os
import sys

import numpy as np
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_TETRA, vtkCellArray, vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_vtk_pipeline import TET_FACES, boundary_faces  # noqa: E402

FLIPPED = [0, 17, 1000]  # tets turned inside out in the Mesh Quality input


def grid_from_numpy(points, tets, point_arrays):
    """A vtkUnstructuredGrid of tets from numpy arrays (copied)."""
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=float), deep=True))
    grid.SetPoints(vtk_points)
    cells = vtkCellArray()
    offsets = np.arange(0, 4 * len(tets) + 1, 4, dtype=np.int64)
    cells.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_to_vtkIdTypeArray(np.ascontiguousarray(tets.ravel(), dtype=np.int64),
                                          deep=True))
    grid.SetCells(VTK_TETRA, cells)
    wrapped = dsa.WrapDataObject(grid)
    for name, values in point_arrays.items():
        wrapped.PointData.append(values, name)
    return grid


def stretch(points, tets):
    """Thesis Eq. 1.1 with the signed volume: 6 sqrt(6) V / (L_max A)."""
    p = points[tets]
    volume = np.einsum("ij,ij->i", p[:, 1] - p[:, 0],
                       np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    l_max = np.max([np.linalg.norm(p[:, j] - p[:, i], axis=1) for i, j in pairs], axis=0)
    area = sum(0.5 * np.linalg.norm(np.cross(p[:, j] - p[:, i], p[:, k] - p[:, i]), axis=1)
               for i, j, k in TET_FACES)
    return 6.0 * math.sqrt(6.0) * volume / (l_max * area)


def check_mesh_quality(points, tets):
    from femorph import vtkFEMorphMeshQuality

    flipped = tets.copy()
    flipped[FLIPPED, 0], flipped[FLIPPED, 1] = tets[FLIPPED, 1], tets[FLIPPED, 0]
    quality = vtkFEMorphMeshQuality()
    quality.SetInputData(grid_from_numpy(points, flipped, {}))
    quality.Update()
    out = dsa.WrapDataObject(quality.GetOutput())

    expected = stretch(points, flipped)
    got = np.asarray(out.CellData["Stretch"], dtype=float)
    assert got.shape == expected.shape, (got.shape, expected.shape)
    assert np.allclose(got, expected, rtol=1e-9, atol=1e-12), \
        "Stretch differs from Eq. 1.1 at %d tets" % (~np.isclose(got, expected, 1e-9, 1e-12)).sum()
    inverted = np.flatnonzero(np.asarray(out.CellData["Inverted"]))
    assert inverted.tolist() == FLIPPED, "Inverted at %s, flipped %s" % (inverted.tolist(), FLIPPED)
    assert out.FieldData["InvertedCount"][0] == len(FLIPPED), out.FieldData["InvertedCount"]
    assert math.isclose(out.FieldData["StretchMin"][0], expected.min(), rel_tol=1e-9), \
        (out.FieldData["StretchMin"][0], expected.min())
    print("Mesh Quality: Stretch = Eq. 1.1 on %d tets, Inverted exactly at %s" % (
        len(tets), FLIPPED))


def check_segment(points, tets):
    from femorph import vtkFEMorphSegment

    height = points[:, 2] * 2.0 + 1.0
    segment = vtkFEMorphSegment()
    segment.SetInputData(grid_from_numpy(points, tets, {"Height": height}))
    segment.Update()
    mesh = dsa.WrapDataObject(segment.GetOutput())
    surface = dsa.WrapDataObject(segment.GetOutputDataObject(1))
    regions = dsa.WrapDataObject(segment.GetOutputDataObject(2))

    assert np.array_equal(np.asarray(mesh.PointData["Height"]), height), "Height not carried"
    face_region = np.asarray(mesh.CellData["FaceRegion"])
    boundary = boundary_faces(tets)
    assert np.array_equal(face_region >= 0, boundary), "FaceRegion >= 0 off the boundary faces"

    # Each region's area and triangle count from its faces, here.
    triangles = tets[:, TET_FACES][boundary]  # (F, 3)
    region_of = face_region[boundary]
    p = points[triangles]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    n_regions = regions.VTKObject.GetNumberOfRows()
    region_id = vtk_to_numpy(regions.VTKObject.GetColumnByName("RegionId"))
    assert n_regions > 0 and region_id.tolist() == list(range(n_regions)), region_id
    expected_area = np.bincount(region_of, weights=area, minlength=n_regions)
    expected_count = np.bincount(region_of, minlength=n_regions)
    assert np.allclose(regions.RowData["Area"], expected_area, rtol=1e-9, atol=0.0), \
        (np.asarray(regions.RowData["Area"]), expected_area)
    assert np.array_equal(regions.RowData["TriangleCount"], expected_count), \
        (np.asarray(regions.RowData["TriangleCount"]), expected_count)

    # The boundary vertices of each region on its fitted surface.
    type_names = regions.VTKObject.GetColumnByName("TypeName")
    size = np.linalg.norm(points.max(axis=0) - points.min(axis=0))
    tolerance = 1e-6 * size
    checked = {}
    for r in range(n_regions):
        name = type_names.GetValue(r)
        q = points[np.unique(triangles[region_of == r])]
        if name == "plane":
            normal, point = regions.RowData["Normal"][r], regions.RowData["Point"][r]
            distance = np.abs((q - point) @ normal) / np.linalg.norm(normal)
            assert math.isnan(regions.RowData["Radius"][r]), "a plane with a Radius"
        elif name == "cylinder":
            axis, center = regions.RowData["Axis"][r], regions.RowData["Center"][r]
            axis = axis / np.linalg.norm(axis)
            d = q - center
            radial = np.linalg.norm(d - np.outer(d @ axis, axis), axis=1)
            distance = np.abs(radial - regions.RowData["Radius"][r])
        elif name == "sphere":
            center = regions.RowData["Center"][r]
            distance = np.abs(np.linalg.norm(q - center, axis=1) - regions.RowData["Radius"][r])
        else:
            continue
        assert distance.max() <= tolerance, "region %d (%s): a vertex %g off its surface" % (
            r, name, distance.max())
        checked[name] = checked.get(name, 0) + 1
    assert checked.get("plane") and checked.get("cylinder"), checked

    mesh_point_id = np.asarray(surface.PointData["MeshPointId"]).astype(np.int64)
    assert np.array_equal(np.asarray(surface.Points), points[mesh_point_id]), \
        "Surface points are not the mesh points MeshPointId names"
    print("Segment: %d regions, areas and counts = numpy on %d faces, on their surfaces: %s" % (
        n_regions, len(triangles), ", ".join("%d %s" % (n, k) for k, n in sorted(checked.items()))))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--data", required=True, help="a tet .vtu part from Data/")
    args = parser.parse_args()

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.data)
    reader.Update()
    part = dsa.WrapDataObject(reader.GetOutput())
    assert (np.asarray(part.CellTypes) == VTK_TETRA).all(), "the part must be all tets"
    # Legacy connectivity: 4, a, b, c, d per tet.
    cells = np.asarray(part.Cells).reshape(-1, 5)
    assert (cells[:, 0] == 4).all()
    points, tets = np.array(part.Points, dtype=float), cells[:, 1:].astype(np.int64)
    assert len(tets) > max(FLIPPED), "the part is too small"

    check_mesh_quality(points, tets)
    check_segment(points, tets)
    print("OK: FEMorph with numpy in %s" % sys.executable)


if __name__ == "__main__":
    main()
