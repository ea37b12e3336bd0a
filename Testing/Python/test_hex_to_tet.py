"""pvbatch test of FEMorph Hex To Tet through the plugin.

Loads the plugin, runs FEMorphHexToTet on the unstructured all-hex part
Data/hex/hex_block.vtu and checks the tetrahedral mesh against an independent
numpy computation, in this file, from the part's points and hexahedra (read
with VTK's own reader, not through the filter):
  - every tet is positive and lies in its SourceCell's hexahedron;
  - each hexahedron gives 5 (type A) or 6 tets;
  - conformity: no tet face is shared by more than two tets, and the faces of
    one tet are exactly the boundary quads of the hex mesh, each split in two
    (a quad split differently on its two sides would leave four);
  - the volume equals the volume inside the boundary quads split along their
    smallest-id diagonal (divergence theorem);
  - cell data copied from the source cell, point data passed;
and that a fixed type (C+ in every hexahedron's node order, which does not
conform on this mesh) reports its conflicts in NonConformingFaceCount.

Usage: pvbatch test_hex_to_tet.py --plugin FEMorph.so --data Data/hex/hex_block.vtu
"""
import argparse
import os

import numpy as np
from paraview import servermanager
from paraview.simple import LoadPlugin, XMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_HEXAHEDRON, VTK_TETRA
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

# VTK_HEXAHEDRON's faces, outward.
HEX_FACES = [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)]


def read_vtu(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def cells_of(grid, cell_type, nodes):
    types = vtk_to_numpy(grid.GetCellTypesArray())
    assert (types == cell_type).all(), "cells of types %s" % np.unique(types)
    return vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, nodes).astype(np.int64)


def signed_volumes(points, tets):
    p = points[tets]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0],
                     np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0


def unique_rows(rows):
    """Distinct rows and how often each occurs."""
    _, inverse, counts = np.unique(rows, axis=0, return_inverse=True, return_counts=True)
    return inverse.reshape(-1), counts


def boundary_quads(hexes):
    """The faces of exactly one hexahedron, as in the cell (outward)."""
    faces = hexes[:, HEX_FACES].reshape(-1, 4)
    inverse, counts = unique_rows(np.sort(faces, axis=1))
    assert counts.max() <= 2, "a quad of more than two hexahedra"
    return faces[counts[inverse] == 1]


def tet_face_counts(tets):
    """Sorted faces of the tets and, per tet face, how many tets have it."""
    faces = np.sort(tets[:, [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]].reshape(-1, 3), axis=1)
    inverse, counts = unique_rows(faces)
    return faces, counts[inverse]


def enclosed_volume(points, quads):
    """Volume inside outward quads, each split along its smallest-id diagonal."""
    d = np.argmin(quads, axis=1) % 2
    tris = np.where(d[:, None, None] == 0,
                    quads[:, [[0, 1, 2], [0, 2, 3]]], quads[:, [[0, 1, 3], [1, 2, 3]]])
    p = points[tris.reshape(-1, 3)]
    return np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0


def cell_array(grid, name):
    array = grid.GetCellData().GetArray(name)
    assert array is not None, "cell array %s missing" % name
    return vtk_to_numpy(array)


def field_count(grid, name):
    array = grid.GetFieldData().GetArray(name)
    assert array is not None, "field data %s missing" % name
    return int(array.GetTuple1(0))


def check_conforming(grid, points, hexes, quads, out):
    tets = cells_of(out, VTK_TETRA, 4)
    source = cell_array(out, "SourceCell").astype(np.int64)
    types = cell_array(out, "DecompositionType")
    assert out.GetNumberOfPoints() == len(points)
    assert np.array_equal(vtk_to_numpy(out.GetPoints().GetData()), points), "points moved"

    # Children: in their source hexahedron, 5 for type A, 6 otherwise.
    assert np.all((0 <= source) & (source < len(hexes)))
    inside = (tets[:, :, None] == hexes[source][:, None, :]).any(axis=2).all(axis=1)
    assert inside.all(), "%d tets not in their source cell" % (~inside).sum()
    children = np.bincount(source, minlength=len(hexes))
    hex_type = np.full(len(hexes), -1)
    hex_type[source] = types
    assert np.all((0 <= hex_type) & (hex_type <= 5)), "DecompositionType of a hexahedron"
    assert np.array_equal(children, np.where(hex_type == 0, 5, 6)), "tet count per hexahedron"
    assert len(tets) == int(np.where(hex_type == 0, 5, 6).sum())

    # Orientation, conformity, boundary, volume.
    vol = signed_volumes(points, tets)
    assert (vol > 0).all(), "%d tets not positive" % (vol <= 0).sum()
    faces, count = tet_face_counts(tets)
    assert count.max() <= 2, "a triangle of more than two tets"
    boundary = faces[count == 1]
    assert len(boundary) == 2 * len(quads), (len(boundary), 2 * len(quads))
    # Every boundary triangle lies in a boundary quad.
    tri_in_quad = set()
    for q in quads.tolist():
        for skip in range(4):
            tri_in_quad.add(tuple(sorted(q[:skip] + q[skip + 1:])))
    outside = [t for t in map(tuple, boundary.tolist()) if t not in tri_in_quad]
    assert not outside, "boundary triangles inside the mesh: %r" % outside[:3]
    expected = enclosed_volume(points, quads)
    assert abs(vol.sum() - expected) <= 1e-10 * expected, (vol.sum(), expected)
    assert field_count(out, "NonConformingFaceCount") == 0
    assert field_count(out, "InvertedCellCount") == 0
    assert (cell_array(out, "Inverted") == 0).all()

    # Attributes: cell data from the source cell, point data passed.
    cad = vtk_to_numpy(grid.GetCellData().GetArray("CADFace"))
    assert np.array_equal(cell_array(out, "CADFace"), cad[source]), "CADFace not copied"
    dim = vtk_to_numpy(grid.GetPointData().GetArray("CADEntityDim"))
    assert np.array_equal(vtk_to_numpy(out.GetPointData().GetArray("CADEntityDim")), dim)
    used = sorted(np.unique(hex_type).tolist())
    print("  conforming: %d hexahedra -> %d tets, types %s, volume %.6f, %d boundary "
          "triangles" % (len(hexes), len(tets), "".join("ABCDEF"[t] for t in used),
                         vol.sum(), len(boundary)))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True, help="path of FEMorph.so")
    parser.add_argument("--data", required=True, help="the all-hex .vtu (Data/hex/hex_block.vtu)")
    args = parser.parse_args()

    LoadPlugin(args.plugin, ns=globals())
    print("%s:" % os.path.basename(args.data))
    grid = read_vtu(args.data)
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    hexes = cells_of(grid, VTK_HEXAHEDRON, 8)
    quads = boundary_quads(hexes)

    reader = XMLUnstructuredGridReader(FileName=[args.data])
    h2t = FEMorphHexToTet(Input=reader)  # noqa: F821 (defined by LoadPlugin)
    assert h2t.Conforming == 1 and h2t.Mirrored == 0 and h2t.AllowInverted == 0
    assert h2t.DecompositionType == "C", h2t.DecompositionType
    h2t.UpdatePipeline()
    check_conforming(grid, points, hexes, quads, servermanager.Fetch(h2t))

    # Fixed C+ in every hexahedron's own node order: conflicts on this mesh,
    # each leaving four one-sided triangles inside.
    h2t.Conforming = 0
    h2t.DecompositionType = "C"
    h2t.AllowInverted = 1
    h2t.UpdatePipeline()
    out = servermanager.Fetch(h2t)
    tets = cells_of(out, VTK_TETRA, 4)
    assert len(tets) == 6 * len(hexes)
    assert (cell_array(out, "DecompositionType") == 2).all()
    conflicts = field_count(out, "NonConformingFaceCount")
    _, count = tet_face_counts(tets)
    one_sided = int((count == 1).sum())
    assert conflicts > 0
    assert one_sided == 2 * len(quads) + 4 * conflicts, (one_sided, len(quads), conflicts)
    inverted = int((signed_volumes(points, tets) <= 0).sum())
    assert inverted == int(cell_array(out, "Inverted").sum()), inverted
    print("  fixed C+: %d quads split both ways, %d tets of zero or negative volume"
          % (conflicts, inverted))
    print("OK")


if __name__ == "__main__":
    main()
