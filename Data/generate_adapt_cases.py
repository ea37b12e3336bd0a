#!/usr/bin/python3
"""Build the test cases of FEMorph Adapt: a rigid block in a box of tets.

Run with Debian's interpreter (python3-numpy and python3-paraview are Debian
packages that a pyenv python cannot see):

    /usr/bin/python3 Data/generate_adapt_cases.py                 # Data/adapt/*.vtu, .json
    /usr/bin/python3 Data/generate_adapt_cases.py --cells 20 20 50 --object 3 5 1 \
        --object-at 8 7 6 --out /tmp/adapt/block_in_box_3_7_2.vtu

The mesh is the one of thesis 3.7.2: a grid of nx x ny x nz cubes of edge
--edge, a vertex at every cube centre, each cube split into 12 tets (each
square face cut into two triangles, each triangle joined to the centre). The
diagonal of a square face joins its two corners of even i + j + k, a choice
that depends on the face only, so neighbouring cubes cut their common face
the same way and the mesh is conformal. The cubes of the object block
(--object cubes, centred in the grid unless --object-at) get MaterialId 1,
the others 0: object and space share their interface vertices and faces.

Then every vertex is jittered by a seeded uniform random move of up to
--jitter x the edge per coordinate, except along the axes on which it is
held: a vertex on a face of the box or of the object block keeps that
coordinate (it slides within the plane; on an edge of the box or block it
slides along the edge; a corner stays). So the box and the block keep their
exact planes, the block its exact volume and area. A move is rejected (the
vertex keeps its grid position) when a tet around it would get a stretch
(thesis Eq. 1.1) below --min-stretch; the rejection repeats until no tet is
below it. --smooth N adds N Laplacian sweeps (same holds and rejection).

Writes <out>.vtu (VTK XML unstructured grid, appended raw binary with zlib
compression: Float64 points, VTK_TETRA cells positively oriented,
(p1-p0).((p2-p0)x(p3-p0)) > 0, cell array MaterialId Int32) and <out>.json
next to it (the grid, the object's initial box and corners, the thesis
3.7.2 motion per step and how many steps of it keep the block inside the
box, counts, quality, the generator command). Deterministic: the same
options give the same bytes.

Without --out it writes the two kept cases into Data/adapt/ (DEFAULT_CASES).

The contact case of thesis 3.7.3, Data/adapt/cylinder_half_tube.vtu and
.json (a cylinder sliding into a half tube, both meshed by TetGen), is not
made here (TetGen is C++) but by the test program make_adapt_case
(Testing/Cxx/make_adapt_case.cpp, built with the tests):

    cmake --build build --target make_adapt_case
    build/bin/make_adapt_case Data/adapt/cylinder_half_tube.vtu
"""

import argparse
import json
import math
import os
import re
import shlex
import sys

import numpy as np

# python3-paraview puts vtkmodules in dist-packages; make sure it is found
# even when PYTHONPATH points elsewhere.
sys.path.append("/usr/lib/python3/dist-packages")
try:
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    HAVE_VTK = True
except ImportError:  # fall back to writing the XML ourselves
    HAVE_VTK = False

VTK_TETRA_TYPE = 10
OBJECT_ID = 1
SPACE_ID = 0

# The kept cases (Data/adapt/<name>.vtu): cells, object size in cubes.
DEFAULT_CASES = {
    "block_in_box": {"cells": (10, 10, 14), "object": (3, 5, 1)},
    "block_in_box_small": {"cells": (6, 6, 8), "object": (2, 2, 1)},
}

# Thesis 3.7.2's motion per step, in cube edges and degrees: 0.1 along z,
# 1 degree about the x axis through the block's centre.
THESIS_TRANSLATION = (0.0, 0.0, 0.1)
THESIS_AXIS = (1.0, 0.0, 0.0)
THESIS_DEGREES = 1.0

TET_EDGES = np.array([(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)])
OPPOSITE = np.array([(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)])

# The six faces of a unit cube, each as its four corners in cyclic order.
CUBE_FACES = np.array([
    [(0, 0, 0), (0, 1, 0), (0, 1, 1), (0, 0, 1)],   # x = 0
    [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)],   # x = 1
    [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)],   # y = 0
    [(0, 1, 0), (1, 1, 0), (1, 1, 1), (0, 1, 1)],   # y = 1
    [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)],   # z = 0
    [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)],   # z = 1
])


# ----------------------------------------------------------------------------
# Geometry
# ----------------------------------------------------------------------------

def signed_volumes(points, tets):
    p0, p1, p2, p3 = (points[tets[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", p1 - p0, np.cross(p2 - p0, p3 - p0)) / 6.0


def stretch(points, tets):
    """Thesis Eq. 1.1 (Core/quality's tet_stretch): 6 sqrt(6) V / (Lmax A),
    A the total area of the four faces; 1 for the regular tet, negative
    when inverted."""
    x = points[tets]
    v = signed_volumes(points, tets)
    e = x[:, TET_EDGES[:, 1]] - x[:, TET_EDGES[:, 0]]
    lmax = np.sqrt(np.max(np.einsum("ijk,ijk->ij", e, e), axis=1))
    f = x[:, OPPOSITE]
    area = 0.5 * np.linalg.norm(np.cross(f[:, :, 1] - f[:, :, 0], f[:, :, 2] - f[:, :, 0]),
                                axis=2).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = 6.0 * math.sqrt(6.0) * v / (lmax * area)
    return np.where(np.isfinite(s), s, 0.0)


def rotation(axis, degrees):
    """Rotation matrix about a unit axis (Rodrigues)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    t = math.radians(degrees)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * (k @ k)


# ----------------------------------------------------------------------------
# The structured 12-tets-per-cube mesh
# ----------------------------------------------------------------------------

def cube_grid(cells, edge):
    """Points (corners first, i fastest, then the cube centres), tets
    (12 per cube, positively oriented) and the cube (i, j, k) of every tet."""
    nx, ny, nz = cells
    i, j, k = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), np.arange(nz + 1), indexing="ij")
    corner_ijk = np.stack([i.ravel(order="F"), j.ravel(order="F"), k.ravel(order="F")], axis=1)
    n_corner = len(corner_ijk)
    ci, cj, ck = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    cube_ijk = np.stack([ci.ravel(order="F"), cj.ravel(order="F"), ck.ravel(order="F")], axis=1)
    n_cube = len(cube_ijk)
    points = np.vstack([corner_ijk.astype(float), cube_ijk + 0.5]) * edge

    def corner_id(ijk):
        return ijk[..., 0] + (nx + 1) * (ijk[..., 1] + (ny + 1) * ijk[..., 2])

    centre = n_corner + np.arange(n_cube)
    tets = []
    for face in CUBE_FACES:
        q = corner_id(cube_ijk[:, None, :] + face[None, :, :])    # (n_cube, 4)
        # The diagonal joins the face's two corners of even i + j + k.
        even0 = (cube_ijk + face[0]).sum(axis=1) % 2 == 0
        t1 = np.where(even0[:, None], q[:, [0, 1, 2]], q[:, [0, 1, 3]])
        t2 = np.where(even0[:, None], q[:, [0, 2, 3]], q[:, [1, 2, 3]])
        tets.append(np.column_stack([t1, centre]))
        tets.append(np.column_stack([t2, centre]))
    # Cube-major: the 12 tets of cube c are rows 12 c .. 12 c + 11.
    tets = np.stack(tets, axis=1).reshape(-1, 4)
    tet_cube = np.repeat(np.arange(n_cube), 12)
    flip = signed_volumes(points, tets) < 0
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    return points, tets.astype(np.int64), cube_ijk, corner_ijk, tet_cube


def held_axes(cells, lo, hi, corner_ijk, n_points):
    """Per point, the axes along which it may not move: those of the box
    faces and of the object block's faces it lies on (cube centres: none)."""
    held = np.zeros((n_points, 3), dtype=bool)
    ijk = corner_ijk
    n = np.asarray(cells)
    on_box = (ijk == 0) | (ijk == n)
    in_block = np.all((ijk >= lo) & (ijk <= hi), axis=1)
    on_block = in_block[:, None] & ((ijk == lo) | (ijk == hi))
    held[:len(ijk)] = on_box | on_block
    return held


def neighbours(tets, n_points):
    """The edge graph as a sparse (rows, cols) pair list."""
    e = tets[:, TET_EDGES].reshape(-1, 2)
    e = np.unique(np.sort(e, axis=1), axis=0)
    return np.concatenate([e[:, 0], e[:, 1]]), np.concatenate([e[:, 1], e[:, 0]])


def apply_moves(points, tets, move, min_stretch):
    """points + move, with the moves of the points of every tet below
    min_stretch undone until there is none (the set of undone points only
    grows, and the unmoved mesh has none). Returns the points and the count
    of undone moves."""
    move = move.copy()
    moving = np.any(move != 0, axis=1)
    undone = 0
    while True:
        x = points + move
        bad = stretch(x, tets) < min_stretch
        pts = np.unique(tets[bad])
        pts = pts[moving[pts]]
        if not len(pts):
            return x, undone
        move[pts] = 0.0
        moving[pts] = False
        undone += len(pts)


def build_case(cells, obj, edge=1.0, seed=1, jitter=0.15, min_stretch=0.15, smooth=0,
               object_at=None):
    """The case as a dict: points, tets, material and its description."""
    cells = tuple(int(c) for c in cells)
    obj = tuple(int(c) for c in obj)
    if any(o < 1 or o > c for o, c in zip(obj, cells)):
        raise ValueError(f"object {obj} does not fit in {cells} cubes")
    lo = (np.array([(c - o) // 2 for c, o in zip(cells, obj)]) if object_at is None
          else np.asarray(object_at, dtype=int))
    hi = lo + np.asarray(obj)
    if np.any(lo < 0) or np.any(hi > np.asarray(cells)):
        raise ValueError(f"object at {lo.tolist()} of size {obj} leaves the {cells} grid")
    points, tets, cube_ijk, corner_ijk, tet_cube = cube_grid(cells, edge)
    in_obj = np.all((cube_ijk >= lo) & (cube_ijk < hi), axis=1)
    material = np.where(in_obj[tet_cube], OBJECT_ID, SPACE_ID).astype(np.int32)
    grid_stretch = stretch(points, tets)
    floor = min(min_stretch, 0.999 * float(grid_stretch.min()))
    held = held_axes(cells, lo, hi, corner_ijk, len(points))

    rng = np.random.default_rng(seed)
    move = rng.uniform(-jitter, jitter, size=points.shape) * edge
    move[held] = 0.0
    points, undone = apply_moves(points, tets, move, floor)
    smooth_undone = 0
    if smooth:
        rows, cols = neighbours(tets, len(points))
        count = np.bincount(rows, minlength=len(points)).astype(float)
        for _ in range(smooth):
            mean = np.zeros_like(points)
            for d in range(3):
                mean[:, d] = np.bincount(rows, weights=points[cols, d], minlength=len(points))
            move = mean / count[:, None] - points
            move[held] = 0.0
            points, u = apply_moves(points, tets, move, floor)
            smooth_undone += u

    vol = signed_volumes(points, tets)
    assert np.all(vol > 0), "a tet is not positively oriented"
    s = stretch(points, tets)
    box_lo = lo * edge
    box_hi = hi * edge
    corners = [[float(box_lo[0] if a == 0 else box_hi[0]), float(box_lo[1] if b == 0 else box_hi[1]),
                float(box_lo[2] if c == 0 else box_hi[2])]
               for c in (0, 1) for b in (0, 1) for a in (0, 1)]
    centre = 0.5 * (box_lo + box_hi)
    domain = np.asarray(cells, dtype=float) * edge
    info = {
        "description": "rigid block (MaterialId 1) in a box of space tets (MaterialId 0), "
                       "thesis 3.7.2: cubes split into 12 tets around a centre vertex, jittered",
        "units": "cube edges x edge",
        "cells": list(cells),
        "edge": float(edge),
        "domain": {"min": [0.0, 0.0, 0.0], "max": domain.tolist()},
        "object": {
            "material_id": OBJECT_ID,
            "size_cubes": list(obj),
            "cube_min": lo.tolist(), "cube_max": hi.tolist(),
            "box": {"min": box_lo.astype(float).tolist(), "max": box_hi.astype(float).tolist()},
            "corners": corners,
            "center": centre.tolist(),
            "volume": float(np.prod(hi - lo) * edge ** 3),
            "area": float(2 * (obj[0] * obj[1] + obj[1] * obj[2] + obj[0] * obj[2]) * edge ** 2),
        },
        "space_material_id": SPACE_ID,
        "diagonals": "each square face cut by the diagonal joining its corners of even i + j + k",
        "jitter": {"seed": int(seed), "fraction_of_edge": float(jitter),
                   "min_stretch": float(floor), "moves_undone": int(undone),
                   "smooth_sweeps": int(smooth), "smooth_moves_undone": int(smooth_undone),
                   "held": "box and block face vertices keep the coordinate of every face "
                           "they lie on"},
        "counts": {"points": int(len(points)), "tets": int(len(tets)),
                   "object_tets": int(np.count_nonzero(material == OBJECT_ID)),
                   "space_tets": int(np.count_nonzero(material == SPACE_ID))},
        "volume": float(vol.sum()),
        "quality": {"stretch_min": float(s.min()), "stretch_mean": float(s.mean()),
                    "grid_stretch_min": float(grid_stretch.min()),
                    "volume_min": float(vol.min())},
        "orientation": "VTK_TETRA, (p1-p0).((p2-p0)x(p3-p0)) > 0 for every tet",
        "motion_3_7_2": motion_info(domain, box_lo, box_hi, edge),
    }
    return {"points": points, "tets": tets, "material": material, "info": info}


def motion_info(domain, box_lo, box_hi, edge):
    """Thesis 3.7.2's motion per step for this block, and the last step at
    which the moved block keeps one cube edge from the box faces."""
    centre = 0.5 * (box_lo + box_hi)
    t = np.asarray(THESIS_TRANSLATION) * edge
    corners = np.array([[x, y, z] for x in (box_lo[0], box_hi[0]) for y in (box_lo[1], box_hi[1])
                        for z in (box_lo[2], box_hi[2])])
    last = 0
    for n in range(1, 100000):
        x = centre + n * t + (corners - centre) @ rotation(THESIS_AXIS, n * THESIS_DEGREES).T
        if np.any(x < edge) or np.any(x > domain - edge):
            break
        last = n
    return {"translation_per_step": t.tolist(), "rotation_axis": list(THESIS_AXIS),
            "rotation_center": centre.tolist(), "rotation_degrees_per_step": THESIS_DEGREES,
            "pose": "x_n = c + n t + R(axis, n angle) (x_0 - c)",
            "last_step_one_edge_from_the_box": last}


# ----------------------------------------------------------------------------
# Output
# ----------------------------------------------------------------------------

def write_vtu(path, points, tets, material):
    if HAVE_VTK:
        grid = vtkUnstructuredGrid()
        pts = vtkPoints()
        pts.SetDataTypeToDouble()
        pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
        grid.SetPoints(pts)
        n = len(tets)
        conn = np.hstack([np.full((n, 1), 4, dtype=np.int64), tets.astype(np.int64)]).ravel()
        cells = vtkCellArray()
        cells.SetCells(n, numpy_to_vtkIdTypeArray(conn, deep=1))
        grid.SetCells(VTK_TETRA_TYPE, cells)
        arr = numpy_to_vtk(np.ascontiguousarray(material, dtype=np.int32), deep=1)
        arr.SetName("MaterialId")
        grid.GetCellData().AddArray(arr)
        w = vtkXMLUnstructuredGridWriter()
        w.SetFileName(path)
        w.SetInputData(grid)
        w.SetCompressorTypeToZLib()
        w.SetDataModeToAppended()
        w.EncodeAppendedDataOff()
        assert w.Write() == 1, f"VTK could not write {path}"
        return

    def rows(a, fmt):
        return "\n".join(" ".join(fmt % v for v in r) for r in np.atleast_2d(a))

    n = len(tets)
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
                'byte_order="LittleEndian" header_type="UInt64">\n<UnstructuredGrid>\n')
        f.write(f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{n}">\n<CellData>\n')
        f.write('<DataArray type="Int32" Name="MaterialId" format="ascii">\n')
        f.write(rows(np.asarray(material).reshape(-1, 1), "%d") + "\n</DataArray>\n</CellData>\n")
        f.write('<Points>\n<DataArray type="Float64" NumberOfComponents="3" format="ascii">\n')
        f.write(rows(points, "%.17g") + "\n</DataArray>\n</Points>\n<Cells>\n")
        f.write('<DataArray type="Int64" Name="connectivity" format="ascii">\n')
        f.write(rows(tets, "%d") + "\n</DataArray>\n")
        f.write('<DataArray type="Int64" Name="offsets" format="ascii">\n')
        f.write(rows((np.arange(1, n + 1) * 4).reshape(-1, 1), "%d") + "\n</DataArray>\n")
        f.write('<DataArray type="UInt8" Name="types" format="ascii">\n')
        f.write(rows(np.full((n, 1), VTK_TETRA_TYPE), "%d") + "\n</DataArray>\n")
        f.write('</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n')


def generate(path, command, **kwargs):
    case = build_case(**kwargs)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    write_vtu(path, case["points"], case["tets"], case["material"])
    info = dict(case["info"])
    info["name"] = os.path.splitext(os.path.basename(path))[0]
    info["generator"] = command
    info["file_bytes"] = os.path.getsize(path)
    text = json.dumps(info, indent=1)
    # Lists of numbers on one line.
    text = re.sub(r"\[\s*([-0-9.e+,\s]+?)\s*\]",
                  lambda m: "[" + ", ".join(m.group(1).replace(",", " ").split()) + "]", text)
    with open(os.path.splitext(path)[0] + ".json", "w") as f:
        f.write(text + "\n")
    c, q = info["counts"], info["quality"]
    print(f"{path}: {c['points']} points, {c['tets']} tets ({c['object_tets']} object), "
          f"stretch min {q['stretch_min']:.3f} mean {q['stretch_mean']:.3f}, "
          f"{info['file_bytes'] / 1024:.0f} KB")
    return case


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, nargs=3, metavar=("NX", "NY", "NZ"),
                        help="cubes along x, y, z (with --out)")
    parser.add_argument("--object", type=int, nargs=3, metavar=("OX", "OY", "OZ"),
                        help="size of the object block in cubes (with --out)")
    parser.add_argument("--object-at", type=int, nargs=3, metavar=("I", "J", "K"),
                        help="the block's lowest cube (default: centred)")
    parser.add_argument("--edge", type=float, default=1.0, help="cube edge (default 1)")
    parser.add_argument("--seed", type=int, default=1, help="jitter seed (default 1)")
    parser.add_argument("--jitter", type=float, default=0.15,
                        help="largest move per coordinate, x the edge (default 0.15)")
    parser.add_argument("--min-stretch", type=float, default=0.15,
                        help="moves making a tet of lower stretch are undone (default 0.15)")
    parser.add_argument("--smooth", type=int, default=0,
                        help="Laplacian sweeps after the jitter (default 0)")
    parser.add_argument("--out", default=None,
                        help="the .vtu to write (its .json next to it); default: the kept "
                             "cases into Data/adapt/")
    args = parser.parse_args()
    common = {"edge": args.edge, "seed": args.seed, "jitter": args.jitter,
              "min_stretch": args.min_stretch, "smooth": args.smooth}
    if args.out is None:
        if args.cells or args.object or args.object_at:
            parser.error("--cells/--object/--object-at need --out")
        here = os.path.dirname(os.path.abspath(__file__))
        for name, case in DEFAULT_CASES.items():
            command = ("/usr/bin/python3 Data/generate_adapt_cases.py --cells "
                       + " ".join(map(str, case["cells"])) + " --object "
                       + " ".join(map(str, case["object"]))
                       + f" --edge {args.edge:g} --seed {args.seed} --jitter {args.jitter:g}"
                       f" --min-stretch {args.min_stretch:g} --smooth {args.smooth}"
                       f" --out Data/adapt/{name}.vtu")
            generate(os.path.join(here, "adapt", name + ".vtu"), command,
                     cells=case["cells"], obj=case["object"], **common)
        return 0
    if not args.cells or not args.object:
        parser.error("--out needs --cells and --object")
    command = "/usr/bin/python3 Data/generate_adapt_cases.py " + " ".join(
        shlex.quote(a) for a in sys.argv[1:])
    generate(args.out, command, cells=args.cells, obj=args.object,
             object_at=args.object_at, **common)
    return 0


if __name__ == "__main__":
    sys.exit(main())
