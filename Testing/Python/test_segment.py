"""pvbatch test of FEMorph Segment through the plugin, on a Data/ part.

Loads the plugin, segments the part (Data/boss_block.vtu by default) and
checks the three outputs against the part's construction in the .json next to
it (written by Data/generate_parts.py from the CAD model; for a STEP file made
by others, `generate_parts.py --step`, the faces' primitives and parameters
come from fits of their nodes):
  output 2 (table): exactly the columns of docs/ARCHITECTURE.md; one row per
      CAD face, each matched one-to-one to a face of the same type with its
      parameters (radius, torus radii, cone half angle and apex, axes, plane
      normals), convexity and area (when several regions match, e.g. two
      coaxial cylinders of one radius or two unknown faces, the one holding
      most of the face's triangles by the input's CADFace); NaN in the
      columns that do not apply; neighbours symmetric; the triangle counts
      add up to the boundary;
  output 0 (mesh): FaceRegion on exactly the boundary faces, VertexClass,
      the field arrays (RegionType/RegionParameters agreeing with the table,
      curve arrays consistent, curves of the CAD model's types);
  output 1 (surface): RegionId/RegionType per triangle agreeing with output
      0's FaceRegion, the curves as polylines agreeing with CurveVertices,
      MeshPointId pointing at the same positions.
And the proxy as the GUI shows it (label, menu, port names, defaults), and
that a second run with the same seed gives the same table.

Usage: pvbatch test_segment.py --plugin FEMorph.so [--data Data/boss_block.vtu]
"""
import argparse
import json
import math
import os
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import LoadPlugin, XMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_LINE, VTK_POLY_LINE, VTK_TETRA, VTK_TRIANGLE

COLUMNS = ["RegionId", "TypeName", "Radius", "MajorRadius", "MinorRadius", "HalfAngle", "Axis",
           "Center", "Apex", "Normal", "Point", "Area", "Convexity", "TriangleCount",
           "FitResidual", "Neighbors"]
TYPE_CODES = {"plane": 0, "cylinder": 1, "cone": 2, "sphere": 3, "torus": 4, "unknown": 5}
# Gmsh's curve types -> FEMorph's CurveType codes (Core/geometry/curve_primitive.h):
# Gmsh calls full circles and circular arcs "Circle".
CURVE_CODES = {"Line": (0,), "Circle": (1, 2)}
LINE, CIRCLE, CIRCULAR_ARC = 0, 1, 2
# Which table columns apply to which type (docs/ARCHITECTURE.md); the others are NaN.
APPLIES = {
    "plane": {"Normal", "Point"},
    "cylinder": {"Radius", "Axis", "Center"},
    "cone": {"HalfAngle", "Axis", "Apex"},
    "sphere": {"Radius", "Center"},
    "torus": {"MajorRadius", "MinorRadius", "Axis", "Center"},
    "unknown": set(),
}
NUMERIC = ["Radius", "MajorRadius", "MinorRadius", "HalfAngle", "Axis", "Center", "Apex",
           "Normal", "Point"]
DEFAULTS = {"SharpAngle": 30.0, "CylinderAngleTolerance": 1.5, "ConeAngleTolerance": 0.8,
            "SphereDirectionAngle": 60.0, "DistanceTolerance": 0.01, "RansacIterations": 500,
            "RandomSeed": 1, "RefineFits": 1,
            "AdaptiveTolerance": 1}

# Points where three or more curves meet, by part (the .json does not list them).
CORNERS = {"boss_block": 8}

# Tolerances of the fits: Gmsh puts the nodes on the CAD surfaces (the .json's
# max_node_distance is ~1e-15), so the fits can be close.
RADIUS_RTOL = 5e-3        # radii, relative
POSITION_TOL = 0.05       # mm: apex, centres, axis lines, plane offsets
ANGLE_TOL_DEG = 0.5       # cone half angle, axis and normal directions
AREA_RTOL = 0.03          # region area against the CAD face's


def fail(message):
    print("FAILED: " + message)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def angle_deg(a, b, signed=False):
    c = float(np.dot(unit(a), unit(b)))
    if not signed:
        c = abs(c)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def line_distance(point, line_point, direction):
    d = np.asarray(point, dtype=float) - np.asarray(line_point, dtype=float)
    u = unit(direction)
    return float(np.linalg.norm(d - np.dot(d, u) * u))


def rel(a, b):
    return abs(a - b) / abs(b)


# --------------------------------------------------------------------------
# Output 2: the region table.

def table_rows(table):
    names = [table.GetColumnName(i) for i in range(table.GetNumberOfColumns())]
    check(names == COLUMNS, "table columns %r != %r" % (names, COLUMNS))
    rows = []
    for r in range(table.GetNumberOfRows()):
        row = {}
        for name in COLUMNS:
            column = table.GetColumnByName(name)
            if name in ("TypeName", "Convexity", "Neighbors"):
                check(column.IsA("vtkStringArray"), "%s is not a string column" % name)
                row[name] = column.GetValue(r)
            else:
                check(column.IsA("vtkDataArray"), "%s is not numeric" % name)
                n = column.GetNumberOfComponents()
                check(n == (3 if name in ("Axis", "Center", "Apex", "Normal", "Point") else 1),
                      "%s has %d components" % (name, n))
                t = column.GetTuple(r)
                row[name] = np.array(t) if n == 3 else t[0]
        rows.append(row)
    return rows


def face_matches(face, row):
    """Whether the table row is the CAD face (type and parameters)."""
    kind = face["primitive"]
    if row["TypeName"] != kind:
        return False
    if kind == "plane":
        return (angle_deg(row["Normal"], face["normal"]) < ANGLE_TOL_DEG and
                abs(np.dot(unit(row["Normal"]), np.subtract(face["point"], row["Point"])))
                < POSITION_TOL)
    if kind == "cylinder":
        return (rel(row["Radius"], face["radius"]) < RADIUS_RTOL and
                angle_deg(row["Axis"], face["axis_direction"]) < ANGLE_TOL_DEG and
                line_distance(face["axis_point"], row["Center"], row["Axis"]) < POSITION_TOL)
    if kind == "cone":
        # The apex is a point, and the axis points from it into the cone.
        return (abs(row["HalfAngle"] - face["half_angle_deg"]) < ANGLE_TOL_DEG and
                np.linalg.norm(np.subtract(row["Apex"], face["apex"])) < POSITION_TOL and
                angle_deg(row["Axis"], face["axis_direction"], signed=True) < ANGLE_TOL_DEG)
    if kind == "sphere":
        return (rel(row["Radius"], face["radius"]) < RADIUS_RTOL and
                np.linalg.norm(np.subtract(row["Center"], face["center"])) < POSITION_TOL)
    if kind == "torus":
        return (rel(row["MajorRadius"], face["major_radius"]) < RADIUS_RTOL and
                rel(row["MinorRadius"], face["minor_radius"]) < RADIUS_RTOL and
                angle_deg(row["Axis"], face["axis_direction"]) < ANGLE_TOL_DEG and
                np.linalg.norm(np.subtract(row["Center"], face["center"])) < POSITION_TOL)
    # A freeform face has no parameters to compare: the area check below
    # tells unknown regions apart.
    return kind == "unknown"


def describe(row):
    keep = ["TypeName"] + sorted(APPLIES[row["TypeName"]]) + ["Area", "Convexity"]
    return ", ".join("%s=%s" % (k, np.round(row[k], 4) if not isinstance(row[k], str)
                                else row[k]) for k in keep)


def check_table(rows, part, overlap, edge):
    """overlap[tag][region]: how many triangles of CAD face `tag` the
    segmentation put in `region`."""
    faces = part["faces"]
    print("  regions: %s" % ", ".join(
        "%d %s" % (sum(r["TypeName"] == t for r in rows), t) for t in TYPE_CODES
        if any(r["TypeName"] == t for r in rows)))
    expected_types = part["counts"]["surfaces_by_type"]
    found_types = {t: sum(r["TypeName"] == t for r in rows) for t in TYPE_CODES}
    for t in TYPE_CODES:
        check(found_types[t] == expected_types.get(t, 0),
              "%d %s regions, the part has %d:\n    %s" % (
                  found_types[t], t, expected_types.get(t, 0),
                  "\n    ".join(describe(r) for r in rows)))
    check(len(rows) == len(faces), "%d regions for %d CAD faces" % (len(rows), len(faces)))

    # Every CAD face matched to its own region.
    match = {}
    for face in faces:
        candidates = [i for i, r in enumerate(rows) if face_matches(face, r) and i not in
                      match.values()]
        mine = overlap.get(face["tag"], {})
        if len(candidates) > 1:
            # Faces on one surface (two coaxial cylinders of one radius, two
            # unknown faces): the region holding most of the face's triangles,
            # which must be most of them.
            best = max(candidates, key=lambda i: mine.get(i, 0))
            check(mine.get(best, 0) > 0.5 * face["triangle_count"],
                  "CAD face %d (%s, %s) matches regions %r, none holding most of its %d "
                  "triangles (%r)" % (face["tag"], face["label"], face["primitive"], candidates,
                                      face["triangle_count"], mine))
            candidates = [best]
        check(len(candidates) == 1, "CAD face %d (%s, %s) matches regions %r:\n    %s" % (
            face["tag"], face["label"], face["primitive"], candidates,
            "\n    ".join(describe(r) for r in rows if r["TypeName"] == face["primitive"])))
        match[face["tag"]] = candidates[0]
        row = rows[candidates[0]]
        # FEMorph gives no convexity for planes and unknown regions.
        convexity = ("" if face["convexity"] in ("flat", "mixed") or
                     face["primitive"] == "unknown" else face["convexity"])
        check(row["Convexity"] == convexity, "%s: convexity %r, expected %r" % (
            face["label"], row["Convexity"], convexity))
        check(rel(row["Area"], face["area"]) < AREA_RTOL, "%s: area %.3f, CAD %.3f" % (
            face["label"], row["Area"], face["area"]))
        print("  %-18s region %2d: %s" % (face["label"], candidates[0], describe(row)))

    for i, row in enumerate(rows):
        check(row["RegionId"] == i, "row %d has RegionId %r" % (i, row["RegionId"]))
        for name in NUMERIC:
            value = np.atleast_1d(row[name])
            if name in APPLIES[row["TypeName"]]:
                check(np.isfinite(value).all(), "region %d (%s): %s is %r" % (
                    i, row["TypeName"], name, row[name]))
            else:
                check(np.isnan(value).all(), "region %d (%s): %s should be NaN, is %r" % (
                    i, row["TypeName"], name, row[name]))
        if row["TypeName"] == "unknown":
            check(np.isnan(row["FitResidual"]), "region %d (unknown): FitResidual %r" % (
                i, row["FitResidual"]))
        else:
            check(np.isfinite(row["FitResidual"]) and row["FitResidual"] >= 0,
                  "region %d: FitResidual %r" % (i, row["FitResidual"]))
        check(row["TriangleCount"] > 0, "region %d has no triangles" % i)
    total = sum(int(r["TriangleCount"]) for r in rows)
    check(total == part["counts"]["boundary_triangles"], "triangle counts add up to %d, not %d" % (
        total, part["counts"]["boundary_triangles"]))

    # Neighbours: symmetric, and those of the CAD model (faces sharing a curve).
    neighbors = [set(int(n) for n in r["Neighbors"].split()) for r in rows]
    for i, n in enumerate(neighbors):
        for j in n:
            check(0 <= j < len(rows) and i in neighbors[j], "neighbours not symmetric: %d %d" % (
                i, j))
    for curve in part["curves"]:
        tags = sorted(set(curve["surfaces"]))
        if len(tags) == 2 and not curve["degenerate"]:
            a, b = match[tags[0]], match[tags[1]]
            if curve["length"] < edge and b not in neighbors[a]:
                # A curve shorter than a mesh edge is one edge of the mesh at
                # most: below what the segmentation resolves (documented).
                print("  curve %d between faces %d and %d (length %.3g < edge %.3g) not resolved"
                      % (curve["tag"], tags[0], tags[1], curve["length"], edge))
                continue
            check(b in neighbors[a], "regions %d and %d (CAD faces %d, %d) are not neighbours" % (
                a, b, tags[0], tags[1]))
    return match


# --------------------------------------------------------------------------
# Output 0: the mesh.

def field(grid, name, components=None):
    array = grid.GetFieldData().GetAbstractArray(name)
    check(array is not None, "field data %s missing" % name)
    if components is not None:
        check(array.GetNumberOfComponents() == components, "%s has %d components" % (
            name, array.GetNumberOfComponents()))
    return vtk_to_numpy(array)


def boundary_faces(points, tets):
    """Faces with one tet: {sorted point triple: (tet, local vertex opposite)}."""
    count = {}
    for t, tet in enumerate(tets):
        for i in range(4):
            key = tuple(sorted(int(tet[k]) for k in range(4) if k != i))
            count.setdefault(key, []).append((t, i))
    return {k: v[0] for k, v in count.items() if len(v) == 1}


def check_mesh(mesh, grid, rows, part):
    check(mesh.GetNumberOfCells() == grid.GetNumberOfCells(), "cells changed")
    check(mesh.GetNumberOfPoints() == grid.GetNumberOfPoints(), "points changed")
    tets = vtk_to_numpy(mesh.GetCells().GetConnectivityArray()).reshape(-1, 4)
    check((vtk_to_numpy(mesh.GetCellTypesArray()) == VTK_TETRA).all(), "not all tets")
    face_region = mesh.GetCellData().GetArray("FaceRegion")
    check(face_region is not None and face_region.GetNumberOfComponents() == 4,
          "FaceRegion missing or not 4 components")
    face_region = vtk_to_numpy(face_region).reshape(-1, 4)
    boundary = boundary_faces(None, tets)
    check(len(boundary) == part["counts"]["boundary_triangles"], "%d boundary faces" % len(
        boundary))
    on_boundary = np.zeros_like(face_region, dtype=bool)
    for t, i in boundary.values():
        on_boundary[t, i] = True
    check((face_region[on_boundary] >= 0).all(), "a boundary face has no region")
    check((face_region[on_boundary] < len(rows)).all(), "a region id out of range")
    check((face_region[~on_boundary] == -1).all(), "an interior face has a region")
    counts = np.bincount(face_region[on_boundary], minlength=len(rows))
    for r, row in enumerate(rows):
        check(counts[r] == row["TriangleCount"], "region %d: %d faces, table says %d" % (
            r, counts[r], row["TriangleCount"]))

    vertex_class = mesh.GetPointData().GetArray("VertexClass")
    check(vertex_class is not None, "VertexClass missing")
    vertex_class = vtk_to_numpy(vertex_class)
    surface_points = np.unique(np.array(list(boundary.keys())).ravel())
    inner = np.ones(len(vertex_class), dtype=bool)
    inner[surface_points] = False
    check((vertex_class[inner] == 0).all(), "an inner point is not class 0")
    check((vertex_class[surface_points] >= 1).all(), "a surface point has class 0")
    corners = int((vertex_class == 3).sum())
    print("  vertex classes: %d inner, %d surface, %d curve, %d corner" % tuple(
        int((vertex_class == c).sum()) for c in range(4)))
    if part["name"] in CORNERS:
        check(corners == CORNERS[part["name"]], "%d corner points; the part has %d" % (
            corners, CORNERS[part["name"]]))

    region_type = field(mesh, "RegionType", 1)
    region_parameters = field(mesh, "RegionParameters", 12).reshape(-1, 12)
    region_convexity = field(mesh, "RegionConvexity", 1)
    check(len(region_type) == len(rows) == len(region_parameters) == len(region_convexity),
          "region field arrays of different lengths")
    for r, row in enumerate(rows):
        check(region_type[r] == TYPE_CODES[row["TypeName"]], "RegionType[%d] = %d" % (
            r, region_type[r]))
        p = region_parameters[r]
        check(math.isclose(p[11], row["Area"], rel_tol=1e-12), "RegionParameters area %d" % r)
        if row["TypeName"] in ("cylinder", "sphere"):
            check(math.isclose(p[6], row["Radius"], rel_tol=1e-12), "radius of %d" % r)
        if row["TypeName"] == "cone":
            check(math.isclose(math.degrees(p[8]), row["HalfAngle"], rel_tol=1e-12),
                  "half angle of %d" % r)
        convexity = {"": 0, "convex": 1, "concave": 2}[row["Convexity"]]
        check(region_convexity[r] == convexity and p[9] == convexity, "convexity of %d" % r)

    curve_type = field(mesh, "CurveType", 1)
    curve_parameters = field(mesh, "CurveParameters", 20).reshape(-1, 20)
    curve_closed = field(mesh, "CurveClosed", 1)
    curve_vertices = field(mesh, "CurveVertices", 1)
    curve_offsets = field(mesh, "CurveOffsets", 1)
    n = len(curve_type)
    check(len(curve_parameters) == n and len(curve_closed) == n and len(curve_offsets) == n + 1,
          "curve field arrays of different lengths")
    check(curve_offsets[0] == 0 and curve_offsets[-1] == len(curve_vertices) and
          (np.diff(curve_offsets) >= 2).all(), "CurveOffsets malformed")
    check(((curve_vertices >= 0) & (curve_vertices < mesh.GetNumberOfPoints())).all(),
          "CurveVertices out of range")
    check((vertex_class[curve_vertices] >= 2).all(), "a curve vertex is not a curve or corner")
    for c in range(n):
        a, b = curve_parameters[c][17:19]
        check(0 <= a < len(rows) and 0 <= b < len(rows) and a != b,
              "curve %d separates regions %r and %r" % (c, a, b))
    expected = {}
    for curve in part["curves"]:
        if len(set(curve["surfaces"])) == 2 and not curve["degenerate"]:
            expected[curve["gmsh_type"]] = expected.get(curve["gmsh_type"], 0) + 1
    found = {name: int(np.isin(curve_type, codes).sum()) for name, codes in CURVE_CODES.items()}
    closed = curve_closed != 0
    check(closed[curve_type == CIRCLE].all(), "a circle is not a closed curve")
    check(not closed[np.isin(curve_type, (LINE, CIRCULAR_ARC))].any(),
          "a line or circular arc is a closed curve")
    print("  curves: %d (%s), expected %s" % (n, ", ".join(
        "%d %s" % (v, k) for k, v in found.items()), expected))
    # OpenCASCADE's "TrimmedCurve" is a trimmed basis curve (here circular
    # arcs); the .json does not say which, so such curves may be counted as
    # circles/arcs or as other types.
    trimmed = expected.get("TrimmedCurve", 0)
    for name, count in expected.items():
        if name not in CURVE_CODES:
            continue
        slack = trimmed if name == "Circle" else 0
        if name == "Line":
            # A B-spline curve may be straight (a plane cutting an extruded
            # freeform face), and is then recognised as a line.
            slack = sum(1 for c in part["curves"] if c["gmsh_type"] == "BSpline" and
                        len(set(c["surfaces"])) == 2 and not c["degenerate"])
        # Curves of one type between the same two faces (a circle cut at a
        # seam into two arcs) may come out as one.
        of_type = [tuple(sorted(set(c["surfaces"]))) for c in part["curves"]
                   if c["gmsh_type"] == name and not c["degenerate"]]
        split = len(of_type) - len(set(of_type))
        check(count - split <= found.get(name, 0) <= count + slack,
              "%d %s curves, the part has %d%s%s" % (
                  found.get(name, 0), name, count, " (+%d trimmed or B-spline)" % slack if slack else "",
                  " (-%d seam splits)" % split if split else ""))
    # OpenCASCADE splits a closed curve at a seam vertex into several; the
    # segmentation sees one loop. So: at most the CAD's count, at least one
    # per pair of adjacent faces.
    pairs = {tuple(sorted(set(c["surfaces"]))) for c in part["curves"]
             if len(set(c["surfaces"])) == 2 and not c["degenerate"]}
    check(len(pairs) <= n <= sum(expected.values()), "%d curves, the part has %d (%d face pairs)" % (
        n, sum(expected.values()), len(pairs)))
    times = mesh.GetFieldData().GetArray("SegmentationTimes")
    check(times is not None and times.GetNumberOfTuples() == 1, "SegmentationTimes missing")
    print("  segmentation time: %.2f s" % times.GetComponent(0, times.GetNumberOfComponents() - 1))
    return face_region, tets, curve_type, curve_closed, curve_vertices, curve_offsets


# --------------------------------------------------------------------------
# Output 1: the surface.

def check_surface(surface, mesh, rows, face_region, tets, curves):
    curve_type, curve_closed, curve_vertices, curve_offsets = curves
    n_curves = len(curve_type)
    n_faces = int(sum(r["TriangleCount"] for r in rows))
    check(surface.GetNumberOfPolys() == n_faces, "%d triangles, %d boundary faces" % (
        surface.GetNumberOfPolys(), n_faces))
    check(surface.GetNumberOfLines() == n_curves, "%d lines, %d curves" % (
        surface.GetNumberOfLines(), n_curves))
    cd, pd = surface.GetCellData(), surface.GetPointData()
    arrays = {}
    for name in ("RegionId", "RegionType", "CurveId", "CurveType"):
        check(cd.GetArray(name) is not None, "surface cell array %s missing" % name)
        arrays[name] = vtk_to_numpy(cd.GetArray(name))
    check(pd.GetArray("MeshPointId") is not None, "MeshPointId missing")
    check(pd.GetArray("VertexClass") is not None, "surface VertexClass missing")
    mesh_point = vtk_to_numpy(pd.GetArray("MeshPointId"))
    positions = vtk_to_numpy(surface.GetPoints().GetData())
    mesh_positions = vtk_to_numpy(mesh.GetPoints().GetData())
    check(np.array_equal(positions, mesh_positions[mesh_point]), "MeshPointId positions differ")
    check(np.array_equal(vtk_to_numpy(pd.GetArray("VertexClass")),
                         vtk_to_numpy(mesh.GetPointData().GetArray("VertexClass"))[mesh_point]),
          "surface VertexClass differs from the mesh's")

    # Region of each boundary face from output 0, keyed by its points.
    region_of = {}
    for t, i in zip(*np.nonzero(face_region >= 0)):
        key = tuple(sorted(int(tets[t][k]) for k in range(4) if k != i))
        region_of[key] = int(face_region[t][i])
    types = [TYPE_CODES[r["TypeName"]] for r in rows]
    lines = polys = 0
    for c in range(surface.GetNumberOfCells()):
        cell_type = surface.GetCellType(c)
        ids = surface.GetCell(c).GetPointIds()
        points = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
        if cell_type == VTK_TRIANGLE:
            region = arrays["RegionId"][c]
            key = tuple(sorted(int(mesh_point[p]) for p in points))
            check(region_of.get(key) == region, "triangle %d: RegionId %d, FaceRegion %r" % (
                c, region, region_of.get(key)))
            check(arrays["RegionType"][c] == types[region], "triangle %d RegionType" % c)
            check(arrays["CurveId"][c] == -1 and arrays["CurveType"][c] == -1,
                  "triangle %d has curve ids" % c)
            polys += 1
        else:
            # vtkPolyData calls a two-point line VTK_LINE.
            check(cell_type in (VTK_POLY_LINE, VTK_LINE), "cell %d has type %d" % (c, cell_type))
            k = arrays["CurveId"][c]
            check(0 <= k < n_curves and arrays["CurveType"][c] == curve_type[k],
                  "line %d: CurveId %d" % (c, k))
            check(arrays["RegionId"][c] == -1 and arrays["RegionType"][c] == -1,
                  "line %d has region ids" % c)
            expected = list(curve_vertices[curve_offsets[k]:curve_offsets[k + 1]])
            if curve_closed[k]:
                expected.append(expected[0])
            check([int(mesh_point[p]) for p in points] == [int(v) for v in expected],
                  "polyline %d differs from CurveVertices" % k)
            lines += 1
    check(lines == n_curves and polys == n_faces, "cell counts")


# --------------------------------------------------------------------------

def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True, help="path of FEMorph.so")
    parser.add_argument("--data", default=os.path.join(here, "..", "..", "Data", "boss_block.vtu"),
                        help="a part with its .json (Data/, or generate_parts.py --step)")
    args = parser.parse_args()
    with open(os.path.splitext(args.data)[0] + ".json") as f:
        part = json.load(f)

    ns = globals()
    LoadPlugin(args.plugin, ns=ns)
    check("FEMorphSegment" in ns, "FEMorphSegment is not defined: the plugin did not load")
    reader = XMLUnstructuredGridReader(FileName=[args.data])
    reader.UpdatePipeline()
    grid = servermanager.Fetch(reader)

    segment = ns["FEMorphSegment"](Input=reader)
    for name, value in DEFAULTS.items():
        check(segment.GetPropertyValue(name) == value, "default %s = %r, expected %r" % (
            name, segment.GetPropertyValue(name), value))
    proxy = segment.SMProxy
    check(proxy.GetXMLLabel() == "FEMorph Segment", proxy.GetXMLLabel())
    hints = proxy.GetHints()
    menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
    check(menu is not None and menu.GetAttribute("category") == "FEMorph", "menu category")
    check(proxy.GetNumberOfOutputPorts() == 3, "%d output ports" % proxy.GetNumberOfOutputPorts())
    names = [proxy.GetOutputPortName(i) for i in range(3)]
    check(names == ["Mesh", "Surface", "Regions"], "output port names %r" % names)
    doc = proxy.GetDocumentation().GetDescription()
    for name in ["FaceRegion", "VertexClass", "RegionType", "RegionParameters", "CurveType",
                 "RegionId", "MeshPointId"] + COLUMNS:
        check(name in doc, "the filter's help does not mention %s" % name)

    print("%s (%d points, %d tets):" % (os.path.basename(args.data), grid.GetNumberOfPoints(),
                                        grid.GetNumberOfCells()))
    segment.UpdatePipeline()
    mesh = servermanager.Fetch(segment, idx=0)
    surface = servermanager.Fetch(segment, idx=1)
    table = servermanager.Fetch(segment, idx=2)
    check(mesh.IsA("vtkUnstructuredGrid"), "output 0 is a %s" % mesh.GetClassName())
    check(surface.IsA("vtkPolyData"), "output 1 is a %s" % surface.GetClassName())
    check(table.IsA("vtkTable"), "output 2 is a %s" % table.GetClassName())

    rows = table_rows(table)
    # Triangles of each CAD face (the input's CADFace) per region (FaceRegion).
    check(np.array_equal(vtk_to_numpy(mesh.GetCells().GetConnectivityArray()),
                         vtk_to_numpy(grid.GetCells().GetConnectivityArray())), "cells changed")
    cad_face = vtk_to_numpy(grid.GetCellData().GetArray("CADFace")).reshape(-1)
    face_region = mesh.GetCellData().GetArray("FaceRegion")
    check(face_region is not None, "FaceRegion missing")
    face_region = vtk_to_numpy(face_region).reshape(-1)
    overlap = {}
    for tag, region in zip(cad_face[cad_face >= 0], face_region[cad_face >= 0]):
        counts = overlap.setdefault(int(tag), {})
        counts[int(region)] = counts.get(int(region), 0) + 1
    points = vtk_to_numpy(grid.GetPoints().GetData())
    tet_points = points[vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)]
    mean_edge = np.mean([np.linalg.norm(tet_points[:, i] - tet_points[:, j], axis=1).mean()
                         for i in range(4) for j in range(i + 1, 4)])
    check_table(rows, part, overlap, mean_edge)
    face_region, tets, *curves = check_mesh(mesh, grid, rows, part)
    check_surface(surface, mesh, rows, face_region, tets, curves)

    # The input's arrays pass through; the input itself is unchanged.
    for i in range(grid.GetPointData().GetNumberOfArrays()):
        name = grid.GetPointData().GetArrayName(i)
        check(mesh.GetPointData().GetArray(name) is not None, "point array %s lost" % name)
    check(servermanager.Fetch(reader).GetCellData().GetArray("FaceRegion") is None,
          "the input was modified")

    # Same seed, same result.
    again = ns["FEMorphSegment"](Input=reader, RandomSeed=1)
    again.UpdatePipeline()
    rows_again = table_rows(servermanager.Fetch(again, idx=2))
    check(len(rows_again) == len(rows), "a second run gives %d regions" % len(rows_again))
    for a, b in zip(rows, rows_again):
        for name in COLUMNS:
            same = (a[name] == b[name]) if isinstance(a[name], str) else np.array_equal(
                np.atleast_1d(a[name]), np.atleast_1d(b[name]), equal_nan=True)
            check(same, "a second run differs in %s: %r != %r" % (name, a[name], b[name]))
    print("OK")


if __name__ == "__main__":
    main()
