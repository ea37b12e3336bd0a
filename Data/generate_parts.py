#!/usr/bin/python3
"""Build the CAD test parts of FEMorph and mesh them with linear tetrahedra.

Run with Debian's interpreter (python3-gmsh, python3-numpy and python3-paraview
are Debian packages that a pyenv python cannot see):

    /usr/bin/python3 Data/generate_parts.py [--out-dir Data] [--only NAME]

For every part it writes <name>.vtu (tets, CAD face labels per tet face, CAD
entity of every node) and <name>.json (construction dimensions, mesh options,
counts, and one entry per CAD surface with its exact analytic parameters).
Because the parts are built from primitives whose parameters we chose, the
integration tests of the segmentation (thesis 2.4) and the deformation
(thesis 2.5) can compare fitted types and radii against known truth.

The output is deterministic: one thread, fixed mesh options, nodes numbered
in Gmsh's tag order. Data/README.md describes the file formats.
"""

import argparse
import json
import math
import os
import sys

import numpy as np
import gmsh

# python3-paraview puts vtkmodules in dist-packages; make sure it is found
# even when PYTHONPATH points elsewhere.
sys.path.append("/usr/lib/python3/dist-packages")
try:
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import (VTK_TETRA, vtkCellArray,
                                               vtkUnstructuredGrid)
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    HAVE_VTK = True
except ImportError:  # fall back to writing the XML ourselves
    HAVE_VTK = False

VTK_TETRA_TYPE = 10
GMSH_TET = 4        # Gmsh element type: 4-node tetrahedron
GMSH_TRIANGLE = 2   # Gmsh element type: 3-node triangle

# Gmsh surface type -> FEMorph primitive name (DESIGN.md "RegionType" codes).
PRIMITIVE_OF_GMSH_TYPE = {
    "Plane": "plane",
    "Cylinder": "cylinder",
    "Cone": "cone",
    "Sphere": "sphere",
    "Torus": "torus",
}

# Options shared by all parts. Frontal-Delaunay surfaces, Delaunay volumes and
# a single thread: Gmsh's multi-threaded 3D meshing is not repeatable.
COMMON_MESH_OPTIONS = {
    "General.NumThreads": 1,
    "Mesh.MaxNumThreads1D": 1,
    "Mesh.MaxNumThreads2D": 1,
    "Mesh.MaxNumThreads3D": 1,
    "Mesh.Algorithm": 6,
    "Mesh.Algorithm3D": 1,
    "Mesh.ElementOrder": 1,
    "Mesh.Optimize": 1,
    "Mesh.OptimizeNetgen": 0,
    "Mesh.MeshSizeFromPoints": 0,
    "Mesh.MeshSizeExtendFromBoundary": 1,
    "Mesh.RandomSeed": 1,
}


# ----------------------------------------------------------------------------
# Analytic surfaces: construction parameters and point-to-surface distance
# ----------------------------------------------------------------------------

def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def plane(label, point, normal, convexity="flat"):
    """normal points out of the material."""
    return {"label": label, "primitive": "plane", "convexity": convexity,
            "point": list(map(float, point)), "normal": list(map(float, unit(normal)))}


def cylinder(label, axis_point, axis_direction, radius, convexity):
    return {"label": label, "primitive": "cylinder", "convexity": convexity,
            "axis_point": list(map(float, axis_point)),
            "axis_direction": list(map(float, unit(axis_direction))),
            "radius": float(radius)}


def cone(label, apex, axis_direction, half_angle_deg, convexity):
    """axis_direction points from the apex into the cone (radius grows)."""
    return {"label": label, "primitive": "cone", "convexity": convexity,
            "apex": list(map(float, apex)),
            "axis_direction": list(map(float, unit(axis_direction))),
            "half_angle_deg": float(half_angle_deg)}


def sphere(label, center, radius, convexity):
    return {"label": label, "primitive": "sphere", "convexity": convexity,
            "center": list(map(float, center)), "radius": float(radius)}


def torus(label, center, axis_direction, major_radius, minor_radius, convexity):
    return {"label": label, "primitive": "torus", "convexity": convexity,
            "center": list(map(float, center)),
            "axis_direction": list(map(float, unit(axis_direction))),
            "major_radius": float(major_radius), "minor_radius": float(minor_radius)}


def axial_split(x, origin, direction):
    """Height along the axis and distance from the axis, per point."""
    v = x - np.asarray(origin)
    d = np.asarray(direction)
    h = v @ d
    rho = np.linalg.norm(v - np.outer(h, d), axis=1)
    return h, rho


def distance_to_surface(surf, x):
    """Unsigned distance of points x (n x 3) to the unbounded analytic surface."""
    kind = surf["primitive"]
    if kind == "plane":
        return np.abs((x - np.asarray(surf["point"])) @ np.asarray(surf["normal"]))
    if kind == "cylinder":
        _, rho = axial_split(x, surf["axis_point"], surf["axis_direction"])
        return np.abs(rho - surf["radius"])
    if kind == "cone":
        h, rho = axial_split(x, surf["apex"], surf["axis_direction"])
        a = math.radians(surf["half_angle_deg"])
        # Distance to the generating line rho = h tan(a) in the meridian half-plane.
        return np.abs(rho * math.cos(a) - h * math.sin(a))
    if kind == "sphere":
        return np.abs(np.linalg.norm(x - np.asarray(surf["center"]), axis=1) - surf["radius"])
    if kind == "torus":
        h, rho = axial_split(x, surf["center"], surf["axis_direction"])
        return np.abs(np.hypot(rho - surf["major_radius"], h) - surf["minor_radius"])
    raise ValueError(kind)


# ----------------------------------------------------------------------------
# Gmsh helpers
# ----------------------------------------------------------------------------

def entities_in_box(dim, lo, hi, eps=1e-3):
    """Entities of a dimension lying inside [lo, hi] grown by eps (OCC boxes
    carry small tolerances)."""
    occ = gmsh.model.occ
    return [t for d, t in occ.getEntitiesInBoundingBox(
        lo[0] - eps, lo[1] - eps, lo[2] - eps, hi[0] + eps, hi[1] + eps, hi[2] + eps, dim)]


def single_volume():
    vols = gmsh.model.occ.getEntities(3)
    assert len(vols) == 1, f"expected one volume, got {vols}"
    return vols[0][1]


def circle_curve(center, radius, normal_axis=2):
    """The one curve that is the circle of given centre/radius in an axis
    plane (a plane normal to x, y or z)."""
    lo = [c - radius for c in center]
    hi = [c + radius for c in center]
    lo[normal_axis] = hi[normal_axis] = center[normal_axis]
    tags = entities_in_box(1, lo, hi)
    # Keep the closed curve whose length is the full circumference.
    tags = [t for t in tags
            if abs(gmsh.model.occ.getMass(1, t) - 2 * math.pi * radius) < 1e-6 * radius]
    assert len(tags) == 1, f"circle at {center} r={radius}: found {tags}"
    return tags[0]


# ----------------------------------------------------------------------------
# The parts. Each builder makes the OCC solid (not yet synchronized) and
# returns its construction dimensions, the analytic surfaces it is bounded
# by, the mesh sizes and a one-line description.
# ----------------------------------------------------------------------------

def build_boss_block():
    occ = gmsh.model.occ
    d = {
        "block_size_x": 100.0, "block_size_y": 60.0, "block_size_z": 20.0,
        "block_origin": [0.0, 0.0, 0.0],
        "boss_center_x": 35.0, "boss_center_y": 30.0,
        "boss_radius": 12.0, "boss_height": 15.0,
        "boss_fillet_radius": 3.0,
        "boss_chamfer_length": 2.0, "boss_chamfer_angle_deg": 45.0,
        "hole_center_x": 75.0, "hole_center_y": 30.0, "hole_radius": 6.0,
        "hole_note": "through the block only (z = 0 .. block_size_z), beside the boss",
    }
    L, W, H = d["block_size_x"], d["block_size_y"], d["block_size_z"]
    bx, by, rb, hb = d["boss_center_x"], d["boss_center_y"], d["boss_radius"], d["boss_height"]
    rf, c = d["boss_fillet_radius"], d["boss_chamfer_length"]
    hx, hy, rh = d["hole_center_x"], d["hole_center_y"], d["hole_radius"]
    top = H + hb

    block = occ.addBox(0, 0, 0, L, W, H)
    boss = occ.addCylinder(bx, by, H, 0, 0, hb, rb)
    occ.fuse([(3, block)], [(3, boss)])
    occ.synchronize()
    # Concave fillet at the boss base: the boss/block-top circle.
    base_circle = circle_curve([bx, by, H], rb)
    occ.fillet([single_volume()], [base_circle], [rf], True)
    occ.synchronize()
    # 45-degree chamfer at the boss top edge (equal distances on both faces).
    top_circle = circle_curve([bx, by, top], rb)
    top_face = entities_in_box(2, [bx - rb, by - rb, top], [bx + rb, by + rb, top])
    assert len(top_face) == 1, top_face
    occ.chamfer([single_volume()], [top_circle], top_face, [c], True)
    solid = single_volume()
    hole = occ.addCylinder(hx, hy, -1.0, 0, 0, H + 2.0, rh)
    occ.cut([(3, solid)], [(3, hole)])

    z = [0.0, 0.0, 1.0]
    alpha = math.radians(d["boss_chamfer_angle_deg"])
    # The chamfer cone narrows upwards; its apex is on the boss axis where the
    # generating line through (rb - c, top) reaches radius 0.
    apex_z = top + (rb - c) / math.tan(alpha)
    surfaces = [
        plane("block bottom", [0, 0, 0], [0, 0, -1]),
        plane("block top", [0, 0, H], [0, 0, 1]),
        plane("block side x=0", [0, 0, 0], [-1, 0, 0]),
        plane("block side x=L", [L, 0, 0], [1, 0, 0]),
        plane("block side y=0", [0, 0, 0], [0, -1, 0]),
        plane("block side y=W", [0, W, 0], [0, 1, 0]),
        plane("boss top", [bx, by, top], [0, 0, 1]),
        cylinder("boss side", [bx, by, H], z, rb, "convex"),
        torus("boss base fillet", [bx, by, H + rf], z, rb + rf, rf, "concave"),
        cone("boss top chamfer", [bx, by, apex_z], [0, 0, -1],
             d["boss_chamfer_angle_deg"], "convex"),
        cylinder("through hole", [hx, hy, 0], z, rh, "concave"),
    ]
    mesh = {"Mesh.MeshSizeMin": 0.6, "Mesh.MeshSizeMax": 5.0,
            "Mesh.MeshSizeFromCurvature": 16,
            "refine": {"gmsh_types": ["Torus", "Cone"], "size_near": 0.9, "size_far": 5.0,
                       "dist_near": 0.5, "dist_far": 8.0}}
    return ("block with a filleted and chamfered cylindrical boss and a through hole",
            d, surfaces, mesh)


def build_filleted_box():
    occ = gmsh.model.occ
    d = {"box_size_x": 80.0, "box_size_y": 50.0, "box_size_z": 30.0,
         "box_origin": [0.0, 0.0, 0.0], "edge_fillet_radius": 6.0}
    L, W, H, r = d["box_size_x"], d["box_size_y"], d["box_size_z"], d["edge_fillet_radius"]
    box = occ.addBox(0, 0, 0, L, W, H)
    occ.synchronize()
    edges = [t for _, t in gmsh.model.getEntities(1)]
    assert len(edges) == 12
    occ.fillet([box], edges, [r], True)

    surfaces = [
        plane("face x=0", [0, 0, 0], [-1, 0, 0]), plane("face x=L", [L, 0, 0], [1, 0, 0]),
        plane("face y=0", [0, 0, 0], [0, -1, 0]), plane("face y=W", [0, W, 0], [0, 1, 0]),
        plane("face z=0", [0, 0, 0], [0, 0, -1]), plane("face z=H", [0, 0, H], [0, 0, 1]),
    ]
    # Each edge fillet is a quarter cylinder whose axis is the box edge moved
    # inwards by r in both directions; each corner is an eighth sphere.
    lo = np.array([r, r, r])
    hi = np.array([L - r, W - r, H - r])
    names = "xyz"
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        for s0 in (0, 1):
            for s1 in (0, 1):
                p = np.zeros(3)
                p[others[0]] = (lo, hi)[s0][others[0]]
                p[others[1]] = (lo, hi)[s1][others[1]]
                direction = np.zeros(3)
                direction[axis] = 1.0
                label = (f"edge fillet along {names[axis]} at "
                         f"{names[others[0]]}={p[others[0]]:g}, {names[others[1]]}={p[others[1]]:g}")
                surfaces.append(cylinder(label, p, direction, r, "convex"))
    for sx in (0, 1):
        for sy in (0, 1):
            for sz in (0, 1):
                c = [(lo, hi)[sx][0], (lo, hi)[sy][1], (lo, hi)[sz][2]]
                surfaces.append(sphere(f"corner at ({c[0]:g}, {c[1]:g}, {c[2]:g})", c, r, "convex"))
    mesh = {"Mesh.MeshSizeMin": 1.0, "Mesh.MeshSizeMax": 7.0,
            "Mesh.MeshSizeFromCurvature": 14,
            "refine": {"gmsh_types": ["Sphere"], "size_near": 1.5, "size_far": 7.0,
                       "dist_near": 0.5, "dist_far": 8.0}}
    return "box with all twelve edges filleted (spherical corners)", d, surfaces, mesh


def build_cone_sphere_torus():
    occ = gmsh.model.occ
    d = {
        "axis_point": [0.0, 0.0, 0.0], "axis_direction": [0.0, 0.0, 1.0],
        "base_radius": 30.0, "base_thickness": 10.0,
        "shaft_radius": 12.0, "shaft_height": 20.0,
        "shaft_fillet_radius": 4.0,
        "cone_height": 12.0, "cone_top_radius": 8.0,
        "cap_sphere_radius": 9.0,
        "bolt_hole_radius": 3.0, "bolt_hole_circle_radius": 22.0, "bolt_hole_count": 4,
        "bolt_hole_note": "through the base plate, at 0, 90, 180, 270 degrees from +x",
    }
    rb, tb = d["base_radius"], d["base_thickness"]
    rs, hs, rf = d["shaft_radius"], d["shaft_height"], d["shaft_fillet_radius"]
    hc, rc = d["cone_height"], d["cone_top_radius"]
    rsph = d["cap_sphere_radius"]
    z_shaft_top = tb + hs
    z_cone_top = z_shaft_top + hc
    # The cap is the part of the sphere above the cone's top plane; its centre
    # sits below that plane so that the sphere cuts it in the cone's top circle.
    z_sphere = z_cone_top - math.sqrt(rsph ** 2 - rc ** 2)
    d["cap_sphere_center_z"] = z_sphere
    d["cap_height"] = z_sphere + rsph - z_cone_top

    base = occ.addCylinder(0, 0, 0, 0, 0, tb, rb)
    shaft = occ.addCylinder(0, 0, tb, 0, 0, hs, rs)
    frustum = occ.addCone(0, 0, z_shaft_top, 0, 0, hc, rs, rc)
    ball = occ.addSphere(0, 0, z_sphere, rsph)
    upper = occ.addBox(-rsph, -rsph, z_cone_top, 2 * rsph, 2 * rsph, rsph)
    cap, _ = occ.intersect([(3, ball)], [(3, upper)])
    occ.fuse([(3, base)], [(3, shaft), (3, frustum)] + cap)
    occ.synchronize()
    occ.fillet([single_volume()], [circle_curve([0, 0, tb], rs)], [rf], True)
    holes = []
    for k in range(d["bolt_hole_count"]):
        a = 2 * math.pi * k / d["bolt_hole_count"]
        cx, cy = d["bolt_hole_circle_radius"] * math.cos(a), d["bolt_hole_circle_radius"] * math.sin(a)
        holes.append((round(cx, 12) + 0.0, round(cy, 12) + 0.0))
    d["bolt_hole_centers_xy"] = [list(h) for h in holes]
    solid = single_volume()
    tools = [(3, occ.addCylinder(cx, cy, -1.0, 0, 0, tb + 2.0, d["bolt_hole_radius"]))
             for cx, cy in holes]
    occ.cut([(3, solid)], tools)

    z = [0.0, 0.0, 1.0]
    half_angle = math.degrees(math.atan((rs - rc) / hc))
    d["cone_half_angle_deg"] = half_angle
    apex_z = z_shaft_top + hc * rs / (rs - rc)
    surfaces = [
        plane("base bottom", [0, 0, 0], [0, 0, -1]),
        plane("base top", [0, 0, tb], [0, 0, 1]),
        cylinder("base rim", [0, 0, 0], z, rb, "convex"),
        torus("shaft fillet", [0, 0, tb + rf], z, rs + rf, rf, "concave"),
        cylinder("shaft", [0, 0, 0], z, rs, "convex"),
        cone("cone", [0, 0, apex_z], [0, 0, -1], half_angle, "convex"),
        sphere("spherical cap", [0, 0, z_sphere], rsph, "convex"),
    ]
    for k, (cx, cy) in enumerate(holes):
        surfaces.append(cylinder(f"bolt hole {k}", [cx, cy, 0], z, d["bolt_hole_radius"], "concave"))
    mesh = {"Mesh.MeshSizeMin": 0.6, "Mesh.MeshSizeMax": 5.0,
            "Mesh.MeshSizeFromCurvature": 12,
            "refine": {"gmsh_types": ["Torus", "Cone", "Sphere"], "size_near": 1.3,
                       "size_far": 5.0, "dist_near": 0.5, "dist_far": 8.0}}
    return ("round base plate with bolt holes, filleted shaft, cone and spherical cap",
            d, surfaces, mesh)


PARTS = {
    "boss_block": build_boss_block,
    "filleted_box": build_filleted_box,
    "cone_sphere_torus": build_cone_sphere_torus,
}


# ----------------------------------------------------------------------------
# Mesh extraction
# ----------------------------------------------------------------------------

def signed_volumes(points, tets):
    p0, p1, p2, p3 = (points[tets[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", p1 - p0, np.cross(p2 - p0, p3 - p0)) / 6.0


def extract_mesh():
    """Tets, boundary triangles per surface and node classification from the
    current Gmsh model, renumbered to 0-based over the nodes the tets use."""
    vol = single_volume()
    types, _, node_tags = gmsh.model.mesh.getElements(3, vol)
    assert list(types) == [GMSH_TET], f"volume elements of types {types}"
    tet_tags = np.asarray(node_tags[0], dtype=np.int64).reshape(-1, 4)

    all_tags, all_coords, _ = gmsh.model.mesh.getNodes()
    all_tags = np.asarray(all_tags, dtype=np.int64)
    all_coords = np.asarray(all_coords, dtype=float).reshape(-1, 3)

    # Keep only nodes used by tets, in increasing Gmsh tag order.
    used = np.unique(tet_tags)
    order = np.argsort(all_tags)
    sorted_tags = all_tags[order]
    pos = np.searchsorted(sorted_tags, used)
    assert np.all(sorted_tags[pos] == used), "tet uses an unknown node"
    points = all_coords[order[pos]]
    index_of = {int(t): i for i, t in enumerate(used)}
    remap = np.vectorize(index_of.__getitem__, otypes=[np.int64])
    tets = remap(tet_tags)

    # Gmsh's reference tet is (0,0,0),(1,0,0),(0,1,0),(0,0,1), the same
    # handedness as VTK's; still check every element and flip any negative one.
    vol6 = signed_volumes(points, tets)
    negative = int(np.count_nonzero(vol6 < 0))
    if negative:
        tets[vol6 < 0] = tets[vol6 < 0][:, [0, 1, 3, 2]]
    vol6 = signed_volumes(points, tets)
    assert np.all(vol6 > 0), "non-positive tet volume after orientation fix"

    # Node classification: the entity a node is classified on (its own, not
    # its closure), from the lowest-dimensional entity up.
    entity_dim = np.full(len(used), -1, dtype=np.int32)
    entity_tag = np.full(len(used), -1, dtype=np.int32)
    for dim in range(4):
        for _, tag in gmsh.model.getEntities(dim):
            ntags, _, _ = gmsh.model.mesh.getNodes(dim, tag, includeBoundary=False,
                                                   returnParametricCoord=False)
            for nt in ntags:
                i = index_of.get(int(nt))
                if i is not None:
                    assert entity_dim[i] == -1, f"node {nt} classified twice"
                    entity_dim[i] = dim
                    entity_tag[i] = tag
    assert np.all(entity_dim >= 0), "unclassified node"

    # Boundary triangles per surface.
    triangles = {}
    for _, stag in gmsh.model.getEntities(2):
        types, _, ntags = gmsh.model.mesh.getElements(2, stag)
        assert list(types) == [GMSH_TRIANGLE], f"surface {stag}: element types {types}"
        triangles[stag] = remap(np.asarray(ntags[0], dtype=np.int64).reshape(-1, 3))

    return points, tets, entity_dim, entity_tag, triangles, negative


# Local vertex ids of the face opposite vertex i (any order; faces are matched
# as vertex sets).
OPPOSITE_FACE = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]


def cad_face_labels(tets, triangles):
    """CADFace: per tet and local face i, the surface tag of the boundary face
    opposite vertex i, -1 for interior faces."""
    face_slot = {}
    seen = {}
    for t, tet in enumerate(tets.tolist()):
        for i, (a, b, c) in enumerate(OPPOSITE_FACE):
            key = tuple(sorted((tet[a], tet[b], tet[c])))
            seen[key] = seen.get(key, 0) + 1
            face_slot[key] = (t, i)
    boundary = {k for k, n in seen.items() if n == 1}
    labels = np.full((len(tets), 4), -1, dtype=np.int32)
    matched = 0
    for stag, tris in triangles.items():
        for tri in tris.tolist():
            key = tuple(sorted(tri))
            assert key in boundary, f"surface {stag} triangle {tri} is not a boundary tet face"
            t, i = face_slot[key]
            assert labels[t, i] == -1, "boundary face labelled twice"
            labels[t, i] = stag
            matched += 1
    assert matched == len(boundary), (
        f"{len(boundary) - matched} boundary tet faces without a CAD surface")
    return labels, len(boundary)


# ----------------------------------------------------------------------------
# Surface identification and checks
# ----------------------------------------------------------------------------

def describe_surfaces(points, triangles, candidates, part_size):
    """One JSON entry per Gmsh surface: its type, the construction surface
    it lies on (with exact parameters), triangle count, area and the largest
    distance of its mesh nodes to the analytic surface."""
    tolerance = 1e-9 * part_size
    faces = []
    use_count = [0] * len(candidates)
    for _, stag in gmsh.model.getEntities(2):
        gmsh_type = gmsh.model.getType(2, stag)
        primitive = PRIMITIVE_OF_GMSH_TYPE.get(gmsh_type, "unknown")
        tris = triangles[stag]
        nodes = np.unique(tris)
        x = points[nodes]
        dists = [float(np.max(distance_to_surface(c, x))) for c in candidates]
        best = int(np.argmin(dists))
        cand = candidates[best]
        assert dists[best] < tolerance, (
            f"surface {stag} ({gmsh_type}): nearest construction surface "
            f"'{cand['label']}' at {dists[best]:.3g} > {tolerance:.3g}")
        assert cand["primitive"] == primitive, (
            f"surface {stag}: Gmsh type {gmsh_type} but built as {cand['primitive']} "
            f"'{cand['label']}'")
        use_count[best] += 1
        p0, p1, p2 = (points[tris[:, i]] for i in range(3))
        area = float(np.sum(np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)) / 2.0)
        entry = {"tag": int(stag), "gmsh_type": gmsh_type}
        entry.update(cand)
        entry.update({"triangle_count": int(len(tris)), "node_count": int(len(nodes)),
                      "area": area, "max_node_distance": dists[best]})
        faces.append(entry)
    unused = [c["label"] for c, n in zip(candidates, use_count) if n == 0]
    assert not unused, f"construction surfaces without a mesh face: {unused}"
    split = [c["label"] for c, n in zip(candidates, use_count) if n > 1]
    return faces, split


def describe_curves(part_size):
    """Curves with their Gmsh type and adjacent surfaces. OCC's sphere patches
    have a zero-length edge at the pole, which Gmsh reports as "Unknown";
    flag those as degenerate."""
    curves = []
    for _, ctag in gmsh.model.getEntities(1):
        up, _ = gmsh.model.getAdjacencies(1, ctag)
        length = float(gmsh.model.occ.getMass(1, ctag))
        curves.append({"tag": int(ctag), "gmsh_type": gmsh.model.getType(1, ctag),
                       "length": length, "degenerate": length < 1e-9 * part_size,
                       "surfaces": sorted(int(s) for s in up)})
    return curves


# ----------------------------------------------------------------------------
# Writers
# ----------------------------------------------------------------------------

def write_vtu(path, points, tets, cad_face, entity_dim, entity_tag):
    if HAVE_VTK:
        write_vtu_vtk(path, points, tets, cad_face, entity_dim, entity_tag)
    else:
        write_vtu_ascii(path, points, tets, cad_face, entity_dim, entity_tag)


def int_array(name, values, components=1):
    arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.int32), deep=1)
    arr.SetName(name)
    arr.SetNumberOfComponents(components)
    return arr


def write_vtu_vtk(path, points, tets, cad_face, entity_dim, entity_tag):
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
    grid.SetPoints(pts)
    n = len(tets)
    conn = np.hstack([np.full((n, 1), 4, dtype=np.int64), tets.astype(np.int64)]).ravel()
    cells = vtkCellArray()
    cells.SetCells(n, numpy_to_vtkIdTypeArray(conn, deep=1))
    grid.SetCells(VTK_TETRA, cells)
    grid.GetCellData().AddArray(int_array("CADFace", cad_face.reshape(-1), 4))
    grid.GetPointData().AddArray(int_array("CADEntityDim", entity_dim))
    grid.GetPointData().AddArray(int_array("CADEntityTag", entity_tag))
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(grid)
    w.SetCompressorTypeToZLib()
    w.SetDataModeToAppended()
    w.EncodeAppendedDataOff()
    assert w.Write() == 1, f"VTK could not write {path}"


def write_vtu_ascii(path, points, tets, cad_face, entity_dim, entity_tag):
    def rows(a, fmt):
        return "\n".join(" ".join(fmt % v for v in r) for r in np.atleast_2d(a))

    n = len(tets)
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
                'byte_order="LittleEndian" header_type="UInt64">\n<UnstructuredGrid>\n')
        f.write(f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{n}">\n')
        f.write('<PointData>\n')
        for name, a in (("CADEntityDim", entity_dim), ("CADEntityTag", entity_tag)):
            f.write(f'<DataArray type="Int32" Name="{name}" format="ascii">\n')
            f.write(rows(a.reshape(-1, 1), "%d") + "\n</DataArray>\n")
        f.write('</PointData>\n<CellData>\n')
        f.write('<DataArray type="Int32" Name="CADFace" NumberOfComponents="4" format="ascii">\n')
        f.write(rows(cad_face, "%d") + "\n</DataArray>\n</CellData>\n")
        f.write('<Points>\n<DataArray type="Float64" NumberOfComponents="3" format="ascii">\n')
        f.write(rows(points, "%.17g") + "\n</DataArray>\n</Points>\n<Cells>\n")
        f.write('<DataArray type="Int64" Name="connectivity" format="ascii">\n')
        f.write(rows(tets, "%d") + "\n</DataArray>\n")
        f.write('<DataArray type="Int64" Name="offsets" format="ascii">\n')
        f.write(rows((np.arange(1, n + 1) * 4).reshape(-1, 1), "%d") + "\n</DataArray>\n")
        f.write('<DataArray type="UInt8" Name="types" format="ascii">\n')
        f.write(rows(np.full((n, 1), VTK_TETRA_TYPE), "%d") + "\n</DataArray>\n")
        f.write('</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n')


# ----------------------------------------------------------------------------
# Driver
# ----------------------------------------------------------------------------

def refine_near_surfaces(gmsh_types, size_near, size_far, dist_near, dist_far,
                         points_per_curve=40):
    """Smaller elements on and near the small feature faces (fillet, chamfer,
    cap): the segmentation needs several rows of triangles across a narrow
    face to estimate curvature (thesis 2.4). Gmsh uses the minimum of this
    field and the curvature/maximum sizes."""
    tags = [t for _, t in gmsh.model.getEntities(2) if gmsh.model.getType(2, t) in gmsh_types]
    assert tags, f"no surface of types {gmsh_types} to refine"
    dist = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(dist, "SurfacesList", tags)
    gmsh.model.mesh.field.setNumber(dist, "NumPointsPerCurve", points_per_curve)
    thr = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(thr, "InField", dist)
    gmsh.model.mesh.field.setNumber(thr, "SizeMin", size_near)
    gmsh.model.mesh.field.setNumber(thr, "SizeMax", size_far)
    gmsh.model.mesh.field.setNumber(thr, "DistMin", dist_near)
    gmsh.model.mesh.field.setNumber(thr, "DistMax", dist_far)
    gmsh.model.mesh.field.setAsBackgroundMesh(thr)
    return {"field": "Threshold(Distance(surfaces))", "gmsh_types": list(gmsh_types),
            "surfaces": tags, "size_near": size_near, "size_far": size_far,
            "dist_near": dist_near, "dist_far": dist_far, "points_per_curve": points_per_curve}


def generate(name, out_dir):
    gmsh.model.add(name)
    description, dims, candidates, size_options = PARTS[name]()
    gmsh.model.occ.synchronize()

    options = dict(COMMON_MESH_OPTIONS)
    refine = size_options.pop("refine", None)
    options.update(size_options)
    for key, value in options.items():
        gmsh.option.setNumber(key, value)
    if refine:
        refine = refine_near_surfaces(**refine)
    gmsh.model.mesh.generate(3)

    points, tets, entity_dim, entity_tag, triangles, negative = extract_mesh()
    cad_face, n_boundary = cad_face_labels(tets, triangles)
    n_tris = sum(len(t) for t in triangles.values())
    assert n_tris == n_boundary

    lo, hi = points.min(axis=0), points.max(axis=0)
    part_size = float(np.linalg.norm(hi - lo))
    faces, split = describe_surfaces(points, triangles, candidates, part_size)
    curves = describe_curves(part_size)

    by_type = {}
    for f in faces:
        by_type[f["primitive"]] = by_type.get(f["primitive"], 0) + 1
    worst = {}
    for f in faces:
        worst[f["primitive"]] = max(worst.get(f["primitive"], 0.0), f["max_node_distance"])

    info = {
        "name": name,
        "description": description,
        "units": "mm",
        "generator": "Data/generate_parts.py (Gmsh OpenCASCADE kernel)",
        "gmsh_version": gmsh.option.getString("General.Version"),
        "dimensions": dims,
        "mesh_options": options,
        "mesh_refinement": refine,
        "counts": {"points": int(len(points)), "tets": int(len(tets)),
                   "boundary_triangles": int(n_tris), "surfaces": len(faces),
                   "curves": len(curves), "surfaces_by_type": by_type},
        "bounding_box": {"min": lo.tolist(), "max": hi.tolist()},
        "volume": float(signed_volumes(points, tets).sum()),
        "orientation": {"gmsh_negative_tets_flipped": negative,
                        "convention": "(p1-p0).((p2-p0)x(p3-p0)) > 0 for every tet"},
        "max_node_distance_by_type": worst,
        "construction_surfaces_split_into_several_faces": split,
        "faces": faces,
        "curves": curves,
    }
    write_vtu(os.path.join(out_dir, name + ".vtu"), points, tets, cad_face,
              entity_dim, entity_tag)
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")
    gmsh.model.remove()
    return info


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out-dir", default=os.path.dirname(os.path.abspath(__file__)),
                        help="folder for <name>.vtu and <name>.json (default: this script's folder)")
    parser.add_argument("--only", choices=sorted(PARTS), action="append",
                        help="generate only this part (repeatable)")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)

    gmsh.initialize(["generate_parts"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    rows = []
    try:
        for name in PARTS:
            if args.only and name not in args.only:
                continue
            info = generate(name, args.out_dir)
            rows.append(info)
    finally:
        gmsh.finalize()

    print(f"{'part':<18} {'points':>7} {'tets':>7} {'tris':>6}  {'faces by type':<44} "
          f"{'max dist':>9}  {'vtu KB':>7}")
    for info in rows:
        c = info["counts"]
        types = ", ".join(f"{n} {t}" for t, n in sorted(c["surfaces_by_type"].items()))
        dist = max(info["max_node_distance_by_type"].values())
        size = os.path.getsize(os.path.join(args.out_dir, info["name"] + ".vtu")) / 1024
        print(f"{info['name']:<18} {c['points']:>7} {c['tets']:>7} {c['boundary_triangles']:>6}  "
              f"{types:<44} {dist:>9.2e}  {size:>7.0f}")
    print(f"written to {args.out_dir}" + ("" if HAVE_VTK else " (ascii .vtu: vtkmodules not found)"))


if __name__ == "__main__":
    main()
