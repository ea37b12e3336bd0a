"""FEMorph's filters as a plain VTK pipeline in Python, without ParaView's proxies.

Run with pvpython and with the Python ParaView was built for (Debian's
/usr/bin/python3 with python3-paraview's vtkmodules), PYTHONPATH holding the
folder of the package femorph (the build tree's or an installed one):

  PYTHONPATH=build/lib/python3.11/dist-packages \\
    pvpython|python3 test_vtk_pipeline.py --data Data/boss_block.vtu --out DIR \\
      [--classes vtkFEMorphSegment ...] [--prefix DIR]

Checks:
  - `import femorph` gives exactly the wrapped classes of --classes (every
    public header of the module FEMorph::FEMorphFilters), each a vtkAlgorithm
    that can be made unless it is abstract; with --prefix, femorph and
    libFEMorphFilters.so are loaded from below that folder;
  - reader -> vtkFEMorphSegment -> vtkFEMorphImprove -> writer runs, and on
    the Segment output and on the file written, read back with a new reader,
    against numpy computations here (not the filters'):
      FaceRegion (4 per tet) is >= 0 exactly on the faces only one tet has
      (the boundary), uses regions 0..R-1 with R the rows of the Regions
      table (R > 0); VertexClass in 0..3 and > 0 exactly on the boundary's
      vertices; only tets, every tet positive (signed volumes), every point
      used; the point count within [0.5, 2] times the input's; the volume and
      the bounds of the part kept (1e-3 relative); the minimum stretch
      (thesis Eq. 1.1) not below the input's.
"""
import argparse
import math
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_TETRA
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

# Face f of a tet is the one opposite its local vertex f (FaceRegion's order).
TET_FACES = np.array([(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)])


def points_and_tets(grid):
    """(N, 3) points and (T, 4) point ids of an all-tet vtkUnstructuredGrid."""
    types = vtk_to_numpy(grid.GetCellTypesArray())
    assert len(types) > 0, "no cells"
    assert (types == VTK_TETRA).all(), "cells other than tets: %s" % sorted(set(types) - {VTK_TETRA})
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    tets = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4).astype(np.int64)
    return points, tets


def signed_volumes(points, tets):
    """Volume of each tet, positive when (p1 - p0) . ((p2 - p0) x (p3 - p0)) > 0."""
    p = points[tets]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0],
                     np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0


def min_stretch(points, tets):
    """Minimum of thesis Eq. 1.1, 6 sqrt(6) V / (L_max A), over the tets."""
    p = points[tets]
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    l_max = np.max([np.linalg.norm(p[:, j] - p[:, i], axis=1) for i, j in pairs], axis=0)
    area = sum(0.5 * np.linalg.norm(np.cross(p[:, j] - p[:, i], p[:, k] - p[:, i]), axis=1)
               for i, j, k in TET_FACES)
    return float(np.min(6.0 * math.sqrt(6.0) * signed_volumes(points, tets) / (l_max * area)))


def boundary_faces(tets):
    """(T, 4) bool: face f of tet t belongs to no other tet."""
    faces = np.sort(tets[:, TET_FACES].reshape(-1, 3), axis=1)
    _, inverse, counts = np.unique(faces, axis=0, return_inverse=True, return_counts=True)
    counts_per_face = counts[inverse.ravel()]
    assert counts_per_face.max() <= 2, "a face shared by more than two tets"
    return (counts_per_face == 1).reshape(-1, 4)


def check_segmentation_arrays(grid, n_regions, label):
    """FaceRegion and VertexClass of `grid` against its own boundary."""
    points, tets = points_and_tets(grid)
    face_region = grid.GetCellData().GetArray("FaceRegion")
    vertex_class = grid.GetPointData().GetArray("VertexClass")
    assert face_region is not None, "%s: no cell array FaceRegion" % label
    assert vertex_class is not None, "%s: no point array VertexClass" % label
    face_region = vtk_to_numpy(face_region)
    vertex_class = vtk_to_numpy(vertex_class)
    assert face_region.shape == (len(tets), 4), (label, face_region.shape)
    assert vertex_class.shape == (len(points),), (label, vertex_class.shape)

    boundary = boundary_faces(tets)
    wrong = (face_region >= 0) != boundary
    assert not wrong.any(), "%s: FaceRegion >= 0 on %d faces that are not boundary faces " \
        "or -1 on boundary faces" % (label, wrong.sum())
    used = np.unique(face_region[boundary])
    assert n_regions > 0, "%s: no region" % label
    assert used.tolist() == list(range(n_regions)), \
        "%s: FaceRegion uses %s, the Regions table has %d rows" % (label, used.tolist(), n_regions)

    on_boundary = np.zeros(len(points), dtype=bool)
    on_boundary[tets[:, TET_FACES][boundary].ravel()] = True
    assert set(np.unique(vertex_class).tolist()) <= {0, 1, 2, 3}, np.unique(vertex_class)
    wrong = (vertex_class > 0) != on_boundary
    assert not wrong.any(), "%s: VertexClass disagrees with the boundary at %d points" % (
        label, wrong.sum())
    return int(boundary.sum())


def check_mesh(grid, input_points, input_tets, label):
    """The mesh properties Improve must keep, against the input part."""
    points, tets = points_and_tets(grid)
    volumes = signed_volumes(points, tets)
    assert (volumes > 0).all(), "%s: %d tets not positive, smallest volume %g" % (
        label, (volumes <= 0).sum(), volumes.min())
    assert len(np.unique(tets)) == len(points), "%s: %d points used by no tet" % (
        label, len(points) - len(np.unique(tets)))
    n_in = len(input_points)
    assert 0.5 * n_in <= len(points) <= 2.0 * n_in, "%s: %d points from %d" % (
        label, len(points), n_in)
    volume_in = signed_volumes(input_points, input_tets).sum()
    assert abs(volumes.sum() - volume_in) <= 1e-3 * volume_in, "%s: volume %.9g, input %.9g" % (
        label, volumes.sum(), volume_in)
    lo_in, hi_in = input_points.min(axis=0), input_points.max(axis=0)
    diagonal = np.linalg.norm(hi_in - lo_in)
    for name, got, expected in (("min", points.min(axis=0), lo_in),
                                ("max", points.max(axis=0), hi_in)):
        assert np.allclose(got, expected, rtol=0.0, atol=1e-3 * diagonal), \
            "%s: bounds %s %s, input %s" % (label, name, got, expected)
    stretch, stretch_in = min_stretch(points, tets), min_stretch(input_points, input_tets)
    assert stretch >= stretch_in, "%s: minimum stretch %.4f below the input's %.4f" % (
        label, stretch, stretch_in)
    return stretch


def check_loaded_from(prefix):
    """femorph and libFEMorphFilters.so come from below `prefix`."""
    import femorph
    prefix = os.path.realpath(prefix) + os.sep
    package = os.path.realpath(femorph.__file__)
    assert package.startswith(prefix), "femorph is %s, not below %s" % (package, prefix)
    with open("/proc/self/maps") as maps:
        libraries = {line.split()[-1] for line in maps if "libFEMorphFilters.so" in line}
    assert libraries, "libFEMorphFilters.so is not loaded"
    for library in libraries:
        assert os.path.realpath(library).startswith(prefix), \
            "libFEMorphFilters.so loaded from %s, not below %s" % (library, prefix)
    print("femorph from %s, libFEMorphFilters.so from %s" % (package, ", ".join(libraries)))


def check_classes(classes):
    """`import femorph` gives exactly these wrapped classes, each a vtkAlgorithm."""
    import femorph
    exported = sorted(name for name in dir(femorph) if name.startswith("vtk"))
    assert exported == sorted(classes), "femorph has %s, the module's headers are %s" % (
        exported, sorted(classes))
    for name in classes:
        cls = getattr(femorph, name)
        assert issubclass(cls, vtkAlgorithm), "%s is not a vtkAlgorithm" % name
        try:
            instance = cls()
        except TypeError as error:  # an abstract base class cannot be made
            assert "abstract" in str(error), (name, error)
            continue
        assert instance.GetClassName() == name, (name, instance.GetClassName())


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--data", required=True, help="a tet .vtu part (Data/boss_block.vtu)")
    parser.add_argument("--out", required=True, help="folder for the written .vtu")
    parser.add_argument("--classes", nargs="*", default=[],
                        help="every class the package must export")
    parser.add_argument("--prefix", help="femorph must be loaded from below this folder")
    args = parser.parse_args()

    # The lines README.md's "Use from Python/VTK" shows.
    from femorph import vtkFEMorphImprove, vtkFEMorphSegment

    if args.classes:
        check_classes(args.classes)
    if args.prefix:
        check_loaded_from(args.prefix)

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.data)
    segment = vtkFEMorphSegment()
    segment.SetInputConnection(reader.GetOutputPort())
    improve = vtkFEMorphImprove()
    improve.SetInputConnection(segment.GetOutputPort())
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, os.path.splitext(os.path.basename(args.data))[0] + "_improved.vtu")
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetInputConnection(improve.GetOutputPort())
    writer.SetFileName(path)
    assert writer.Write() == 1, "the writer failed"

    input_points, input_tets = points_and_tets(reader.GetOutput())
    regions = segment.GetOutputDataObject(2)
    n_regions = regions.GetNumberOfRows()
    region_type = segment.GetOutput().GetFieldData().GetArray("RegionType")
    assert region_type is not None and region_type.GetNumberOfTuples() == n_regions, \
        "field data RegionType does not have one value per row of the Regions table"
    faces = check_segmentation_arrays(segment.GetOutput(), n_regions, "Segment")
    print("Segment: %d regions on %d boundary faces" % (n_regions, faces))

    result = vtkXMLUnstructuredGridReader()
    result.SetFileName(path)
    result.Update()
    improved = result.GetOutput()
    check_segmentation_arrays(improved, n_regions, "Improve")
    stretch = check_mesh(improved, input_points, input_tets, "Improve")
    print("Improve: %d -> %d points, %d -> %d tets, minimum stretch %.4f -> %.4f, written to %s" % (
        len(input_points), improved.GetNumberOfPoints(), len(input_tets),
        improved.GetNumberOfCells(), min_stretch(input_points, input_tets), stretch, path))
    print("OK: FEMorph as a VTK pipeline in %s" % sys.executable)


if __name__ == "__main__":
    main()
