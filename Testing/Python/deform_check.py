#!/usr/bin/python3
"""Check a deformed tet mesh against the CAD of the changed part.

An independent checker for FEMorph Deform (thesis 2.5): numpy and VTK's
Python modules only, no FEMorph code. The changed CAD is a variant written by
Data/generate_parts.py --variants: Data/variants/<part>__<variant>.json (each
CAD face's label and exact parameters, the CAD volume) and .vtp (a fine
triangle mesh of the variant's CAD boundary with the cell array CADFace).
The deformed mesh carries the base part's cell array CADFace (Gmsh surface
tag of each tet face, -1 inside), whose tags the base part's .json maps to
labels, and the labels to the variant's faces.

    /usr/bin/python3 Testing/Python/deform_check.py --base Data/boss_block.vtu \\
        --variant Data/variants/boss_block__boss_height_20 --mesh out.vtu \\
        [--fixed-labels "block bottom" "through hole"]

prints one row per check and exits with 1 when one fails:

- validity: no tet of signed volume <= 0 (VTK's orientation), every triangle
  face in one or two tets, the faces in one tet a closed 2-manifold (every
  edge of them in exactly two), no point without a tet; minimum stretch
  (thesis Eq. 1.1) at least 0.2;
- on_surfaces: every boundary vertex within 1e-6 x the variant's bounding box
  diagonal of the exact variant surface of every CAD face it belongs to;
- cad_to_mesh: the largest distance from the variant's CAD sample (vertices
  and triangle centroids) to the mesh boundary at most 1.1 x the base mesh's
  own (chord_error, against <part>__base.vtp next to the variant), plus
  1e-9 x the diagonal (the beam's planes have no chord error);
- volume: |V - V_cad| at most |V_base_mesh - V_base_cad| + 1e-9 V_cad;
- fixed_unchanged (with --fixed-labels): the points on those faces only keep
  their coordinates bit for bit (same point ids as the base mesh).

As a module: read_mesh, validity, on_surfaces, cad_to_mesh, chord_error,
volume, fixed_unchanged and check (all of them, with the thresholds).
"""

import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.append("/usr/lib/python3/dist-packages")
from vtkmodules.vtkCommonCore import mutable, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import (  # noqa: E402
    vtkCellArray, vtkGenericCell, vtkPolyData, vtkStaticCellLocator, vtkUnstructuredGrid)
from vtkmodules.vtkIOXML import (  # noqa: E402
    vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader)
from vtkmodules.util.numpy_support import (  # noqa: E402
    numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy)

VTK_TETRA = 10
# Local vertices of the face opposite local vertex i (CADFace component i).
OPPOSITE = np.array([(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)])
TET_EDGES = np.array([(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)])

# Thresholds of the Deform tests.
SURFACE_TOL_REL = 1e-6      # x the part's bounding box diagonal
CHORD_FACTOR = 1.1          # x the base mesh's chord error
CHORD_FLOOR_REL = 1e-9      # x the diagonal, added (parts whose chord error is 0)
VOLUME_REL_SLACK = 1e-9     # x the CAD volume, added to the base mesh's error
MIN_STRETCH = 0.2


class Mesh:
    """A tet mesh as numpy arrays: points (n x 3), tets (m x 4), cad_face
    (m x 4 or None) and the VTK cell types (to refuse other cells)."""

    def __init__(self, points, tets, cad_face=None, cell_types=None, name=""):
        self.points = np.asarray(points, dtype=np.float64)
        self.tets = np.asarray(tets, dtype=np.int64)
        self.cad_face = None if cad_face is None else np.asarray(cad_face).reshape(-1, 4)
        self.cell_types = (np.full(len(self.tets), VTK_TETRA) if cell_types is None
                           else np.asarray(cell_types))
        self.name = name
        self._boundary = None

    def boundary(self):
        """Boundary faces (those of one tet): (tet, local face) slots, the
        triangles' vertex ids, and the face-use count of every distinct face."""
        if self._boundary is None:
            faces = np.sort(self.tets[:, OPPOSITE].reshape(-1, 3), axis=1)
            n = max(len(self.points), 1)
            if n < (1 << 21):
                keys = (faces[:, 0] << 42) | (faces[:, 1] << 21) | faces[:, 2]
                _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
            else:
                _, inverse, counts = np.unique(faces, axis=0, return_inverse=True,
                                               return_counts=True)
            inverse = inverse.reshape(-1)
            single = counts[inverse] == 1
            slots = np.nonzero(single)[0]
            tris = self.tets[:, OPPOSITE].reshape(-1, 3)[slots]
            self._boundary = (slots, tris, counts)
        return self._boundary


def read_mesh(source):
    """A Mesh from a .vtu path or a vtkUnstructuredGrid."""
    if isinstance(source, str):
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(source)
        reader.Update()
        grid = reader.GetOutput()
        name = source
        if grid is None or grid.GetNumberOfPoints() == 0:
            raise ValueError(f"{source}: no points (not a readable .vtu)")
    else:
        grid, name = source, "grid"
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    types = vtk_to_numpy(grid.GetCellTypesArray()) if grid.GetNumberOfCells() else np.zeros(0)
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).astype(np.int64)
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray()).astype(np.int64)
    sizes = np.diff(offsets)
    if len(sizes) and np.any(sizes != 4):
        raise ValueError(f"{name}: cells with other than 4 points")
    tets = conn.reshape(-1, 4)
    arr = grid.GetCellData().GetArray("CADFace")
    cad_face = None
    if arr is not None:
        if arr.GetNumberOfComponents() != 4:
            raise ValueError(f"{name}: CADFace has {arr.GetNumberOfComponents()} components")
        cad_face = vtk_to_numpy(arr).reshape(-1, 4).astype(np.int64)
    return Mesh(points, tets, cad_face, types, name)


def read_sample(path):
    """Points, triangles and CADFace (tag per triangle) of a variant's .vtp."""
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    poly = reader.GetOutput()
    if poly is None or poly.GetNumberOfPoints() == 0:
        raise ValueError(f"{path}: no points (not a readable .vtp)")
    points = vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    conn = vtk_to_numpy(poly.GetPolys().GetConnectivityArray()).astype(np.int64)
    tags = vtk_to_numpy(poly.GetCellData().GetArray("CADFace")).astype(np.int64)
    return points, conn.reshape(-1, 3), tags


def load_json(path):
    with open(path) as f:
        return json.load(f)


def signed_volumes(points, tets):
    p0, p1, p2, p3 = (points[tets[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", p1 - p0, np.cross(p2 - p0, p3 - p0)) / 6.0


def diagonal(info):
    box = info["bounding_box"]
    return float(np.linalg.norm(np.subtract(box["max"], box["min"])))


# ----------------------------------------------------------------------------
# Validity and quality
# ----------------------------------------------------------------------------

def stretch(points, tets):
    """Thesis Eq. 1.1: 6 sqrt(6) V / (Lmax A_total), 1 for the regular tet;
    negative for an inverted one."""
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


def validity(mesh):
    """Inverted tets, conformity, closed boundary, unused points, stretch."""
    if isinstance(mesh, (str, vtkUnstructuredGrid)):
        mesh = read_mesh(mesh)
    res = {"tets": int(len(mesh.tets)), "points": int(len(mesh.points))}
    res["non_tetra_cells"] = int(np.count_nonzero(mesh.cell_types != VTK_TETRA))
    out_of_range = (len(mesh.tets) and (mesh.tets.min() < 0 or
                                        mesh.tets.max() >= len(mesh.points)))
    res["bad_point_ids"] = bool(out_of_range)
    if out_of_range or not len(mesh.tets):
        res["ok"] = False
        return res
    vol = signed_volumes(mesh.points, mesh.tets)
    res["inverted"] = int(np.count_nonzero(vol <= 0.0))
    slots, tris, counts = mesh.boundary()
    res["faces_in_more_than_two_tets"] = int(np.count_nonzero(counts > 2))
    res["boundary_triangles"] = int(len(tris))
    edges = np.sort(tris[:, [0, 1, 1, 2, 0, 2]].reshape(-1, 2), axis=1)
    _, ecounts = np.unique(edges[:, 0] * len(mesh.points) + edges[:, 1], return_counts=True)
    res["boundary_edges_not_in_two_triangles"] = int(np.count_nonzero(ecounts != 2))
    res["unused_points"] = int(len(mesh.points) - len(np.unique(mesh.tets)))
    s = stretch(mesh.points, mesh.tets)
    res["stretch_min"] = float(s.min())
    res["stretch_mean"] = float(s.mean())
    res["ok"] = (res["non_tetra_cells"] == 0 and res["inverted"] == 0
                 and res["faces_in_more_than_two_tets"] == 0
                 and res["boundary_edges_not_in_two_triangles"] == 0
                 and res["unused_points"] == 0)
    return res


# ----------------------------------------------------------------------------
# Exact distances to the analytic CAD surfaces
# ----------------------------------------------------------------------------

def _axial(x, origin, direction):
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    v = x - np.asarray(origin, dtype=float)
    h = v @ d
    rho = np.linalg.norm(v - np.outer(h, d), axis=1)
    return h, rho


def surface_distance(face, x):
    """Distance of points x (n x 3) to the whole analytic surface of a face
    entry (plane, cylinder, one nappe of a cone, sphere, torus)."""
    kind = face["primitive"]
    x = np.atleast_2d(np.asarray(x, dtype=float))
    if kind == "plane":
        n = np.asarray(face["normal"], dtype=float)
        return np.abs((x - np.asarray(face["point"])) @ (n / np.linalg.norm(n)))
    if kind == "cylinder":
        _, rho = _axial(x, face["axis_point"], face["axis_direction"])
        return np.abs(rho - face["radius"])
    if kind == "cone":
        h, rho = _axial(x, face["apex"], face["axis_direction"])
        a = math.radians(face["half_angle_deg"])
        along = h * math.cos(a) + rho * math.sin(a)
        return np.where(along >= 0.0, np.abs(rho * math.cos(a) - h * math.sin(a)),
                        np.hypot(h, rho))
    if kind == "sphere":
        return np.abs(np.linalg.norm(x - np.asarray(face["center"]), axis=1) - face["radius"])
    if kind == "torus":
        h, rho = _axial(x, face["center"], face["axis_direction"])
        return np.abs(np.hypot(rho - face["major_radius"], h) - face["minor_radius"])
    raise ValueError(f"no analytic distance for a '{kind}' face ({face.get('label')})")


def _faces_by_label(info):
    by_label = {}
    for f in info["faces"]:
        by_label.setdefault(f["label"], []).append(f)
    return by_label


def on_surfaces(mesh, variant_json, base_json, tol=None, relabel=False):
    """Largest distance of the boundary vertices to the variant's surface of
    every CAD face label they belong to (the base tag of their boundary faces
    -> label -> the variant's face). Returns max, per_label, tol and ok."""
    if isinstance(mesh, (str, vtkUnstructuredGrid)):
        mesh = read_mesh(mesh)
    if isinstance(variant_json, str):
        variant_json = load_json(variant_json)
    if isinstance(base_json, str):
        base_json = load_json(base_json)
    if tol is None:
        tol = SURFACE_TOL_REL * diagonal(variant_json)
    if mesh.cad_face is None:
        return {"max": float("inf"), "per_label": {}, "tol": tol, "ok": False,
                "error": "no CADFace array"}
    label_of_tag = {f["tag"]: f["label"] for f in base_json["faces"]}
    variant_faces = _faces_by_label(variant_json)
    slots, tris, _ = mesh.boundary()
    # relabel: a mesh an editor made new tets in (see boundary_face_tags);
    # off, each face has its own CADFace value.
    tags = (boundary_face_tags(mesh, slots, tris, label_of_tag, variant_faces) if relabel
            else mesh.cad_face.reshape(-1)[slots])
    res = {"tol": tol, "per_label": {}}
    unlabelled = int(np.count_nonzero(~np.isin(tags, list(label_of_tag))))
    res["boundary_faces_without_cad_face"] = unlabelled
    worst = 0.0
    for tag in np.unique(tags):
        if int(tag) not in label_of_tag:
            continue
        label = label_of_tag[int(tag)]
        if label not in variant_faces:
            res.setdefault("labels_missing_in_variant", []).append(label)
            continue
        verts = np.unique(tris[tags == tag])
        x = mesh.points[verts]
        d = np.min([surface_distance(f, x) for f in variant_faces[label]], axis=0)
        m = float(d.max())
        res["per_label"][label] = max(res["per_label"].get(label, 0.0), m)
        worst = max(worst, m)
    res["max"] = worst
    res["ok"] = (worst <= tol and unlabelled == 0
                 and not res.get("labels_missing_in_variant"))
    return res


def cad_sample_deviation(sample, sample_json, variant_json):
    """How far the CAD moved, per label: the largest distance of the sample's
    vertices (of `sample_json`'s part, e.g. <part>__base.vtp) to the surface
    of the same label in `variant_json`."""
    points, tris, tags = read_sample(sample) if isinstance(sample, str) else sample
    label_of_tag = {f["tag"]: f["label"] for f in sample_json["faces"]}
    variant_faces = _faces_by_label(variant_json)
    out = {}
    for tag in np.unique(tags):
        label = label_of_tag[int(tag)]
        x = points[np.unique(tris[tags == tag])]
        d = np.min([surface_distance(f, x) for f in variant_faces[label]], axis=0)
        out[label] = max(out.get(label, 0.0), float(d.max()))
    return out


# ----------------------------------------------------------------------------
# CAD to mesh (chord error) and volume
# ----------------------------------------------------------------------------

def _boundary_polydata(mesh):
    _, tris, _ = mesh.boundary()
    used, inverse = np.unique(tris, return_inverse=True)
    poly = vtkPolyData()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(mesh.points[used]), deep=1))
    poly.SetPoints(pts)
    n = len(tris)
    conn = np.hstack([np.full((n, 1), 3, dtype=np.int64),
                      inverse.reshape(-1, 3).astype(np.int64)]).ravel()
    cells = vtkCellArray()
    cells.SetCells(n, numpy_to_vtkIdTypeArray(conn, deep=1))
    poly.SetPolys(cells)
    return poly


def cad_to_mesh(mesh, sample, sample_json=None):
    """Distances from the CAD sample's points (its vertices and triangle
    centroids) to the mesh's boundary triangles: max, 99th percentile and,
    with the sample's JSON, the max per face label."""
    if isinstance(mesh, (str, vtkUnstructuredGrid)):
        mesh = read_mesh(mesh)
    points, tris, tags = read_sample(sample) if isinstance(sample, str) else sample
    query = np.vstack([points, points[tris].mean(axis=1)])
    poly = _boundary_polydata(mesh)
    locator = vtkStaticCellLocator()
    locator.SetDataSet(poly)
    locator.BuildLocator()
    closest = [0.0, 0.0, 0.0]
    cell = vtkGenericCell()
    cell_id, sub_id, dist2 = mutable(0), mutable(0), mutable(0.0)
    d = np.empty(len(query))
    for i, p in enumerate(query.tolist()):
        locator.FindClosestPoint(p, closest, cell, cell_id, sub_id, dist2)
        d[i] = float(dist2)
    d = np.sqrt(d)
    res = {"max": float(d.max()), "p99": float(np.percentile(d, 99.0)),
           "samples": int(len(query))}
    if sample_json is not None:
        label_of_tag = {f["tag"]: f["label"] for f in sample_json["faces"]}
        vert_d = d[:len(points)]
        cent_d = d[len(points):]
        per_label = {}
        for tag in np.unique(tags):
            sel = tags == tag
            m = max(float(cent_d[sel].max()), float(vert_d[np.unique(tris[sel])].max()))
            label = label_of_tag.get(int(tag), str(tag))
            per_label[label] = max(per_label.get(label, 0.0), m)
        res["per_label"] = per_label
    return res


def chord_error(base_mesh, base_sample, base_sample_json=None):
    """cad_to_mesh of the base part against its own CAD sample."""
    return cad_to_mesh(base_mesh, base_sample, base_sample_json)


def volume(mesh):
    if isinstance(mesh, (str, vtkUnstructuredGrid)):
        mesh = read_mesh(mesh)
    return float(signed_volumes(mesh.points, mesh.tets).sum())


# ----------------------------------------------------------------------------
# Fixed faces
# ----------------------------------------------------------------------------

def boundary_face_tags(mesh, slots, tris, label_of_tag, variant_faces):
    """The CAD face tag of every boundary face of a mesh an editor changed.
    CADFace is per tet face, and an editor that makes new tets copies its
    parent's four values (cell data), so a new tet's own face order does not
    match them: the tag of a boundary face is its own CADFace value when that
    names a face whose variant surface its three vertices lie on, else the
    one among its tet's values whose variant surface is nearest to them,
    else (when that one's does not pass through them either) the nearest of
    all faces'. A face of the wrong surface still fails: its vertices lie on
    no face's."""
    cad = mesh.cad_face.reshape(-1, 4)
    own = mesh.cad_face.reshape(-1)[slots].copy()
    tets = slots // 4
    all_tags = [t for t in label_of_tag if label_of_tag[t] in variant_faces]

    def dist(tag, x):
        faces = variant_faces.get(label_of_tag.get(int(tag), None), None)
        if not faces:
            return np.full(len(x), np.inf)
        return np.min([surface_distance(f, x) for f in faces], axis=0)

    out = own.copy()
    x = mesh.points[tris]  # (n, 3, 3)
    flat = x.reshape(-1, 3)
    scale = float(np.linalg.norm(flat.max(axis=0) - flat.min(axis=0))) if len(flat) else 1.0
    # Faces whose own tag fits: keep.
    fits = np.zeros(len(slots), dtype=bool)
    for tag in np.unique(own):
        sel = own == tag
        d = dist(tag, x[sel].reshape(-1, 3)).reshape(-1, 3).max(axis=1)
        fits[np.nonzero(sel)[0]] = d <= 1e-6 * scale
    for i in np.nonzero(~fits)[0]:
        cands = [int(t) for t in cad[tets[i]] if int(t) in label_of_tag] or all_tags
        best = min(cands, key=lambda t: float(dist(t, x[i]).max()))
        if float(dist(best, x[i]).max()) > 1e-6 * scale:
            best = min(all_tags, key=lambda t: float(dist(t, x[i]).max()))
        out[i] = best
    return out


def labels_of_points(mesh, base_json):
    """Per boundary point id: the set of CAD labels of its boundary faces."""
    label_of_tag = {f["tag"]: f["label"] for f in base_json["faces"]}
    slots, tris, _ = mesh.boundary()
    tags = mesh.cad_face.reshape(-1)[slots]
    out = {}
    for tri, tag in zip(tris.tolist(), tags.tolist()):
        label = label_of_tag.get(tag, None)
        for v in tri:
            out.setdefault(v, set()).add(label)
    return out


def fixed_unchanged(base_mesh, deformed_mesh, labels, base_json):
    """The points of the base mesh lying only on faces with the given labels
    keep their coordinates bit for bit in the deformed mesh (found by
    their coordinates: an editor may renumber the points it keeps)."""
    if isinstance(base_mesh, (str, vtkUnstructuredGrid)):
        base_mesh = read_mesh(base_mesh)
    if isinstance(deformed_mesh, (str, vtkUnstructuredGrid)):
        deformed_mesh = read_mesh(deformed_mesh)
    if isinstance(base_json, str):
        base_json = load_json(base_json)
    known = {f["label"] for f in base_json["faces"]}
    unknown = sorted(set(labels) - known)
    wanted = set(labels)
    ids = np.array(sorted(v for v, ls in labels_of_points(base_mesh, base_json).items()
                          if ls <= wanted), dtype=np.int64)
    res = {"points": int(len(ids)), "unknown_labels": unknown}
    a = base_mesh.points[ids]
    # The same coordinates, bit for bit, somewhere in the deformed mesh (an
    # editor may renumber the points it keeps).
    have = {row.tobytes() for row in np.ascontiguousarray(deformed_mesh.points)}
    same = np.array([np.ascontiguousarray(row).tobytes() in have for row in a], dtype=bool)
    b = a.copy()
    res["changed"] = int(np.count_nonzero(~same))
    res["max_move"] = float(np.max(np.linalg.norm(a - b, axis=1))) if len(ids) else 0.0
    res["ok"] = res["changed"] == 0 and not unknown and len(ids) > 0
    return res


# ----------------------------------------------------------------------------
# All checks with the thresholds of the Deform tests
# ----------------------------------------------------------------------------

def variant_paths(variant):
    """(json, vtp) of a variant given as its path with or without extension."""
    stem = variant[:-5] if variant.endswith(".json") else (
        variant[:-4] if variant.endswith(".vtp") else variant)
    return stem + ".json", stem + ".vtp"


def base_paths(base_vtu, variant_json_path, base_json):
    """The base part's JSON and its CAD sample (<part>__base.vtp next to the
    variant)."""
    folder = os.path.dirname(os.path.abspath(variant_json_path))
    stem = os.path.join(folder, base_json["name"] + "__base")
    return stem + ".json", stem + ".vtp"


_CHORD_CACHE = {}


def check(base, variant, mesh, fixed_labels=None, base_chord=None, volume_scale=1.0, relabel=True):
    """Every check of the module on `mesh` (path or Mesh) against the variant
    (path stem of <part>__<variant>.json/.vtp) for the base part (.vtu path,
    its .json next to it). Returns (ok, rows): rows of (name, value, limit,
    passed). `volume_scale` multiplies the base mesh's own volume error in
    the volume bound: the chord error of a face grows with its radius at a
    given edge length (Deform keeps the edges, and Improve keeps the largest
    chord error, not the integral), so a radius change r -> r' allows about
    (r'/r)^2 times the base error."""
    base_json_path = os.path.splitext(base)[0] + ".json"
    base_json = load_json(base_json_path)
    variant_json_path, variant_vtp = variant_paths(variant)
    variant_json = load_json(variant_json_path)
    base_cad_json_path, base_vtp = base_paths(base, variant_json_path, base_json)
    base_cad_json = load_json(base_cad_json_path)
    base_mesh = read_mesh(base)
    mesh = read_mesh(mesh) if isinstance(mesh, str) else mesh

    rows = []
    val = validity(mesh)
    rows.append(("inverted tets", val.get("inverted", -1), 0, val.get("inverted", 1) == 0))
    rows.append(("non-conforming faces / open boundary edges",
                 f"{val.get('faces_in_more_than_two_tets', -1)} / "
                 f"{val.get('boundary_edges_not_in_two_triangles', -1)}", "0 / 0",
                 val.get("faces_in_more_than_two_tets", 1) == 0
                 and val.get("boundary_edges_not_in_two_triangles", 1) == 0))
    rows.append(("unused points / other cells",
                 f"{val.get('unused_points', -1)} / {val.get('non_tetra_cells', -1)}", "0 / 0",
                 val.get("unused_points", 1) == 0 and val.get("non_tetra_cells", 1) == 0))
    smin = val.get("stretch_min", float("nan"))
    rows.append(("stretch min (mean)", f"{smin:.4f} ({val.get('stretch_mean', float('nan')):.4f})",
                 f">= {MIN_STRETCH}", smin >= MIN_STRETCH))

    surf = on_surfaces(mesh, variant_json, base_json, relabel=relabel)
    rows.append(("boundary vertices on variant surfaces (mm)", f"{surf['max']:.3e}",
                 f"<= {surf['tol']:.3e}", surf["ok"]))

    key = (os.path.abspath(base), os.path.abspath(base_vtp))
    if base_chord is None:
        if key not in _CHORD_CACHE:
            _CHORD_CACHE[key] = chord_error(base_mesh, base_vtp, base_cad_json)
        base_chord = _CHORD_CACHE[key]
    c2m = cad_to_mesh(mesh, variant_vtp, variant_json)
    c2m_limit = CHORD_FACTOR * base_chord["max"] + CHORD_FLOOR_REL * diagonal(variant_json)
    rows.append(("CAD to mesh max (p99) (mm)", f"{c2m['max']:.4f} ({c2m['p99']:.4f})",
                 f"<= {c2m_limit:.4f}", c2m["max"] <= c2m_limit))

    v = volume(mesh)
    v_cad = variant_json["cad_volume"]
    v_base_err = abs(volume(base_mesh) - base_cad_json["cad_volume"])
    limit = v_base_err * volume_scale + VOLUME_REL_SLACK * abs(v_cad)
    rows.append(("|V - V_cad| (mm^3)", f"{abs(v - v_cad):.4f} (V {v:.3f}, CAD {v_cad:.3f})",
                 f"<= {limit:.4f}", abs(v - v_cad) <= limit))

    if fixed_labels:
        fx = fixed_unchanged(base_mesh, mesh, fixed_labels, base_json)
        rows.append((f"fixed points unchanged ({fx['points']})", fx["changed"], 0, fx["ok"]))

    details = {"validity": val, "on_surfaces": surf, "cad_to_mesh": c2m,
               "base_chord_error": base_chord, "cad_to_mesh_limit": c2m_limit, "volume": v, "cad_volume": v_cad,
               "base_volume_error": v_base_err}
    return all(r[3] for r in rows), rows, details


def print_rows(rows, out=sys.stdout):
    w0 = max(len(r[0]) for r in rows)
    w1 = max(len(str(r[1])) for r in rows)
    w2 = max(len(str(r[2])) for r in rows)
    for name, value, limit, ok in rows:
        print(f"{name:<{w0}}  {str(value):>{w1}}  {str(limit):<{w2}}  "
              f"{'ok' if ok else 'FAILED'}", file=out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", required=True, help="the base part's .vtu (its .json next to it)")
    parser.add_argument("--variant", required=True,
                        help="the variant, Data/variants/<part>__<variant> (.json/.vtp)")
    parser.add_argument("--mesh", required=True, help="the deformed mesh (.vtu, with CADFace)")
    parser.add_argument("--fixed-labels", nargs="*", default=None,
                        help="CAD face labels whose points must not move")
    parser.add_argument("--details", action="store_true",
                        help="print the per-label distances as well")
    args = parser.parse_args()
    ok, rows, details = check(args.base, args.variant, args.mesh, args.fixed_labels)
    print(f"{args.mesh} against {os.path.basename(variant_paths(args.variant)[0])}")
    print_rows(rows)
    if args.details:
        print("on surfaces, per label:")
        for label, d in sorted(details["on_surfaces"]["per_label"].items()):
            print(f"  {label:<40} {d:.3e}")
        print("CAD to mesh, per label (base chord error):")
        base = details["base_chord_error"].get("per_label", {})
        for label, d in sorted(details["cad_to_mesh"].get("per_label", {}).items()):
            print(f"  {label:<40} {d:.4f} ({base.get(label, float('nan')):.4f})")
    print("PASSED" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
