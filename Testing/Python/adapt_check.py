#!/usr/bin/python3
"""Check one output step of FEMorph Adapt against its input mesh.

An independent checker for FEMorph Adapt (thesis chapter 3, 3.7.2-3.7.4: a
rigid object moving through a conformal space tet mesh): numpy and VTK's
Python modules (for reading) only, no FEMorph code. Both meshes are .vtu
files of tets with the cell array MaterialId (the moving object's id, 0 for
space), e.g. Data/adapt/block_in_box.vtu (Data/generate_adapt_cases.py) and
a step that FEMorph Adapt wrote from it.

    /usr/bin/python3 Testing/Python/adapt_check.py INPUT.vtu STEP.vtu --step N \\
        [--translation X Y Z] [--axis X Y Z] [--center X Y Z] [--angle DEG]
    /usr/bin/python3 Testing/Python/adapt_check.py INPUT.vtu STEP.vtu --step N \\
        --case Data/adapt/block_in_box.json          # thesis 3.7.2's motion from the JSON
    /usr/bin/python3 Testing/Python/adapt_check.py INPUT.vtu STEP.vtu --step N \\
        --case Data/adapt/cylinder_half_tube.json    # 3.7.3: motion and contact (f-h)
    /usr/bin/python3 Testing/Python/adapt_check.py INPUT.vtu STEP.vtu --pose m00 m01 ... m33

The pose of step n is x_n = c + n t + R(axis, n angle) (x_0 - c) (t, angle per
step; FEMorph's RigidMotion), or --pose's row-major 4x4 matrix x -> R x + t
(the absolute pose of the step). Prints one line per check and exits with 1
when one fails:

(a) volumes: every tet's signed volume (VTK's orientation) > 0; reports the
    minimum volume and the minimum and mean stretch (thesis Eq. 1.1,
    6 sqrt(6) V / (L_max A), as Core/quality's tet_stretch), the input's too;
(b) conformity: no triangle face in more than two tets; the two tets of a
    shared face use it in opposite orientations; the boundary faces (in one
    tet) form a closed surface (every edge in two of them); it is the input's
    outer boundary: the same area within 1e-9 relative, every boundary vertex
    and triangle centroid within 1e-9 x the input's bounding-box diagonal of
    the input's boundary (of the box faces when the input is a box); the
    total volume equals the input's within 1e-9 relative (no hole, no crack);
(c) moving object (MaterialId == --moving-id): its vertices mapped back by
    the inverse pose coincide, one to one, with the input object's vertices
    within the tolerance (a rigid object mesh; with --object-remeshed only:
    its boundary vertices and centroids lie on the input object's boundary
    surface, its other vertices inside it); its boundary area and volume
    equal the input object's within 1e-9 relative;
(d) interface: every boundary face of the object's submesh is in exactly two
    tets of the step, the other one not of the object (space, MaterialId 0,
    or another object: counted apart);
(e) counts: vertices and tets of the step against the input (drift in
    percent; a failure only beyond --max-drift).

With --contact A B (or a --case whose .json has contact_materials, as
Data/adapt/cylinder_half_tube.json, thesis 3.7.3), numpy only:

(f) contact conformity: no face in more than two tets, every face of two
    objects' tets in exactly one tet of each, and no object boundary face
    lying on another object's boundary face without being that face;
(g) no degenerate tet: min V / (mean edge)^3 above 1e-6 (regular: 0.118);
(h) contact area: the faces shared by A and B, their area within 1 % of
    --contact-area (default: the .json's contact_area.discrete[step]).

As a module: read_mesh, mesh_from_grid, motion_pose, matrix_pose, stretch and check (all
of them; returns ok, rows, details); contact_faces, check_contact_conformity,
check_degenerate, check_contact_area and check_contact (f-h).
"""

import argparse
import json
import math
import sys

import numpy as np

sys.path.append("/usr/lib/python3/dist-packages")
from vtkmodules.vtkCommonCore import mutable, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import (  # noqa: E402
    vtkCellArray, vtkGenericCell, vtkPolyData, vtkStaticCellLocator, vtkStaticPointLocator)
from vtkmodules.vtkFiltersCore import vtkImplicitPolyDataDistance  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader  # noqa: E402
from vtkmodules.util.numpy_support import (  # noqa: E402
    numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy)

VTK_TETRA = 10
# The face opposite local vertex i, oriented outwards for a positive tet.
OUTWARD = np.array([(1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)])

REL_TOL = 1e-9        # areas, volumes: relative; distances: x the bounding-box diagonal


class Mesh:
    """A tet mesh as numpy arrays: points (n x 3), tets (m x 4), material
    (m, or None) and the VTK cell types."""

    def __init__(self, points, tets, material=None, cell_types=None, name=""):
        self.points = np.asarray(points, dtype=np.float64)
        self.tets = np.asarray(tets, dtype=np.int64).reshape(-1, 4)
        self.material = None if material is None else np.asarray(material).reshape(-1)
        self.cell_types = (np.full(len(self.tets), VTK_TETRA) if cell_types is None
                           else np.asarray(cell_types))
        self.name = name

    def copy(self):
        return Mesh(self.points.copy(), self.tets.copy(),
                    None if self.material is None else self.material.copy(),
                    self.cell_types.copy(), self.name)


def read_mesh(path):
    """A Mesh from a .vtu of tets (MaterialId read when present)."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return mesh_from_grid(reader.GetOutput(), path)


def mesh_from_grid(grid, path=""):
    """A Mesh (copies) from a vtkUnstructuredGrid of tets, e.g. a filter's
    output in pvpython (MaterialId read when present)."""
    if grid is None or grid.GetNumberOfPoints() == 0:
        raise ValueError(f"{path or 'grid'}: no points (not a readable .vtu)")
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    types = np.array(vtk_to_numpy(grid.GetCellTypesArray())) if grid.GetNumberOfCells() else np.zeros(0)
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).astype(np.int64)
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray()).astype(np.int64)
    if np.any(np.diff(offsets) != 4):
        raise ValueError(f"{path}: cells with other than 4 points")
    arr = grid.GetCellData().GetArray("MaterialId")
    material = None if arr is None else vtk_to_numpy(arr).astype(np.int64).reshape(-1)
    return Mesh(points, conn.reshape(-1, 4), material, types, path)


# ----------------------------------------------------------------------------
# Poses
# ----------------------------------------------------------------------------

def rotation(axis, degrees):
    """Rotation matrix about an axis (Rodrigues)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    t = math.radians(degrees)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * (k @ k)


def motion_pose(step, translation=(0, 0, 0), axis=(1, 0, 0), center=(0, 0, 0), degrees=0.0):
    """(R, t) of step n: x_n = c + n t + R(axis, n angle) (x_0 - c)."""
    R = rotation(axis, step * degrees)
    c = np.asarray(center, dtype=float)
    return R, c + step * np.asarray(translation, dtype=float) - R @ c


def matrix_pose(m, tolerance=1e-6):
    """(R, t) of a row-major 4x4 matrix; refuses one that is not rigid."""
    m = np.asarray(m, dtype=float).reshape(4, 4)
    if not np.all(np.isfinite(m)) or np.abs(m[3] - [0, 0, 0, 1]).max() > tolerance:
        raise ValueError("pose: the last row is not 0 0 0 1")
    R = m[:3, :3]
    if (np.abs(R.T @ R - np.eye(3)).max() > tolerance
            or abs(np.linalg.det(R) - 1) > tolerance):
        raise ValueError("pose: the 3x3 block is not a rotation")
    return R, m[:3, 3].copy()


# ----------------------------------------------------------------------------
# Geometry and topology
# ----------------------------------------------------------------------------

# The volume and the stretch (thesis Eq. 1.1, Core/quality's tet_stretch):
# one numpy definition for both independent checkers.
from deform_check import signed_volumes, stretch  # noqa: E402,F401


def triangle_areas(points, tris):
    x = points[tris]
    return 0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)


def face_table(tets, n_points):
    """All 4 m tet faces (outward orientation): the oriented triangles, the
    id of the distinct face of each, each distinct face's use count, and
    the parity of each triangle's vertex order against its sorted order."""
    tris = tets[:, OUTWARD].reshape(-1, 3)
    faces = np.sort(tris, axis=1)
    if n_points < (1 << 21):
        keys = (faces[:, 0] << 42) | (faces[:, 1] << 21) | faces[:, 2]
        _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
    else:
        _, inverse, counts = np.unique(faces, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    parity = ((a > b).astype(int) + (a > c) + (b > c)) % 2
    return tris, inverse, counts, parity


def boundary_of(tets, n_points):
    """The faces of a set of tets in only one of them (oriented outwards),
    with the slots (4 tet + local face) they come from."""
    tris, inverse, counts, _ = face_table(tets, n_points)
    slots = np.nonzero(counts[inverse] == 1)[0]
    return tris[slots], slots


def open_edges(tris, n_points):
    """Edges of a triangle set not in exactly two of its triangles."""
    if not len(tris):
        return 0
    e = np.sort(tris[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, counts = np.unique(e[:, 0] * n_points + e[:, 1], return_counts=True)
    return int(np.count_nonzero(counts != 2))


def polydata(points, tris):
    used, inverse = np.unique(tris, return_inverse=True)
    poly = vtkPolyData()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points[used]), deep=1))
    poly.SetPoints(pts)
    n = len(tris)
    conn = np.hstack([np.full((n, 1), 3, dtype=np.int64),
                      inverse.reshape(-1, 3).astype(np.int64)]).ravel()
    cells = vtkCellArray()
    cells.SetCells(n, numpy_to_vtkIdTypeArray(conn, deep=1))
    poly.SetPolys(cells)
    return poly


def surface_distance(points, tris, query):
    """Distance of each query point to the triangle set."""
    if not len(query):
        return np.zeros(0)
    locator = vtkStaticCellLocator()
    locator.SetDataSet(polydata(points, tris))
    locator.BuildLocator()
    closest = [0.0, 0.0, 0.0]
    cell = vtkGenericCell()
    cell_id, sub_id, dist2 = mutable(0), mutable(0), mutable(0.0)
    d = np.empty(len(query))
    for i, p in enumerate(np.asarray(query, dtype=float).tolist()):
        locator.FindClosestPoint(p, closest, cell, cell_id, sub_id, dist2)
        d[i] = float(dist2)
    return np.sqrt(d)


def box_distance(lo, hi, query):
    """Distance of each point to the surface of the box [lo, hi]."""
    q = np.asarray(query, dtype=float)
    outside = np.linalg.norm(np.maximum(np.maximum(lo - q, q - hi), 0.0), axis=1)
    inside = np.minimum(np.abs(q - lo), np.abs(q - hi)).min(axis=1)
    return np.where(outside > 0, outside, inside)


class Boundary:
    """The outer boundary of the input: a box (when every boundary vertex is
    on its bounding box and the areas agree) or its triangles."""

    def __init__(self, points, tris, tol):
        self.points, self.tris = points, tris
        used = np.unique(tris)
        self.lo, self.hi = points[used].min(axis=0), points[used].max(axis=0)
        size = self.hi - self.lo
        box_area = 2 * (size[0] * size[1] + size[1] * size[2] + size[0] * size[2])
        self.area = float(triangle_areas(points, tris).sum())
        self.is_box = bool(box_distance(self.lo, self.hi, points[used]).max() <= tol
                           and abs(self.area - box_area) <= REL_TOL * box_area)

    def distance(self, query):
        if self.is_box:
            return box_distance(self.lo, self.hi, query)
        return surface_distance(self.points, self.tris, query)


def nearest(points, query):
    """Index of and distance to the nearest of `points`, per query point."""
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
    poly = vtkPolyData()
    poly.SetPoints(pts)
    locator = vtkStaticPointLocator()
    locator.SetDataSet(poly)
    locator.BuildLocator()
    idx = np.array([locator.FindClosestPoint(p) for p in np.asarray(query).tolist()],
                   dtype=np.int64)
    if not len(idx):
        return idx, np.zeros(0)
    return idx, np.linalg.norm(points[idx] - query, axis=1)


def rel(a, b):
    return abs(a - b) / max(abs(b), 1e-300)


# ----------------------------------------------------------------------------
# The checks
# ----------------------------------------------------------------------------

def check(input_mesh, step_mesh, R=np.eye(3), t=np.zeros(3), moving_id=1,
          object_remeshed=False, max_drift=None):
    """All checks of step_mesh (a path or Mesh) against input_mesh at the
    object pose x -> R x + t. Returns (ok, rows, details), rows of
    (key, name, passed, text)."""
    inp = read_mesh(input_mesh) if isinstance(input_mesh, str) else input_mesh
    out = read_mesh(step_mesh) if isinstance(step_mesh, str) else step_mesh
    R = np.asarray(R, dtype=float)
    t = np.asarray(t, dtype=float)
    scale = float(np.linalg.norm(inp.points.max(axis=0) - inp.points.min(axis=0)))
    tol = REL_TOL * scale
    rows, details = [], {"tolerance": tol}
    n_out = len(out.points)

    # (a) Volumes and stretch.
    bad_ids = bool(len(out.tets) == 0 or out.tets.min() < 0 or out.tets.max() >= n_out)
    if bad_ids:
        rows.append(("a", "positive volumes", False, "no tets or point ids out of range"))
        return False, rows, details
    vol = signed_volumes(out.points, out.tets)
    s = stretch(out.points, out.tets)
    s_in = stretch(inp.points, inp.tets)
    inverted = int(np.count_nonzero(vol <= 0))
    other = int(np.count_nonzero(out.cell_types != VTK_TETRA))
    unused = int(n_out - len(np.unique(out.tets)))
    details.update(inverted=inverted, volume_min=float(vol.min()), stretch_min=float(s.min()),
                   stretch_mean=float(s.mean()), input_stretch_min=float(s_in.min()),
                   input_stretch_mean=float(s_in.mean()))
    rows.append(("a", "positive volumes", inverted == 0 and other == 0 and unused == 0,
                 f"{inverted} of {len(vol)} tets with V <= 0, min V {vol.min():.3e}, "
                 f"stretch min {s.min():.4f} mean {s.mean():.4f} "
                 f"(input {s_in.min():.4f} / {s_in.mean():.4f}), "
                 f"{other} non-tet cells, {unused} unused points"))

    # (b) Conformity and the outer boundary.
    tris, inverse, counts, parity = face_table(out.tets, n_out)
    over = int(np.count_nonzero(counts > 2))
    psum = np.bincount(inverse, weights=parity, minlength=len(counts))
    misoriented = int(np.count_nonzero((counts == 2) & (psum != 1)))
    btris = tris[counts[inverse] == 1]
    n_open = open_edges(btris, n_out)
    in_tris, _ = boundary_of(inp.tets, len(inp.points))
    outer = Boundary(inp.points, in_tris, tol)
    area = float(triangle_areas(out.points, btris).sum())
    bverts = np.unique(btris)
    query = np.vstack([out.points[bverts], out.points[btris].mean(axis=1)])
    dist = outer.distance(query) if len(query) else np.zeros(1)
    v_total, v_in = float(vol.sum()), float(signed_volumes(inp.points, inp.tets).sum())
    ok_b = (over == 0 and misoriented == 0 and n_open == 0
            and rel(area, outer.area) <= REL_TOL and float(dist.max()) <= tol
            and rel(v_total, v_in) <= REL_TOL)
    details.update(faces_in_more_than_two=over, misoriented_shared_faces=misoriented,
                   open_boundary_edges=n_open, boundary_area=area, input_boundary_area=outer.area,
                   boundary_distance_max=float(dist.max()), volume=v_total, input_volume=v_in,
                   boundary_is_box=outer.is_box)
    rows.append(("b", "conformity, outer boundary", ok_b,
                 f"{over} faces in > 2 tets, {misoriented} shared faces not opposite, "
                 f"{n_open} open boundary edges, area rel. diff {rel(area, outer.area):.1e}, "
                 f"boundary points off the input's {'box' if outer.is_box else 'boundary'} "
                 f"max {dist.max():.1e} (tol {tol:.1e}), volume rel. diff "
                 f"{rel(v_total, v_in):.1e}"))

    # (c) The moving object.
    if out.material is None or inp.material is None:
        rows.append(("c", "rigid object", False, "no MaterialId array"))
        rows.append(("d", "object-space interface", False, "no MaterialId array"))
        obj_out = obj_in = None
    else:
        obj_out = out.tets[out.material == moving_id]
        obj_in = inp.tets[inp.material == moving_id]
    if obj_out is not None and (not len(obj_out) or not len(obj_in)):
        rows.append(("c", "rigid object", False,
                     f"{len(obj_in)} input and {len(obj_out)} step tets of MaterialId {moving_id}"))
        rows.append(("d", "object-space interface", False, "no object"))
        obj_out = None
    if obj_out is not None:
        back = (out.points - t) @ R          # R^T (x - t), row-wise
        o_tris, _ = boundary_of(obj_out, n_out)
        i_tris, _ = boundary_of(obj_in, len(inp.points))
        o_area = float(triangle_areas(out.points, o_tris).sum())
        i_area = float(triangle_areas(inp.points, i_tris).sum())
        o_vol = float(signed_volumes(out.points, obj_out).sum())
        i_vol = float(signed_volumes(inp.points, obj_in).sum())
        o_verts, i_verts = np.unique(obj_out), np.unique(obj_in)
        o_bverts = np.unique(o_tris)
        surf_q = np.vstack([back[o_bverts], back[o_tris].mean(axis=1)])
        surf_d = surface_distance(inp.points, i_tris, surf_q)
        text = (f"area rel. diff {rel(o_area, i_area):.1e}, volume rel. diff "
                f"{rel(o_vol, i_vol):.1e}, boundary off the input object's max "
                f"{surf_d.max():.1e}")
        ok_c = (rel(o_area, i_area) <= REL_TOL and rel(o_vol, i_vol) <= REL_TOL
                and float(surf_d.max()) <= tol)
        if object_remeshed:
            inner = np.setdiff1d(o_verts, o_bverts)
            implicit = vtkImplicitPolyDataDistance()
            implicit.SetInput(polydata(inp.points, i_tris))
            signed = np.array([implicit.EvaluateFunction(p) for p in back[inner].tolist()])
            outside = int(np.count_nonzero(signed > tol))
            ok_c = ok_c and outside == 0
            text += f", {outside} of {len(inner)} inner vertices outside it"
        else:
            idx, d = nearest(inp.points[i_verts], back[o_verts])
            unmatched = int(np.count_nonzero(d > tol))
            twice = int(len(idx) - len(np.unique(idx)))
            ok_c = (ok_c and unmatched == 0 and twice == 0 and len(o_verts) == len(i_verts)
                    and len(obj_out) == len(obj_in))
            text = (f"{len(o_verts)} vertices ({len(i_verts)} input), {unmatched} off their "
                    f"rigid position (max {d.max():.1e}, tol {tol:.1e}), {twice} doubled, "
                    f"{len(obj_out)} tets ({len(obj_in)} input), " + text)
            details.update(object_rigid_deviation_max=float(d.max()))
        details.update(object_area=o_area, input_object_area=i_area, object_volume=o_vol,
                       input_object_volume=i_vol, object_surface_distance_max=float(surf_d.max()))
        rows.append(("c", "rigid object", bool(ok_c), text))

        # (d) Every object boundary face in one object and one other tet.
        tet_of = np.repeat(np.arange(len(out.tets)), 4)
        key_of_face = inverse
        o_mask = np.repeat(out.material == moving_id, 4)
        obj_uses = np.bincount(key_of_face[o_mask], minlength=len(counts))
        iface = np.nonzero(obj_uses == 1)[0]
        # The other tet of each interface face: the use that is not the object's.
        other_slot = np.full(len(counts), -1)
        sel = ~o_mask
        other_slot[key_of_face[sel]] = np.nonzero(sel)[0]
        in_two = counts[iface] == 2
        has_other = other_slot[iface] >= 0
        ok_faces = in_two & has_other
        other_mat = out.material[tet_of[other_slot[iface[ok_faces]]]]
        n_space = int(np.count_nonzero(other_mat == 0))
        n_other = int(len(other_mat) - n_space)
        bad = int(len(iface) - np.count_nonzero(ok_faces))
        details.update(interface_faces=int(len(iface)), interface_faces_bad=bad,
                       contact_faces=n_other)
        rows.append(("d", "object-space interface", bad == 0 and len(iface) > 0,
                     f"{len(iface)} object boundary faces: {n_space} shared with a space tet, "
                     f"{n_other} with another object's, {bad} not in exactly one object "
                     f"and one other tet"))

    # (e) Counts.
    dv = 100.0 * (n_out - len(inp.points)) / len(inp.points)
    dt = 100.0 * (len(out.tets) - len(inp.tets)) / len(inp.tets)
    details.update(vertex_drift_percent=dv, tet_drift_percent=dt)
    ok_e = max_drift is None or abs(dv) <= max_drift
    rows.append(("e", "vertex count", ok_e,
                 f"{n_out} vertices ({len(inp.points)} input, {dv:+.2f} %), {len(out.tets)} "
                 f"tets ({len(inp.tets)} input, {dt:+.2f} %)"
                 + ("" if max_drift is None else f", limit {max_drift:g} %")))
    return all(r[2] for r in rows), rows, details


# ----------------------------------------------------------------------------
# Contact (thesis 3.7.3): numpy only
# ----------------------------------------------------------------------------

CONTACT_REL_TOL = 0.01     # 3.7.3: the contact area within 1 % of the exact one
DEGENERATE_FLOOR = 1e-6    # min |V| / (mean edge)^3 of a tet (regular tet: 0.118)


def first_slot(inverse, n_faces):
    """Per distinct face of face_table, the first of its 4 m slots."""
    first = np.full(n_faces, -1, dtype=np.int64)
    slots = np.arange(len(inverse))
    first[inverse[::-1]] = slots[::-1]
    return first


def contact_faces(points, tets, material, a, b):
    """The faces shared by a tet of object a and a tet of object b (thesis
    3.7.3's contact triangles, as vertex triples) and their total area."""
    points = np.asarray(points, dtype=np.float64)
    tets = np.asarray(tets, dtype=np.int64).reshape(-1, 4)
    material = np.asarray(material).reshape(-1)
    if not len(tets):
        return np.zeros((0, 3), dtype=np.int64), 0.0
    tris, inverse, counts, _ = face_table(tets, len(points))
    mat = np.repeat(material, 4)
    in_a = np.bincount(inverse, weights=(mat == a).astype(float), minlength=len(counts))
    in_b = np.bincount(inverse, weights=(mat == b).astype(float), minlength=len(counts))
    shared = np.nonzero((in_a > 0) & (in_b > 0))[0]
    faces = tris[first_slot(inverse, len(counts))[shared]]
    return faces, float(triangle_areas(points, faces).sum())


def check_contact_conformity(points, tets, material, tol=None):
    """3.7.3's "every contact triangle shared by exactly the two object
    meshes": every face in at most two tets; every face of two objects' tets
    in exactly one tet of each; and no boundary face of an object lying on
    another object's boundary face (the same corner positions within `tol`,
    default 1e-9 x the bounding-box diagonal) without being that face (a
    non-conformal contact: the objects touch but do not share the
    triangle). Returns (ok, text, details)."""
    points = np.asarray(points, dtype=np.float64)
    tets = np.asarray(tets, dtype=np.int64).reshape(-1, 4)
    material = np.asarray(material).reshape(-1)
    if tol is None:
        tol = REL_TOL * float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))
    tris, inverse, counts, _ = face_table(tets, len(points))
    over = int(np.count_nonzero(counts > 2))
    mat = np.repeat(material, 4)
    objects = [int(m) for m in np.unique(material) if m > 0]
    uses = {m: np.bincount(inverse, weights=(mat == m).astype(float), minlength=len(counts))
            for m in objects}
    n_obj = sum((uses[m] > 0).astype(int) for m in objects) if objects else np.zeros(len(counts))
    between = np.nonzero(n_obj >= 2)[0]
    bad_between = 0
    if len(between):
        ok_between = counts[between] == 2
        for m in objects:
            ok_between &= (uses[m][between] == 0) | (uses[m][between] == 1)
        bad_between = int(np.count_nonzero(~ok_between))
    # Geometric coincidence of object boundary faces: vertices snapped to a
    # grid of `tol` (exactly coincident copies land on one key).
    first = first_slot(inverse, len(counts))
    q = np.round(points / max(tol, 1e-300)).astype(np.int64)
    _, geo = np.unique(q, axis=0, return_inverse=True)
    geo = geo.reshape(-1)
    keys, face_ids, owners = [], [], []
    for m in objects:
        fb = np.nonzero(uses[m] == 1)[0]          # m's boundary faces
        keys.append(np.sort(geo[tris[first[fb]]], axis=1))
        face_ids.append(fb)
        owners.append(np.full(len(fb), m))
    coincident = 0
    if keys and sum(len(k) for k in keys):
        keys, face_ids, owners = np.vstack(keys), np.concatenate(face_ids), np.concatenate(owners)
        _, g = np.unique(keys, axis=0, return_inverse=True)
        order = np.argsort(g.reshape(-1), kind="stable")
        gs = g.reshape(-1)[order]
        starts = np.flatnonzero(np.r_[True, gs[1:] != gs[:-1]])
        own, fid = owners[order], face_ids[order]
        # One place, faces of different objects, not one face.
        mixed_owner = np.minimum.reduceat(own, starts) != np.maximum.reduceat(own, starts)
        mixed_face = np.minimum.reduceat(fid, starts) != np.maximum.reduceat(fid, starts)
        coincident = int(np.count_nonzero(mixed_owner & mixed_face))
    ok = over == 0 and bad_between == 0 and coincident == 0
    details = {"faces_in_more_than_two": over, "object_faces_not_one_each": bad_between,
               "object_faces_between": int(len(between)), "coincident_not_shared": coincident}
    text = (f"{over} faces in > 2 tets, {len(between)} faces between two objects, "
            f"{bad_between} of them not in exactly one tet of each, {coincident} object "
            f"boundary faces on another object's without sharing it")
    return ok, text, details


def check_degenerate(points, tets, floor=DEGENERATE_FLOOR):
    """No inverted or degenerate element: every tet's signed volume over its
    mean edge length cubed above `floor` (a regular tet has 0.118). Returns
    (ok, text, details) with the minimum and the worst tet."""
    points = np.asarray(points, dtype=np.float64)
    tets = np.asarray(tets, dtype=np.int64).reshape(-1, 4)
    x = points[tets]
    vol = np.einsum("ij,ij->i", x[:, 1] - x[:, 0], np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0])) / 6.0
    pairs = np.array([(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)])
    edges = np.linalg.norm(x[:, pairs[:, 1]] - x[:, pairs[:, 0]], axis=2).mean(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(edges > 0, vol / edges ** 3, -np.inf)
    worst = int(np.argmin(ratio)) if len(ratio) else -1
    low = int(np.count_nonzero(ratio <= floor))
    m = float(ratio[worst]) if len(ratio) else float("inf")
    ok = low == 0
    return ok, (f"min V / (mean edge)^3 {m:.3e} (tet {worst}), {low} of {len(ratio)} tets at or "
                f"below {floor:g}"), {"degenerate_ratio_min": m, "degenerate_tets": low,
                                      "degenerate_worst_tet": worst}


def check_contact_area(area, expected, rel_tol=CONTACT_REL_TOL, abs_tol=0.0):
    """|area - expected| <= rel_tol x expected (+ abs_tol): 3.7.3's "contact
    area within 1 % of the exact contact area of the step" (expected: the
    area of the step's overlap, e.g. the .json's contact_area.discrete[n]).
    Returns (ok, text, details)."""
    diff = abs(area - expected)
    ok = bool(diff <= rel_tol * abs(expected) + abs_tol)
    r = diff / abs(expected) if expected else (0.0 if diff == 0 else float("inf"))
    return ok, (f"area {area:.6g}, expected {expected:.6g}, rel. diff {r:.2e} "
                f"(limit {rel_tol:g})"), {"contact_area": area, "expected_contact_area": expected,
                                          "contact_area_rel_diff": r}


def check_contact(mesh, a, b, expected_area, rel_tol=CONTACT_REL_TOL, floor=DEGENERATE_FLOOR):
    """The contact checks of one step (thesis 3.7.3) between objects a and b
    of a Mesh: (f) conformity of the contact, (g) no degenerate element, (h)
    contact area. Returns (ok, rows, details) as check()."""
    rows, details = [], {}
    faces, area = contact_faces(mesh.points, mesh.tets, mesh.material, a, b)
    ok_f, text, d = check_contact_conformity(mesh.points, mesh.tets, mesh.material)
    details.update(d, contact_faces=int(len(faces)))
    rows.append(("f", "contact conformity", ok_f, f"{len(faces)} contact faces of {a} and {b}, " + text))
    ok_g, text, d = check_degenerate(mesh.points, mesh.tets, floor)
    details.update(d)
    rows.append(("g", "no degenerate tet", ok_g, text))
    ok_h, text, d = check_contact_area(area, expected_area, rel_tol)
    details.update(d)
    rows.append(("h", "contact area", ok_h, text))
    return all(r[2] for r in rows), rows, details


def print_rows(rows, out=sys.stdout):
    w = max(len(r[1]) for r in rows)
    for key, name, ok, text in rows:
        print(f"({key}) {name:<{w}}  {'ok    ' if ok else 'FAILED'}  {text}", file=out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("input", help="the input mesh (.vtu with MaterialId)")
    parser.add_argument("step", help="the output of one step (.vtu with MaterialId)")
    parser.add_argument("--step", dest="n", type=int, default=0, help="the step number n")
    parser.add_argument("--translation", type=float, nargs=3, default=None,
                        metavar=("X", "Y", "Z"), help="translation per step")
    parser.add_argument("--axis", type=float, nargs=3, default=None, metavar=("X", "Y", "Z"),
                        help="rotation axis (default x)")
    parser.add_argument("--center", type=float, nargs=3, default=None, metavar=("X", "Y", "Z"),
                        help="a point of the rotation axis")
    parser.add_argument("--angle", type=float, default=None, help="degrees per step")
    parser.add_argument("--case", default=None,
                        help="a Data/adapt/*.json: its motion_3_7_2 (and the object's id) "
                             "unless given by the options above")
    parser.add_argument("--pose", type=float, nargs=16, default=None, metavar="M",
                        help="the step's absolute pose, row-major 4x4 (m00 .. m33) "
                             "instead of the motion")
    parser.add_argument("--moving-id", type=int, default=None,
                        help="MaterialId of the moving object (default 1)")
    parser.add_argument("--object-remeshed", action="store_true",
                        help="(c): the object mesh may differ; only its boundary on the "
                             "input's and its vertices inside")
    parser.add_argument("--max-drift", type=float, default=None,
                        help="(e) fails when the vertex count drifts by more (percent)")
    parser.add_argument("--contact", type=int, nargs=2, default=None, metavar=("A", "B"),
                        help="(f)-(h): the contact checks between objects A and B (default "
                             "with --case: its contact_materials)")
    parser.add_argument("--contact-area", type=float, default=None,
                        help="(h) the expected contact area of the step (default with --case: "
                             "its contact_area.discrete[step])")
    args = parser.parse_args()

    motion = {"translation_per_step": [0, 0, 0], "rotation_axis": [1, 0, 0],
              "rotation_center": [0, 0, 0], "rotation_degrees_per_step": 0.0}
    moving_id = 1
    case = {}
    if args.case:
        with open(args.case) as f:
            case = json.load(f)
        motion.update(case.get("motion_3_7_2", case.get("motion_3_7_3", {})))
        moving_id = case.get("object", {}).get("material_id", 1)
    for name, value in (("translation_per_step", args.translation),
                        ("rotation_axis", args.axis), ("rotation_center", args.center),
                        ("rotation_degrees_per_step", args.angle)):
        if value is not None:
            motion[name] = value
    if args.moving_id is not None:
        moving_id = args.moving_id
    if args.pose is not None:
        R, t = matrix_pose(args.pose)
    else:
        R, t = motion_pose(args.n, motion["translation_per_step"], motion["rotation_axis"],
                           motion["rotation_center"], motion["rotation_degrees_per_step"])
    ok, rows, _ = check(args.input, args.step, R, t, moving_id, args.object_remeshed,
                        args.max_drift)
    contact = args.contact or case.get("contact_materials")
    if contact:
        expected = args.contact_area
        if expected is None:
            areas = case.get("contact_area", {}).get("discrete", [])
            if args.n >= len(areas):
                parser.error("no expected contact area for this step: give --contact-area")
            expected = areas[args.n]
        ok_c, rows_c, _ = check_contact(read_mesh(args.step), contact[0], contact[1], expected)
        ok = ok and ok_c
        rows += rows_c
    print(f"{args.step} (step {args.n}) against {args.input}")
    print_rows(rows)
    print("PASSED" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
