"""pvbatch test of FEMorph Tet To Hex through the plugin.

Loads the plugin and checks FEMorphTetToHex against an independent numpy
computation, in this file, from the points and cells of its input (the
output of FEMorph Hex To Tet, fetched on its own) and of its output:

1. Thesis Table 4.5(a): a structured block of 10 x 3 x 2 unit cubes (60
   VTK_HEXAHEDRON, 132 points) built here, Hex To Tet (defaults: 360 tets),
   then Tet To Hex (defaults) gives back the 60 hexahedra: each output cell's
   point set is one input hexahedron's, the minimum scaled Jacobian (thesis
   Eq. 4.2, computed here) is 1 and equals the ScaledJacobian array, every
   SourceTets is 6; field data HexCount 60, TetCount 0, HexVolumeRatio 1.
2. Data/hex/hex_block.vtu (Gmsh, unstructured, 6,016 hexahedra): Hex To Tet
   (defaults), then Tet To Hex at Quad Angle 20 (default), 5 and 45:
     - cell types 10, 12, 13, 14 only, hexahedra, wedges, pyramids, tets in
       this order; points and point data unchanged; the input unchanged;
     - the tets left are input tets; SourceTets 6 or 5, 3, 2, 1 by type and
       summing to the input's tet count;
     - every cell has positive volume (split into tets from its centroid over
       its faces, each face split at its centroid), and the output's volume
       equals the input's within 1e-9 relative with each quad split along the
       diagonal that is an edge of the input tets (with the centroid split
       the total differs by up to half the warp volume of the non-planar
       quads on the boundary or meeting two triangles, ~1e-5 relative here:
       that is the bound, and it is printed);
     - the numpy minimum scaled Jacobian equals the ScaledJacobian array and
       reaches Min Scaled Jacobian (0.2) on hexahedra, wedges and pyramids
       (base corners); the tets left are exempt;
     - field data counts, volumes and ratios equal the numpy ones;
     - hexahedra non-decreasing from Quad Angle 5 to 20, candidates
       non-decreasing 5 -> 20 -> 45, and at 45 at least half of 6,016
       hexahedra recovered. The number of hexahedra is NOT monotone from 20
       to 45 on this part: the greedy conversion (Eq. 4.1) may adopt a new,
       higher-priority hexahedron across two original ones; that is printed.
3. A mesh with a hexahedron is an error (the message is printed to stderr
   and checked) and gives an empty output.

Usage: pvbatch test_tet_to_hex.py --plugin FEMorph.so --data Data/hex/hex_block.vtu
"""
import argparse
import os
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import Delete, LoadPlugin, XMLUnstructuredGridReader
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import (VTK_HEXAHEDRON, VTK_PYRAMID, VTK_TETRA, VTK_WEDGE,
                                           vtkCellArray, vtkUnstructuredGrid)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

NODES = {VTK_TETRA: 4, VTK_PYRAMID: 5, VTK_WEDGE: 6, VTK_HEXAHEDRON: 8}
# Outward faces in VTK's node orders.
FACES = {
    VTK_TETRA: [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)],
    VTK_PYRAMID: [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
    VTK_WEDGE: [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)],
    VTK_HEXAHEDRON: [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1),
                     (4, 5, 6, 7)],
}
# Eq. 4.2 corners (i, j1, j2, j3): the edge neighbours of i, ordered so that
# a positive cell is positive (and a right-angle box corner gives 1).
CORNERS = {
    VTK_TETRA: [(0, 1, 2, 3), (1, 0, 3, 2), (2, 0, 1, 3), (3, 0, 2, 1)],
    VTK_PYRAMID: [(0, 1, 3, 4), (1, 2, 0, 4), (2, 3, 1, 4), (3, 0, 2, 4)],  # base only
    VTK_WEDGE: [(0, 2, 1, 3), (1, 0, 2, 4), (2, 1, 0, 5), (3, 4, 5, 0), (4, 5, 3, 1),
                (5, 3, 4, 2)],
    VTK_HEXAHEDRON: [(0, 1, 3, 4), (1, 2, 0, 5), (2, 3, 1, 6), (3, 0, 2, 7), (4, 7, 5, 0),
                     (5, 4, 6, 1), (6, 5, 7, 2), (7, 6, 4, 3)],
}
# Output order of the kinds and their names in the field data.
KINDS = [(VTK_HEXAHEDRON, "Hex"), (VTK_WEDGE, "Prism"), (VTK_PYRAMID, "Pyramid"),
         (VTK_TETRA, "Tet")]
SOURCE_TETS = {VTK_HEXAHEDRON: (5, 6), VTK_WEDGE: (3,), VTK_PYRAMID: (2,), VTK_TETRA: (1,)}
VOLUME_RTOL = 1e-9


def fail(message):
    print("FAILED: " + message)
    sys.stdout.flush()
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


# --- numpy geometry, independent of the filter ------------------------------

def cells_by_type(grid):
    """{cell type: (cell ids, nodes (n, k))} of a vtkUnstructuredGrid."""
    types = vtk_to_numpy(grid.GetCellTypesArray()).astype(int)
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray()).astype(np.int64)
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).astype(np.int64)
    out = {}
    for t in np.unique(types).tolist():
        ids = np.nonzero(types == t)[0]
        k = NODES.get(t)
        check(k is not None, "unexpected cell type %d" % t)
        check((offsets[ids + 1] - offsets[ids] == k).all(), "type %d cells without %d nodes" % (t, k))
        out[t] = (ids, conn[offsets[ids][:, None] + np.arange(k)])
    return types, out


def min_scaled_jacobian(points, cell_type, nodes):
    """Thesis Eq. 4.2, minimum over the corners of CORNERS[cell_type]."""
    x = points[nodes]
    values = []
    for i, j1, j2, j3 in CORNERS[cell_type]:
        e1, e2, e3 = x[:, j1] - x[:, i], x[:, j2] - x[:, i], x[:, j3] - x[:, i]
        num = np.einsum("ij,ij->i", e1, np.cross(e2, e3))
        den = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(e3, axis=1)
        values.append(num / den)
    return np.min(np.stack(values, axis=1), axis=1)


def centroid_volumes(points, cell_type, nodes):
    """Each cell split into tets from its centroid over its faces, each face
    split at its centroid."""
    x = points[nodes]
    c = x.mean(axis=1)
    six_v = np.zeros(len(nodes))
    for face in FACES[cell_type]:
        f = x[:, list(face)]
        fc = f.mean(axis=1)
        for k in range(len(face)):
            a, b = f[:, k], f[:, (k + 1) % len(face)]
            # (fc, a, b) is outward: the centroid lies behind it.
            six_v -= np.einsum("ij,ij->i", np.cross(a - fc, b - fc), c - fc)
    return six_v / 6.0


def unmatched_quad_warp(points, cells):
    """Sum over the quads of the cells (`cells`: {type: (ids, nodes)}) not
    shared by two cells (on the boundary, or meeting two triangles) of
    |volume of the tet of the quad's 4 points|. The two diagonal splits of a
    quad differ by that volume and its centroid split lies half way; a quad
    shared by two cells cancels out of the total volume."""
    quads = [nodes[:, list(face)] for t, (_, nodes) in cells.items()
             for face in FACES[t] if len(face) == 4]
    if not quads:
        return 0.0
    quads = np.concatenate(quads)
    _, inverse, counts = np.unique(np.sort(quads, axis=1), axis=0, return_inverse=True,
                                   return_counts=True)
    counts = counts[inverse.reshape(-1)]
    check(counts.max() <= 2, "a quad of more than two cells")
    a, b, c, d = (points[quads[counts == 1][:, i]] for i in range(4))
    return np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))).sum() / 6.0


def edge_keys(tets, n_points):
    pairs = tets[:, [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]].reshape(-1, 2)
    return np.unique(pairs.min(axis=1) * n_points + pairs.max(axis=1))


def split_volumes(points, cell_type, nodes, tet_edges):
    """Each cell split into tets from its centroid over its faces, each quad
    split along its diagonal that is an edge of the tet mesh `tet_edges`
    (so that a cell made of tets has exactly their volume)."""
    n_points = len(points)
    x = points[nodes]
    c = x.mean(axis=1)
    six_v = np.zeros(len(nodes))
    for face in FACES[cell_type]:
        ids = nodes[:, list(face)]
        if len(face) == 3:
            tris = [ids]
        else:
            def has_edge(a, b):
                return np.isin(np.minimum(a, b) * n_points + np.maximum(a, b), tet_edges)
            d02, d13 = has_edge(ids[:, 0], ids[:, 2]), has_edge(ids[:, 1], ids[:, 3])
            check((d02 != d13).all(), "%d quads of type %d cells with %s diagonal in the tets" % (
                (d02 == d13).sum(), cell_type, "no" if (~d02 & ~d13).any() else "each"))
            t02 = [ids[:, [0, 1, 2]], ids[:, [0, 2, 3]]]
            t13 = [ids[:, [0, 1, 3]], ids[:, [1, 2, 3]]]
            tris = [np.where(d02[:, None], a, b) for a, b in zip(t02, t13)]
        for t in tris:
            p = points[t]
            six_v -= np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]),
                               c - p[:, 0])
    return six_v / 6.0


def self_check_geometry():
    """The tables above on VTK's reference cells (vtkCellType.h / vtkWedge.h /
    vtkPyramid.h: hexahedron bottom counter-clockwise seen from the top,
    wedge base normal away from (3, 4, 5), pyramid base normal toward 4)."""
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                     [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    wedge = np.array([[0, 0, 0], [0, 1, 0], [1, 0, 0], [0, 0, 1], [0, 1, 1], [1, 0, 1]], float)
    pyramid = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 1]], float)
    tet = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    for t, pts, vol, sj in [(VTK_HEXAHEDRON, cube, 1.0, 1.0), (VTK_WEDGE, wedge, 0.5, None),
                            (VTK_PYRAMID, pyramid, 1.0 / 3, None), (VTK_TETRA, tet, 1.0 / 6, None)]:
        nodes = np.arange(len(pts))[None, :]
        q = min_scaled_jacobian(pts, t, nodes)[0]
        check(q > 0 and (sj is None or abs(q - sj) < 1e-15), "reference type %d: SJ %r" % (t, q))
        v = centroid_volumes(pts, t, nodes)[0]
        check(abs(v - vol) < 1e-15, "reference type %d: volume %r" % (t, v))
    mirrored = cube * [1, 1, -1]
    check(abs(min_scaled_jacobian(mirrored, VTK_HEXAHEDRON, np.arange(8)[None, :])[0] + 1) < 1e-15,
          "a mirrored cube is not -1")


# --- VTK helpers -------------------------------------------------------------

def make_grid(points, cell_types, cells):
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=float), deep=True))
    grid.SetPoints(pts)
    grid.Allocate(len(cells))
    for t, c in zip(cell_types, cells):
        grid.InsertNextCell(int(t), len(c), [int(i) for i in c])
    return grid


def producer_of(grid):
    producer = servermanager.sources.PVTrivialProducer()
    producer.GetClientSideObject().SetOutput(grid)
    return producer


def read_vtu(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def cell_array(grid, name):
    array = grid.GetCellData().GetArray(name)
    check(array is not None, "cell array %s missing" % name)
    return vtk_to_numpy(array)


def field(grid, name):
    array = grid.GetFieldData().GetArray(name)
    check(array is not None, "field data %s missing" % name)
    check(array.GetNumberOfTuples() == 1, "field data %s has %d tuples" % (
        name, array.GetNumberOfTuples()))
    return array.GetTuple(0) if array.GetNumberOfComponents() > 1 else array.GetTuple1(0)


def snapshot(grid):
    """Deep copies of everything a filter could change in place."""
    snap = {"points": vtk_to_numpy(grid.GetPoints().GetData()).copy(),
            "types": vtk_to_numpy(grid.GetCellTypesArray()).copy(),
            "offsets": vtk_to_numpy(grid.GetCells().GetOffsetsArray()).copy(),
            "conn": vtk_to_numpy(grid.GetCells().GetConnectivityArray()).copy()}
    for kind, data in (("cell", grid.GetCellData()), ("point", grid.GetPointData())):
        for i in range(data.GetNumberOfArrays()):
            snap[kind + ":" + data.GetArrayName(i)] = vtk_to_numpy(data.GetArray(i)).copy()
    fd = grid.GetFieldData()
    snap["field"] = sorted(fd.GetArrayName(i) for i in range(fd.GetNumberOfArrays()))
    return snap


def same_snapshot(a, b):
    if a.keys() != b.keys():
        return False
    return all(np.array_equal(a[k], b[k]) if isinstance(a[k], np.ndarray) else a[k] == b[k]
               for k in a)


# --- 1. Table 4.5(a) round trip ----------------------------------------------

def structured_block(nx=10, ny=3, nz=2):
    i, j, k = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), np.arange(nz + 1), indexing="ij")
    points = np.stack([i, j, k], axis=-1).reshape(-1, 3).astype(float)

    def pid(a, b, c):
        return (a * (ny + 1) + b) * (nz + 1) + c
    hexes = []
    for a in range(nx):
        for b in range(ny):
            for c in range(nz):
                hexes.append([pid(a, b, c), pid(a + 1, b, c), pid(a + 1, b + 1, c), pid(a, b + 1, c),
                              pid(a, b, c + 1), pid(a + 1, b, c + 1), pid(a + 1, b + 1, c + 1),
                              pid(a, b + 1, c + 1)])
    return points, np.array(hexes, dtype=np.int64)


def check_round_trip():
    print("Table 4.5(a): structured block 10 x 3 x 2")
    points, hexes = structured_block()
    check(len(points) == 132 and len(hexes) == 60, "block of %d points, %d hexahedra" % (
        len(points), len(hexes)))
    check(np.allclose(centroid_volumes(points, VTK_HEXAHEDRON, hexes), 1.0, rtol=0, atol=1e-15),
          "the block's cells are not positive unit cubes")
    producer = producer_of(make_grid(points, [VTK_HEXAHEDRON] * len(hexes), hexes))
    h2t = FEMorphHexToTet(Input=producer)  # noqa: F821 (defined by LoadPlugin)
    t2h = FEMorphTetToHex(Input=h2t)  # noqa: F821
    tet_mesh = servermanager.Fetch(h2t)
    _, tet_cells = cells_by_type(tet_mesh)
    check(list(tet_cells) == [VTK_TETRA] and len(tet_cells[VTK_TETRA][0]) == 360,
          "Hex To Tet gave %r" % {t: len(c[0]) for t, c in tet_cells.items()})

    out = servermanager.Fetch(t2h)
    types, cells = cells_by_type(out)
    check(list(cells) == [VTK_HEXAHEDRON] and len(types) == 60,
          "Tet To Hex gave %r, not 60 hexahedra" % {t: len(c[0]) for t, c in cells.items()})
    out_points = vtk_to_numpy(out.GetPoints().GetData())
    check(np.array_equal(out_points, points), "points changed")
    nodes = cells[VTK_HEXAHEDRON][1]
    want = sorted(map(tuple, np.sort(hexes, axis=1).tolist()))
    got = sorted(map(tuple, np.sort(nodes, axis=1).tolist()))
    check(got == want, "the hexahedra's point sets are not the input's (%d of 60 differ)"
          % len(set(want) - set(got)))
    sj = min_scaled_jacobian(points, VTK_HEXAHEDRON, nodes)
    check(np.abs(sj - 1).max() <= 1e-12, "scaled Jacobian of a unit cube: min %r" % sj.min())
    array = cell_array(out, "ScaledJacobian")
    check(np.abs(array - sj).max() <= 1e-12, "ScaledJacobian array %r != numpy %r" % (
        array[np.argmax(np.abs(array - sj))], sj[np.argmax(np.abs(array - sj))]))
    check((cell_array(out, "SourceTets") == 6).all(), "SourceTets %r" % np.unique(
        cell_array(out, "SourceTets")))
    check(field(out, "HexCount") == 60, "HexCount %r" % field(out, "HexCount"))
    check(field(out, "TetCount") == 0, "TetCount %r" % field(out, "TetCount"))
    check(abs(field(out, "HexVolumeRatio") - 1) <= 1e-12, "HexVolumeRatio %r" % field(
        out, "HexVolumeRatio"))
    print("  60 hexahedra -> 360 tets -> %d hexahedra, scaled Jacobian %.15f, HexVolumeRatio %g"
          % (len(nodes), sj.min(), field(out, "HexVolumeRatio")))
    for proxy in (t2h, h2t, producer):
        Delete(proxy)


# --- 2. the unstructured hex part ---------------------------------------------

def check_recombined(out, tet_mesh, hex_keys, hex_cad, min_sj):
    """All the checks of one Tet To Hex output against its input tet_mesh.
    Returns the number of hexahedra, of them not an input hexahedron, and the
    numpy hex volume ratio."""
    points = vtk_to_numpy(tet_mesh.GetPoints().GetData()).astype(float)
    _, tet_cells = cells_by_type(tet_mesh)
    tets = tet_cells[VTK_TETRA][1]
    n_tets = len(tets)

    check(out.GetNumberOfPoints() == len(points), "%d points, input %d" % (
        out.GetNumberOfPoints(), len(points)))
    check(np.array_equal(vtk_to_numpy(out.GetPoints().GetData()),
                         vtk_to_numpy(tet_mesh.GetPoints().GetData())), "points moved")
    for i in range(tet_mesh.GetPointData().GetNumberOfArrays()):
        name = tet_mesh.GetPointData().GetArrayName(i)
        array = out.GetPointData().GetArray(name)
        check(array is not None and np.array_equal(
            vtk_to_numpy(array), vtk_to_numpy(tet_mesh.GetPointData().GetArray(i))),
            "point array %s not passed" % name)

    types, cells = cells_by_type(out)
    check(set(cells) <= set(NODES), "cell types %s" % sorted(cells))
    order = np.array([[k for k, _ in KINDS].index(t) for t in types.tolist()])
    check((np.diff(order) >= 0).all(), "cells not in the order hexahedra, wedges, pyramids, tets")

    # Tets left: input tets (as sets of points).
    if VTK_TETRA in cells:
        n_points = len(points)
        def key(c):
            s = np.sort(c, axis=1)
            return ((s[:, 0] * n_points + s[:, 1]) * n_points + s[:, 2]) * n_points + s[:, 3]
        check(np.isin(key(cells[VTK_TETRA][1]), key(tets)).all(), "tets left that are not input tets")

    source = cell_array(out, "SourceTets")
    check(int(source.sum()) == n_tets, "SourceTets sum to %d, input has %d tets" % (
        source.sum(), n_tets))
    edges = edge_keys(tets, len(points))
    sj_array = cell_array(out, "ScaledJacobian")
    volumes, centroid_total = {}, 0.0
    for t, (ids, nodes) in cells.items():
        check(np.isin(source[ids], SOURCE_TETS[t]).all(), "type %d cells with SourceTets %r" % (
            t, np.unique(source[ids])))
        v = centroid_volumes(points, t, nodes)
        check((v > 0).all(), "%d type %d cells of volume <= 0 (centroid split), min %r" % (
            (v <= 0).sum(), t, v.min()))
        centroid_total += v.sum()
        v = split_volumes(points, t, nodes, edges)
        check((v > 0).all(), "%d type %d cells of volume <= 0 (split as the tets), min %r" % (
            (v <= 0).sum(), t, v.min()))
        volumes[t] = v.sum()
        sj = min_scaled_jacobian(points, t, nodes)
        diff = np.abs(sj_array[ids] - sj)
        check(diff.max() <= 1e-12, "type %d: ScaledJacobian array %r, numpy %r" % (
            t, sj_array[ids][np.argmax(diff)], sj[np.argmax(diff)]))
        if t != VTK_TETRA:
            check(sj.min() >= min_sj, "type %d: %d cells below Min Scaled Jacobian %g (min %r)" % (
                t, (sj < min_sj).sum(), min_sj, sj.min()))

    expected = centroid_volumes(points, VTK_TETRA, tets).sum()
    total = sum(volumes.values())
    check(abs(total - expected) <= VOLUME_RTOL * expected, "volume %r, input %r (rel %.3g)" % (
        total, expected, (total - expected) / expected))
    centroid_rel = (centroid_total - expected) / expected
    warp_total = unmatched_quad_warp(points, cells)
    check(abs(centroid_total - expected) <= 0.5 * warp_total + VOLUME_RTOL * expected,
          "centroid-split volume %r, input %r: off by more than half the quads' warp %r" % (
              centroid_total, expected, warp_total))

    # Field data (Table 4.3) against the counts and volumes above.
    n_cells = len(types)
    for t, name in KINDS:
        count = len(cells[t][0]) if t in cells else 0
        check(field(out, name + "Count") == count, "%sCount %r, %d cells" % (
            name, field(out, name + "Count"), count))
        check(abs(field(out, name + "CountRatio") - count / n_cells) <= 1e-12,
              "%sCountRatio %r" % (name, field(out, name + "CountRatio")))
        v = volumes.get(t, 0.0)
        check(abs(field(out, name + "Volume") - v) <= VOLUME_RTOL * expected,
              "%sVolume %r, numpy %r" % (name, field(out, name + "Volume"), v))
        check(abs(field(out, name + "VolumeRatio") - v / expected) <= VOLUME_RTOL,
              "%sVolumeRatio %r, numpy %r" % (name, field(out, name + "VolumeRatio"), v / expected))
    check(abs(field(out, "TotalVolume") - expected) <= VOLUME_RTOL * expected,
          "TotalVolume %r, input %r" % (field(out, "TotalVolume"), expected))

    # Hexahedra that are input hexahedra keep the hexahedron's CADFace.
    n_hex, foreign = 0, 0
    if VTK_HEXAHEDRON in cells:
        ids, nodes = cells[VTK_HEXAHEDRON]
        n_hex = len(ids)
        cad = cell_array(out, "CADFace")
        for cell, key in zip(ids.tolist(), map(tuple, np.sort(nodes, axis=1).tolist())):
            h = hex_keys.get(key)
            if h is None:
                foreign += 1
            else:
                check(np.array_equal(cad[cell], hex_cad[h]), "hexahedron %d: CADFace %r, input %r" % (
                    cell, cad[cell], hex_cad[h]))
    ratio = volumes.get(VTK_HEXAHEDRON, 0.0) / expected
    counts = " ".join("%d %s" % (len(cells[t][0]) if t in cells else 0, name) for t, name in KINDS)
    print("    %s; hex volume ratio %.6f; min SJ %.4f; volume rel. diff %.1e "
          "(centroid split %.1e, warp bound %.1e); %d hexahedra not input ones"
          % (counts, ratio, min(sj_array[cells[t][0]].min() for t in cells if t != VTK_TETRA),
             (total - expected) / expected, centroid_rel, 0.5 * warp_total / expected, foreign))
    return n_hex, foreign, ratio


def check_hex_part(path):
    print("%s:" % os.path.basename(path))
    grid = read_vtu(path)
    _, hex_cells = cells_by_type(grid)
    check(list(hex_cells) == [VTK_HEXAHEDRON], "the part must be all hexahedra")
    hexes = hex_cells[VTK_HEXAHEDRON][1]
    n_input = len(hexes)
    hex_keys = {k: i for i, k in enumerate(map(tuple, np.sort(hexes, axis=1).tolist()))}
    hex_cad = vtk_to_numpy(grid.GetCellData().GetArray("CADFace"))
    hex_points = vtk_to_numpy(grid.GetPoints().GetData())

    reader = XMLUnstructuredGridReader(FileName=[path])
    h2t = FEMorphHexToTet(Input=reader)  # noqa: F821
    check(h2t.Conforming == 1, "Hex To Tet is not conforming by default")
    h2t.UpdatePipeline()
    tet_mesh = servermanager.Fetch(h2t)
    check(np.array_equal(vtk_to_numpy(tet_mesh.GetPoints().GetData()), hex_points),
          "Hex To Tet moved points")
    n_tets = tet_mesh.GetNumberOfCells()
    print("  %d hexahedra -> %d tets" % (n_input, n_tets))
    # The filter's input, the very object (builtin session), before the runs.
    before = snapshot(h2t.GetClientSideObject().GetOutputDataObject(0))

    t2h = FEMorphTetToHex(Input=h2t)  # noqa: F821
    check(abs(t2h.QuadAngle - 20) < 1e-15 and abs(t2h.MinScaledJacobian - 0.2) < 1e-15,
          "defaults QuadAngle %r, MinScaledJacobian %r" % (t2h.QuadAngle, t2h.MinScaledJacobian))
    check(t2h.Hexahedra == 1 and t2h.Prisms == 1 and t2h.Pyramids == 1
          and t2h.RefuseNonConformal == 0, "defaults of the kinds / RefuseNonConformal")
    hexes_at, candidates_at = {}, {}
    for angle in (20, 5, 45):
        t2h.QuadAngle = angle
        t2h.UpdatePipeline()
        out = servermanager.Fetch(t2h)
        print("  Quad Angle %g:" % angle)
        n_hex, _, ratio = check_recombined(out, tet_mesh, hex_keys, hex_cad, t2h.MinScaledJacobian)
        hexes_at[angle] = n_hex
        candidates_at[angle] = field(out, "CandidateCounts")
        if angle == 20:
            print("  defaults: %d hexahedra of %d (%.1f%%), hex volume ratio %.6f" % (
                n_hex, n_input, 100.0 * n_hex / n_input, ratio))
    after = snapshot(h2t.GetClientSideObject().GetOutputDataObject(0))
    check(same_snapshot(before, after), "Tet To Hex changed its input")

    print("  hexahedra by Quad Angle 5 / 20 / 45: %d / %d / %d; candidates (hex, prism, "
          "pyramid) %s" % (hexes_at[5], hexes_at[20], hexes_at[45],
                           " / ".join("%s" % (tuple(int(c) for c in candidates_at[a]),)
                                      for a in (5, 20, 45))))
    check(hexes_at[5] <= hexes_at[20], "fewer hexahedra at Quad Angle 20 than at 5")
    for k in range(3):
        check(candidates_at[5][k] <= candidates_at[20][k] <= candidates_at[45][k],
              "candidates not non-decreasing with the Quad Angle")
    check(hexes_at[45] >= 0.5 * n_input, "%d hexahedra at Quad Angle 45, < 50%% of %d" % (
        hexes_at[45], n_input))
    for proxy in (t2h, h2t, reader):
        Delete(proxy)


# --- 3. bad input --------------------------------------------------------------

def check_bad_input():
    print("bad input: a hexahedron and a tetrahedron")
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                       [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1], [2, 0, 0]], float)
    grid = make_grid(points, [VTK_HEXAHEDRON, VTK_TETRA],
                     [list(range(8)), [1, 8, 2, 5]])
    producer = producer_of(grid)
    t2h = FEMorphTetToHex(Input=producer)  # noqa: F821
    errors = []

    @calldata_type(VTK_STRING)
    def on_error(_obj, _event, message):
        errors.append(message)
        sys.stderr.write("(expected) " + message + "\n")

    t2h.GetClientSideObject().AddObserver("ErrorEvent", on_error)
    t2h.UpdatePipeline()
    out = servermanager.Fetch(t2h)
    check(len(errors) >= 1, "no error for a hexahedron")
    check(any("reads tetrahedra only" in e and "1 VTK_HEXAHEDRON" in e for e in errors),
          "error message %r" % errors)
    check(out.GetNumberOfCells() == 0 and out.GetNumberOfPoints() == 0,
          "output of %d cells, %d points after the error" % (out.GetNumberOfCells(),
                                                              out.GetNumberOfPoints()))
    print("  error: %s" % errors[0].strip().splitlines()[-1])
    for proxy in (t2h, producer):
        Delete(proxy)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True, help="path of FEMorph.so")
    parser.add_argument("--data", required=True, help="the all-hex .vtu (Data/hex/hex_block.vtu)")
    args = parser.parse_args()

    LoadPlugin(args.plugin, ns=globals())
    self_check_geometry()
    check_round_trip()
    check_hex_part(args.data)
    check_bad_input()
    print("OK")


if __name__ == "__main__":
    main()
