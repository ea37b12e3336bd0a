#!/usr/bin/python3
"""Build the CAD test parts of FEMorph and mesh them with linear tetrahedra.

Run with Debian's interpreter (python3-gmsh, python3-numpy and python3-paraview
are Debian packages that a pyenv python cannot see):

    /usr/bin/python3 Data/generate_parts.py [--out-dir Data] [--only NAME]
    /usr/bin/python3 Data/generate_parts.py --fine boss_block --out-dir /tmp/parts \
        [--target-boundary-triangles 200000]
    /usr/bin/python3 Data/generate_parts.py --step part.step [--step ...] \
        --out-dir /tmp/parts [--mesh-size H]
    /usr/bin/python3 Data/generate_parts.py --hex [--out-dir Data]
    /usr/bin/python3 Data/generate_parts.py --variants [--out-dir Data] [--only NAME]

For every part it writes <name>.vtu (tets, CAD face labels per tet face, CAD
entity of every node) and <name>.json (construction dimensions, mesh options,
counts, and one entry per CAD surface with its exact analytic parameters).
Because the parts are built from primitives whose parameters we chose, the
integration tests of the segmentation (thesis 2.4) and the deformation
(thesis 2.5) can compare fitted types and radii against known truth.

The output is deterministic: one thread, fixed mesh options, nodes numbered
in Gmsh's tag order. Data/README.md describes the file formats.

--fine writes <NAME>_fine.vtu/.json, a version of a part with about the
given number of boundary triangles (mesh sizes scaled; a coarser inside),
for benchmarks; it is not kept in Data/. Its surface mesh is deterministic,
its tets (Gmsh's HXT algorithm) vary slightly between runs.

--hex writes only the all-hexahedral parts, hex/<name>.vtu/.json under the
output folder: a tet mesh of a CAD part, each tet split into four hexahedra
by Gmsh's subdivision (an unstructured hex mesh, for Hex To Tet, thesis 4.4).
They are also written by a run without options.

--variants writes only the changed-CAD variants (VARIANTS), for the tests of
FEMorph Deform: variants/<part>__<variant>.json (the part's JSON layout for
the CAD of the part with one dimension changed, same face labels) and .vtp
(a fine Gmsh triangle mesh of its boundary, cell array CADFace), plus the
identity variant <part>__base. Base and variants come from the same builder
(its `over` dimensions). A run without options writes them too.

--step meshes STEP files made by others (e.g. shared/realparts) the same way
and writes <stem>.vtu/.json with the same arrays. The JSON's faces carry
Gmsh's type and the primitive found by fitting the face's nodes (Gmsh names
many exact cylinders "Unknown"), with the fitted parameters.
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np
import gmsh

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
GMSH_TET = 4        # Gmsh element type: 4-node tetrahedron
GMSH_TRIANGLE = 2   # Gmsh element type: 3-node triangle
GMSH_QUAD = 3       # Gmsh element type: 4-node quadrangle
GMSH_HEX = 5        # Gmsh element type: 8-node hexahedron (VTK's node order)
VTK_HEXAHEDRON_TYPE = 12

# Gmsh surface type -> FEMorph primitive name (the RegionType codes of
# docs/ARCHITECTURE.md).
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
    if kind == "unknown" and surf.get("surface") == "bspline":
        # Vertical distance to the graph z = f(x, y): an upper bound of the
        # distance (infinite outside the graph's rectangle).
        dz = np.abs(x[:, 2] - bspline_graph_height(surf, x))
        return np.where(np.isnan(dz), np.inf, dz)
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

def build_boss_block(over=None):
    """`over`: dimensions to change (the variants, --variants); the chamfer
    keeps its leg on the boss top face (boss_chamfer_length, radial) and makes
    boss_chamfer_angle_deg with that face, so its leg on the boss side is
    boss_chamfer_length x tan(angle) (equal legs at 45 deg)."""
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
    d.update(over or {})
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
    # Chamfer at the boss top edge: leg c on the top face, angle alpha to it
    # (45 deg: equal distances on both faces).
    top_circle = circle_curve([bx, by, top], rb)
    top_face = entities_in_box(2, [bx - rb, by - rb, top], [bx + rb, by + rb, top])
    assert len(top_face) == 1, top_face
    if d["boss_chamfer_angle_deg"] == 45.0:
        distances = [c]
    else:
        # OCC: the first distance on the given face (the top), the second on
        # the other face (the boss side).
        distances = [c, c * math.tan(math.radians(d["boss_chamfer_angle_deg"]))]
    occ.chamfer([single_volume()], [top_circle], top_face, distances, True)
    solid = single_volume()
    hole = occ.addCylinder(hx, hy, -1.0, 0, 0, H + 2.0, rh)
    occ.cut([(3, solid)], [(3, hole)])

    z = [0.0, 0.0, 1.0]
    # The chamfer cone narrows upwards; its apex is on the boss axis where the
    # generating line through (rb - c, top) reaches radius 0. Its half angle
    # (to the axis) is 90 deg - the angle to the top face.
    chamfer_half_angle = 90.0 - d["boss_chamfer_angle_deg"]
    apex_z = top + (rb - c) / math.tan(math.radians(chamfer_half_angle))
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
             chamfer_half_angle, "convex"),
        cylinder("through hole", [hx, hy, 0], z, rh, "concave"),
    ]
    mesh = {"Mesh.MeshSizeMin": 0.6, "Mesh.MeshSizeMax": 5.0,
            "Mesh.MeshSizeFromCurvature": 16,
            "refine": {"gmsh_types": ["Torus", "Cone"], "size_near": 0.9, "size_far": 5.0,
                       "dist_near": 0.5, "dist_far": 8.0}}
    return ("block with a filleted and chamfered cylindrical boss and a through hole",
            d, surfaces, mesh)


def build_filleted_box(over=None):
    occ = gmsh.model.occ
    d = {"box_size_x": 80.0, "box_size_y": 50.0, "box_size_z": 30.0,
         "box_origin": [0.0, 0.0, 0.0], "edge_fillet_radius": 6.0}
    # The labels name the faces by the base part's axis positions, so that a
    # variant's faces keep the base part's labels.
    label_lo = np.full(3, d["edge_fillet_radius"])
    label_hi = np.array([d["box_size_x"], d["box_size_y"], d["box_size_z"]]) - label_lo
    d.update(over or {})
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
                q = np.zeros(3)
                q[others[0]] = (label_lo, label_hi)[s0][others[0]]
                q[others[1]] = (label_lo, label_hi)[s1][others[1]]
                direction = np.zeros(3)
                direction[axis] = 1.0
                label = (f"edge fillet along {names[axis]} at "
                         f"{names[others[0]]}={q[others[0]]:g}, {names[others[1]]}={q[others[1]]:g}")
                surfaces.append(cylinder(label, p, direction, r, "convex"))
    for sx in (0, 1):
        for sy in (0, 1):
            for sz in (0, 1):
                c = [(lo, hi)[sx][0], (lo, hi)[sy][1], (lo, hi)[sz][2]]
                q = [(label_lo, label_hi)[sx][0], (label_lo, label_hi)[sy][1],
                     (label_lo, label_hi)[sz][2]]
                surfaces.append(sphere(f"corner at ({q[0]:g}, {q[1]:g}, {q[2]:g})", c, r, "convex"))
    mesh = {"Mesh.MeshSizeMin": 1.0, "Mesh.MeshSizeMax": 7.0,
            "Mesh.MeshSizeFromCurvature": 14,
            "refine": {"gmsh_types": ["Sphere"], "size_near": 1.5, "size_far": 7.0,
                       "dist_near": 0.5, "dist_far": 8.0}}
    return "box with all twelve edges filleted (spherical corners)", d, surfaces, mesh


def build_cone_sphere_torus(over=None):
    """`over`: dimensions to change (--variants). With cap_sphere_center_z
    given (a cap radius changed with the sphere centre kept), the cone keeps
    its apex and half angle (from the base shaft radius, cone height and top
    radius) and is cut where its generating line leaves the sphere going up
    (the upper intersection, z = 42 in the base part): cone_height and
    cone_top_radius follow. A changed shaft_radius changes the cone's bottom
    radius (its height and top radius kept) and the fillet's major radius."""
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
    over = dict(over or {})
    keep_center_z = over.pop("cap_sphere_center_z", None)
    if keep_center_z is not None:
        # The sphere |x - (0, 0, zc)| = R against the cone line
        # rho = (za - z) t (t = tan(half angle), apex at za):
        # (t^2 + 1) z^2 - 2 (za t^2 + zc) z + za^2 t^2 + zc^2 - R^2 = 0.
        rs0, hc0, rc0 = d["shaft_radius"], d["cone_height"], d["cone_top_radius"]
        z0 = d["base_thickness"] + d["shaft_height"]
        t = (rs0 - rc0) / hc0
        za = z0 + hc0 * rs0 / (rs0 - rc0)
        radius = over.get("cap_sphere_radius", d["cap_sphere_radius"])
        qa, qb = t * t + 1.0, -2.0 * (za * t * t + keep_center_z)
        qc = za * za * t * t + keep_center_z ** 2 - radius ** 2
        z_top = (-qb + math.sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa)
        assert z0 < z_top < za, z_top
        over["cone_height"] = z_top - z0
        over["cone_top_radius"] = (za - z_top) * t
    d.update(over)
    rb, tb = d["base_radius"], d["base_thickness"]
    rs, hs, rf = d["shaft_radius"], d["shaft_height"], d["shaft_fillet_radius"]
    hc, rc = d["cone_height"], d["cone_top_radius"]
    rsph = d["cap_sphere_radius"]
    z_shaft_top = tb + hs
    z_cone_top = z_shaft_top + hc
    # The cap is the part of the sphere above the cone's top plane; its centre
    # sits below that plane so that the sphere cuts it in the cone's top circle.
    z_sphere = z_cone_top - math.sqrt(rsph ** 2 - rc ** 2)
    if keep_center_z is not None:
        assert abs(z_sphere - keep_center_z) < 1e-9, (z_sphere, keep_center_z)
        z_sphere = keep_center_z
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


def build_fillet_junctions():
    """Fillets that meet tangentially (G1), after thesis Figs. 2.47-2.48:
    cylinder-torus-cylinder corners, cone-torus, sphere-torus and
    cylinder-cylinder-sphere junctions."""
    occ = gmsh.model.occ
    d = {
        "block_size_x": 120.0, "block_size_y": 80.0, "block_size_z": 25.0,
        "block_origin": [0.0, 0.0, 0.0],
        "vertical_edge_fillet_radius": 10.0, "top_edge_fillet_radius": 4.0,
        "block_note": ("the four vertical edges are filleted first, then the whole top face "
                       "boundary (4 lines, 4 arcs); each top corner becomes a torus "
                       "(major = vertical - top fillet radius) tangent to three cylinders "
                       "and the top plane; the bottom edges stay sharp"),
        "cone_boss_center_x": 30.0, "cone_boss_center_y": 40.0,
        "cone_boss_base_radius": 15.0, "cone_boss_top_radius": 9.0, "cone_boss_height": 12.0,
        "cone_boss_base_fillet_radius": 3.0, "cone_boss_top_fillet_radius": 2.0,
        "pin_center_x": 65.0, "pin_center_y": 40.0, "pin_radius": 7.0,
        "pin_cylinder_height": 14.0, "pin_top_fillet_radius": 2.5, "pin_cap_sphere_radius": 12.0,
        "pin_base_fillet_radius": 2.0,
        "pin_note": ("cylinder, then a convex torus fillet tangent to it and to a spherical "
                     "cap (built exactly from an OCC torus, cylinder and sphere, since OCC's "
                     "own cylinder-sphere fillet is a B-spline); base fillet by OCC"),
        "pocket_min_x": 82.0, "pocket_max_x": 110.0, "pocket_min_y": 18.0, "pocket_max_y": 62.0,
        "pocket_depth": 10.0, "pocket_fillet_radius": 5.0,
        "pocket_note": ("vertical and floor edges filleted with one radius: concave "
                        "cylinder-cylinder-sphere corners; the rim edges stay sharp"),
    }
    L, W, H = d["block_size_x"], d["block_size_y"], d["block_size_z"]
    rv, rt = d["vertical_edge_fillet_radius"], d["top_edge_fillet_radius"]
    bx, by = d["cone_boss_center_x"], d["cone_boss_center_y"]
    rb, rc, hc = d["cone_boss_base_radius"], d["cone_boss_top_radius"], d["cone_boss_height"]
    fb, ft = d["cone_boss_base_fillet_radius"], d["cone_boss_top_fillet_radius"]
    px, py, rp, hp = d["pin_center_x"], d["pin_center_y"], d["pin_radius"], d["pin_cylinder_height"]
    rpt, rs, rpb = d["pin_top_fillet_radius"], d["pin_cap_sphere_radius"], d["pin_base_fillet_radius"]
    x0, x1, y0, y1 = d["pocket_min_x"], d["pocket_max_x"], d["pocket_min_y"], d["pocket_max_y"]
    dp, rk = d["pocket_depth"], d["pocket_fillet_radius"]

    # Block: vertical edges, then the whole top boundary loop.
    block = occ.addBox(0, 0, 0, L, W, H)
    occ.synchronize()
    vertical = []
    for cx in (0.0, L):
        for cy in (0.0, W):
            vertical += entities_in_box(1, [cx, cy, 0], [cx, cy, H])
    assert len(vertical) == 4, vertical
    occ.fillet([block], vertical, [rv], True)
    occ.synchronize()
    top_loop = entities_in_box(1, [0, 0, H], [L, W, H])
    assert len(top_loop) == 8, top_loop
    occ.fillet([single_volume()], top_loop, [rt], True)
    occ.synchronize()

    # Cone boss (frustum from radius rb at the block top to rc), both circles filleted.
    tan_a = (rb - rc) / hc
    solid = single_volume()
    frustum = occ.addCone(bx, by, H - 1.0, 0, 0, hc + 1.0, rb + tan_a, rc)
    occ.fuse([(3, solid)], [(3, frustum)])
    occ.synchronize()
    occ.fillet([single_volume()], [circle_curve([bx, by, H], rb)], [fb], True)
    occ.synchronize()
    occ.fillet([single_volume()], [circle_curve([bx, by, H + hc], rc)], [ft], True)
    occ.synchronize()

    # Pin: cylinder (radius rp, up to z1), torus fillet (tube radius rpt,
    # centre circle of radius rp - rpt at z1) and a sphere (radius rs) tangent
    # to the tube from outside: |tube centre - sphere centre| = rs - rpt.
    z1 = H + hp
    zs = z1 - math.sqrt((rs - rpt) ** 2 - (rp - rpt) ** 2)
    # The torus-sphere tangency circle: on the ray from the sphere centre
    # through the tube centre.
    zt = zs + rs * (z1 - zs) / (rs - rpt)
    d["pin_cap_sphere_center_z"] = zs
    d["pin_torus_sphere_tangency_z"] = zt
    d["pin_torus_sphere_tangency_radius"] = rs * (rp - rpt) / (rs - rpt)
    solid = single_volume()
    shank = occ.addCylinder(px, py, H - 1.0, 0, 0, z1 - (H - 1.0), rp)
    ring = occ.addTorus(px, py, z1, rp - rpt, rpt)
    slab = occ.addBox(px - rp - 1, py - rp - 1, z1, 2 * rp + 2, 2 * rp + 2, zt - z1)
    ring_slab, _ = occ.intersect([(3, ring)], [(3, slab)])
    core = occ.addCylinder(px, py, z1, 0, 0, zt - z1, rp - rpt)
    middle, _ = occ.fuse(ring_slab, [(3, core)])
    ball = occ.addSphere(px, py, zs, rs)
    upper = occ.addBox(px - rs, py - rs, zt, 2 * rs, 2 * rs, rs)
    cap, _ = occ.intersect([(3, ball)], [(3, upper)])
    occ.fuse([(3, solid), (3, shank)], middle + cap)
    occ.synchronize()
    occ.fillet([single_volume()], [circle_curve([px, py, H], rp)], [rpb], True)
    occ.synchronize()

    # Pocket: a box tool with its vertical and bottom edges filleted, cut out.
    solid = single_volume()
    tool_top = H + 5.0
    tool = occ.addBox(x0, y0, H - dp, x1 - x0, y1 - y0, tool_top - (H - dp))
    occ.synchronize()
    tool_edges = []
    for t in entities_in_box(1, [x0, y0, H - dp], [x1, y1, tool_top]):
        lo_x, lo_y, lo_z, hi_x, hi_y, hi_z = occ.getBoundingBox(1, t)
        if hi_z - lo_z > 1.0 or hi_z < H - dp + 1e-6:
            tool_edges.append(t)
    assert len(tool_edges) == 8, tool_edges
    occ.fillet([tool], tool_edges, [rk], True)
    tools = [(3, t) for t in entities_in_box(3, [x0, y0, H - dp], [x1, y1, tool_top])]
    assert len(tools) == 1, tools
    occ.cut([(3, solid)], tools)

    z = [0.0, 0.0, 1.0]
    surfaces = [
        plane("block bottom", [0, 0, 0], [0, 0, -1]),
        plane("block top", [0, 0, H], [0, 0, 1]),
        plane("block side x=0", [0, 0, 0], [-1, 0, 0]),
        plane("block side x=L", [L, 0, 0], [1, 0, 0]),
        plane("block side y=0", [0, 0, 0], [0, -1, 0]),
        plane("block side y=W", [0, W, 0], [0, 1, 0]),
    ]
    for cx, sx in ((rv, "x=0"), (L - rv, "x=L")):
        for cy, sy in ((rv, "y=0"), (W - rv, "y=W")):
            surfaces.append(cylinder(f"vertical edge fillet at {sx}, {sy}", [cx, cy, 0], z,
                                     rv, "convex"))
            surfaces.append(torus(f"top corner fillet at {sx}, {sy}", [cx, cy, H - rt], z,
                                  rv - rt, rt, "convex"))
    for cy, s in ((rt, "y=0"), (W - rt, "y=W")):
        surfaces.append(cylinder(f"top edge fillet along x at {s}", [0, cy, H - rt],
                                 [1, 0, 0], rt, "convex"))
    for cx, s in ((rt, "x=0"), (L - rt, "x=L")):
        surfaces.append(cylinder(f"top edge fillet along y at {s}", [cx, 0, H - rt],
                                 [0, 1, 0], rt, "convex"))

    # Cone boss: generating line rho(z) = rb - (z - H) tan(a); outward
    # meridian normal (cos a, sin a). A fillet tube of radius f tangent to the
    # block top (concave, centre at height H + f outside the cone) or to the
    # boss top (convex, centre at height H + hc - f inside the cone).
    alpha = math.atan(tan_a)
    cos_a = math.cos(alpha)
    half_angle = math.degrees(alpha)
    d["cone_boss_half_angle_deg"] = half_angle
    apex_z = H + rb / tan_a
    base_major = rb - fb * tan_a + fb / cos_a
    top_major = rc + ft * tan_a - ft / cos_a
    d["cone_boss_base_fillet_major_radius"] = base_major
    d["cone_boss_top_fillet_major_radius"] = top_major
    surfaces += [
        cone("cone boss side", [bx, by, apex_z], [0, 0, -1], half_angle, "convex"),
        torus("cone boss base fillet", [bx, by, H + fb], z, base_major, fb, "concave"),
        torus("cone boss top fillet", [bx, by, H + hc - ft], z, top_major, ft, "convex"),
        plane("cone boss top", [bx, by, H + hc], [0, 0, 1]),
        cylinder("pin side", [px, py, H], z, rp, "convex"),
        torus("pin base fillet", [px, py, H + rpb], z, rp + rpb, rpb, "concave"),
        torus("pin top fillet", [px, py, z1], z, rp - rpt, rpt, "convex"),
        sphere("pin spherical cap", [px, py, zs], rs, "convex"),
        plane("pocket floor", [x0, y0, H - dp], [0, 0, 1]),
        plane("pocket wall x=min", [x0, y0, H], [1, 0, 0]),
        plane("pocket wall x=max", [x1, y0, H], [-1, 0, 0]),
        plane("pocket wall y=min", [x0, y0, H], [0, 1, 0]),
        plane("pocket wall y=max", [x0, y1, H], [0, -1, 0]),
    ]
    zf = H - dp + rk
    for cx, sx in ((x0 + rk, "x=min"), (x1 - rk, "x=max")):
        for cy, sy in ((y0 + rk, "y=min"), (y1 - rk, "y=max")):
            surfaces.append(cylinder(f"pocket vertical fillet at {sx}, {sy}", [cx, cy, H], z,
                                     rk, "concave"))
            surfaces.append(sphere(f"pocket corner at {sx}, {sy}", [cx, cy, zf], rk, "concave"))
    for cy, s in ((y0 + rk, "y=min"), (y1 - rk, "y=max")):
        surfaces.append(cylinder(f"pocket floor fillet along x at {s}", [x0, cy, zf],
                                 [1, 0, 0], rk, "concave"))
    for cx, s in ((x0 + rk, "x=min"), (x1 - rk, "x=max")):
        surfaces.append(cylinder(f"pocket floor fillet along y at {s}", [cx, y0, zf],
                                 [0, 1, 0], rk, "concave"))
    mesh = {"Mesh.MeshSizeMin": 0.7, "Mesh.MeshSizeMax": 10.0,
            "Mesh.MeshSizeFromCurvature": 10,
            "refine": {"gmsh_types": ["Torus", "Sphere", "Cone"], "size_near": 1.4,
                       "size_far": 10.0, "dist_near": 0.5, "dist_far": 5.0}}
    return ("block with G1 fillet junctions: torus corners between cylinders, cone-torus, "
            "sphere-torus, and a pocket with cylinder-cylinder-sphere corners", d, surfaces, mesh)


# Clamped uniform B-spline helpers (the freeform face of bspline_face).

def clamped_knots(n_control, degree):
    """Distinct knots and multiplicities of a clamped uniform knot vector on [0, 1]."""
    inner = n_control - degree - 1
    knots = [k / (inner + 1) for k in range(inner + 2)]
    mult = [degree + 1] + [1] * inner + [degree + 1]
    return knots, mult


def full_knot_vector(knots, mult):
    return np.repeat(np.asarray(knots, dtype=float), mult)


def greville(knots, mult, degree):
    t = full_knot_vector(knots, mult)
    n = len(t) - degree - 1
    return np.array([t[i + 1:i + degree + 1].mean() for i in range(n)])


def bspline_basis(knots, mult, degree, s):
    """Values of all B-spline basis functions at parameters s (m,) -> (m, n)."""
    t = full_knot_vector(knots, mult)
    n = len(t) - degree - 1
    s = np.clip(np.asarray(s, dtype=float), t[0], t[-1])
    # Degree 0 on half-open spans; the last span is closed at the end.
    b = np.zeros((len(s), len(t) - 1))
    for i in range(len(t) - 1):
        if t[i + 1] > t[i]:
            b[:, i] = (s >= t[i]) & (s < t[i + 1])
    last = max(i for i in range(len(t) - 1) if t[i + 1] > t[i])
    b[s >= t[-1], last] = 1.0
    for p in range(1, degree + 1):
        nb = np.zeros((len(s), len(t) - 1 - p))
        for i in range(len(t) - 1 - p):
            if t[i + p] > t[i]:
                nb[:, i] += (s - t[i]) / (t[i + p] - t[i]) * b[:, i]
            if t[i + p + 1] > t[i + 1]:
                nb[:, i] += (t[i + p + 1] - s) / (t[i + p + 1] - t[i + 1]) * b[:, i + 1]
        b = nb
    assert b.shape[1] == n
    return b


def bspline_graph(label, x_range, y_range, degree, z_control, convexity="mixed"):
    """A B-spline surface that is exactly the graph z = f(x, y) over a
    rectangle: control point (i, j) sits at the Greville abscissae of the
    clamped uniform knots, so x(u) and y(v) are linear (B-splines reproduce
    linear functions) and only z is free."""
    z_control = np.asarray(z_control, dtype=float)
    nu, nv = z_control.shape
    ku, mu = clamped_knots(nu, degree)
    kv, mv = clamped_knots(nv, degree)
    gu, gv = greville(ku, mu, degree), greville(kv, mv, degree)
    xs = x_range[0] + (x_range[1] - x_range[0]) * gu
    ys = y_range[0] + (y_range[1] - y_range[0]) * gv
    control = [[[float(xs[i]), float(ys[j]), float(z_control[i, j])] for j in range(nv)]
               for i in range(nu)]
    return {"label": label, "primitive": "unknown", "convexity": convexity,
            "surface": "bspline", "degree_u": degree, "degree_v": degree,
            "knots_u": ku, "multiplicities_u": mu, "knots_v": kv, "multiplicities_v": mv,
            "control_points": control,
            "graph": {"x_range": list(map(float, x_range)), "y_range": list(map(float, y_range)),
                      "note": ("z = f(x, y) with u = (x - x0) / (x1 - x0), "
                               "v = (y - y0) / (y1 - y0); control_points[i][j] is the "
                               "control point of basis functions N_i(u) N_j(v), "
                               "non-rational")}}


def bspline_graph_height(surf, x):
    """f(x, y) of a bspline_graph surface at points x (n x 3); NaN outside."""
    g = surf["graph"]
    u = (x[:, 0] - g["x_range"][0]) / (g["x_range"][1] - g["x_range"][0])
    v = (x[:, 1] - g["y_range"][0]) / (g["y_range"][1] - g["y_range"][0])
    cz = np.asarray(surf["control_points"], dtype=float)[:, :, 2]
    bu = bspline_basis(surf["knots_u"], surf["multiplicities_u"], surf["degree_u"], u)
    bv = bspline_basis(surf["knots_v"], surf["multiplicities_v"], surf["degree_v"], v)
    f = np.einsum("mi,ij,mj->m", bu, cz, bv)
    inside = (u >= -1e-12) & (u <= 1 + 1e-12) & (v >= -1e-12) & (v <= 1 + 1e-12)
    return np.where(inside, f, np.nan)


def build_bspline_face():
    """A block whose top is a freeform B-spline face, with planes and cylinders
    around it (a through hole, a boss, rounded vertical edges)."""
    occ = gmsh.model.occ
    d = {
        "block_size_x": 80.0, "block_size_y": 60.0, "block_origin": [0.0, 0.0, 0.0],
        "vertical_edge_fillet_radius": 8.0,
        "top_note": ("the top is a bicubic B-spline graph z = f(x, y) over x in [-10, 90], "
                     "y in [-10, 70] (control net 7 x 6, clamped uniform knots), "
                     "trimmed by the block sides; its exact definition is in the face entry"),
        "hole_center_x": 20.0, "hole_center_y": 20.0, "hole_radius": 5.0,
        "boss_center_x": 58.0, "boss_center_y": 38.0, "boss_radius": 7.0, "boss_top_z": 38.0,
        "boss_note": "a cylinder standing out of the freeform top (G0 edge with it)",
    }
    L, W = d["block_size_x"], d["block_size_y"]
    degree, nu, nv = 3, 7, 6
    x_range, y_range = (-10.0, L + 10.0), (-10.0, W + 10.0)
    ku, mu = clamped_knots(nu, degree)
    kv, mv = clamped_knots(nv, degree)
    gu, gv = greville(ku, mu, degree), greville(kv, mv, degree)
    # Heights: a tilted saddle with a bump, rounded to 1e-3 mm (the rounded
    # values are the definition). Curvature varies in sign and size.
    zc = np.array([[round(24.0 + 5.0 * math.sin(2.6 * u) * math.cos(3.3 * v) + 4.0 * u * u
                          - 3.0 * v + 2.5 * math.exp(-30.0 * ((u - 0.35) ** 2 + (v - 0.7) ** 2)), 3)
                    for v in gv] for u in gu])
    top = bspline_graph("freeform top", x_range, y_range, degree, zc)
    d["top_height_min_control"] = float(zc.min())
    d["top_height_max_control"] = float(zc.max())

    ctrl = top["control_points"]
    tags = [occ.addPoint(*ctrl[i][j]) for j in range(nv) for i in range(nu)]  # u fastest
    patch = occ.addBSplineSurface(tags, nu, degreeU=degree, degreeV=degree,
                                  knotsU=ku, knotsV=kv, multiplicitiesU=mu, multiplicitiesV=mv)
    occ.remove([(0, t) for t in tags])  # the control points are not part of the solid
    depth = 100.0
    below = [t for dim, t in occ.extrude([(2, patch)], 0, 0, -depth) if dim == 3]
    assert len(below) == 1, below
    box_h = 80.0
    box = occ.addBox(0, 0, 0, L, W, box_h)
    occ.synchronize()
    vertical = []
    for cx in (0.0, L):
        for cy in (0.0, W):
            vertical += entities_in_box(1, [cx, cy, 0], [cx, cy, box_h])
    assert len(vertical) == 4, vertical
    occ.fillet([box], vertical, [d["vertical_edge_fillet_radius"]], True)
    box = entities_in_box(3, [0, 0, 0], [L, W, box_h])
    occ.intersect([(3, below[0])], [(3, t) for t in box])
    solid = single_volume()
    bxc, byc, rbs, ztop = (d["boss_center_x"], d["boss_center_y"], d["boss_radius"],
                           d["boss_top_z"])
    boss = occ.addCylinder(bxc, byc, 5.0, 0, 0, ztop - 5.0, rbs)
    occ.fuse([(3, solid)], [(3, boss)])
    solid = single_volume()
    hx, hy, rh = d["hole_center_x"], d["hole_center_y"], d["hole_radius"]
    hole = occ.addCylinder(hx, hy, -1.0, 0, 0, box_h, rh)
    occ.cut([(3, solid)], [(3, hole)])

    z = [0.0, 0.0, 1.0]
    rv = d["vertical_edge_fillet_radius"]
    surfaces = [
        plane("block bottom", [0, 0, 0], [0, 0, -1]),
        plane("block side x=0", [0, 0, 0], [-1, 0, 0]),
        plane("block side x=L", [L, 0, 0], [1, 0, 0]),
        plane("block side y=0", [0, 0, 0], [0, -1, 0]),
        plane("block side y=W", [0, W, 0], [0, 1, 0]),
        plane("boss top", [bxc, byc, ztop], [0, 0, 1]),
        cylinder("boss side", [bxc, byc, 0], z, rbs, "convex"),
        cylinder("through hole", [hx, hy, 0], z, rh, "concave"),
        top,
    ]
    for cx, sx in ((rv, "x=0"), (L - rv, "x=L")):
        for cy, sy in ((rv, "y=0"), (W - rv, "y=W")):
            surfaces.append(cylinder(f"vertical edge fillet at {sx}, {sy}", [cx, cy, 0], z,
                                     rv, "convex"))
    mesh = {"Mesh.MeshSizeMin": 0.8, "Mesh.MeshSizeMax": 4.0,
            "Mesh.MeshSizeFromCurvature": 16}
    return ("block with a freeform B-spline top, a through hole, a boss and rounded vertical "
            "edges", d, surfaces, mesh)


def build_beam(over=None):
    """A plain box, long in x: the part of the width variant (a distance
    between two parallel planes changed, the face y = 0 kept)."""
    d = {"beam_size_x": 100.0, "beam_size_y": 10.0, "beam_size_z": 10.0,
         "beam_origin": [0.0, 0.0, 0.0]}
    d.update(over or {})
    L, W, H = d["beam_size_x"], d["beam_size_y"], d["beam_size_z"]
    gmsh.model.occ.addBox(0, 0, 0, L, W, H)
    surfaces = [
        plane("face x=0", [0, 0, 0], [-1, 0, 0]), plane("face x=L", [L, 0, 0], [1, 0, 0]),
        plane("face y=0", [0, 0, 0], [0, -1, 0]), plane("face y=W", [0, W, 0], [0, 1, 0]),
        plane("face z=0", [0, 0, 0], [0, 0, -1]), plane("face z=H", [0, 0, H], [0, 0, 1]),
    ]
    mesh = {"Mesh.MeshSizeMin": 1.0, "Mesh.MeshSizeMax": 2.3}
    return "box 100 x 10 x 10 (x along the length)", d, surfaces, mesh


PARTS = {
    "boss_block": build_boss_block,
    "filleted_box": build_filleted_box,
    "cone_sphere_torus": build_cone_sphere_torus,
    "fillet_junctions": build_fillet_junctions,
    "bspline_face": build_bspline_face,
    "beam": build_beam,
}

# Changed-CAD variants of the parts (--variants): name -> the dimensions that
# change (overrides of the builder's dimensions) and what changes, in words.
# The identity variant "base" (no change) is written for every part listed,
# as the CAD truth of the base part at the sampling density of the variants.
VARIANTS = {
    "boss_block": {
        "boss_height_20": ({"boss_height": 20.0}, "boss height 15 -> 20"),
        "boss_height_10": ({"boss_height": 10.0}, "boss height 15 -> 10"),
        "boss_radius_14": ({"boss_radius": 14.0}, "boss radius 12 -> 14"),
        "boss_radius_10": ({"boss_radius": 10.0}, "boss radius 12 -> 10"),
        "boss_fillet_radius_4": ({"boss_fillet_radius": 4.0}, "boss base fillet radius 3 -> 4"),
        "boss_fillet_radius_2": ({"boss_fillet_radius": 2.0}, "boss base fillet radius 3 -> 2"),
        "boss_chamfer_length_3": ({"boss_chamfer_length": 3.0},
                                  "boss chamfer 2 x 45 deg -> 3 x 45 deg"),
        "boss_chamfer_angle_60": ({"boss_chamfer_angle_deg": 60.0},
                                  "boss chamfer angle to the top face 45 -> 60 deg, its leg on "
                                  "the top face kept (2 mm: it meets the top face in the same "
                                  "circle, radius 10); its leg on the side 2 -> 2 tan 60 deg"),
        "boss_moved": ({"boss_center_x": 40.0, "boss_center_y": 40.0},
                       "boss (with its fillet and chamfer) moved by (5, 10) on the block top"),
        "hole_radius_8": ({"hole_radius": 8.0}, "through hole radius 6 -> 8"),
        "hole_radius_4": ({"hole_radius": 4.0}, "through hole radius 6 -> 4"),
    },
    "cone_sphere_torus": {
        "cap_sphere_radius_11": ({"cap_sphere_radius": 11.0,
                                  "cap_sphere_center_z": 42.0 - math.sqrt(17.0)},
                                 "cap sphere radius 9 -> 11, its centre kept (z = 42 - sqrt 17): "
                                 "the cone, apex and half angle kept, now meets the sphere higher "
                                 "up, where its line leaves the sphere"),
        "shaft_radius_13": ({"shaft_radius": 13.0, "shaft_height": 17.0, "cone_height": 15.0},
                            "shaft radius 12 -> 13; the fillet keeps its radius 4 (torus major "
                            "16 -> 17); the cone keeps its surface (apex z = 66, half angle "
                            "18.43 deg), so the shaft meets it 3 mm lower (z = 27) and the "
                            "cone goes from radius 13 to 8 over 15 mm"),
    },
    "filleted_box": {
        "edge_fillet_radius_8": ({"edge_fillet_radius": 8.0},
                                 "edge fillet radius 6 -> 8 (12 cylinders, 8 sphere corners)"),
    },
    "beam": {
        "width20": ({"beam_size_y": 20.0}, "beam width (y) 10 -> 20, the face y = 0 kept"),
    },
}
# Sizes of the variants' CAD surface samples: the part's mesh sizes times this.
VARIANT_SAMPLE_SCALE = 0.5


# ----------------------------------------------------------------------------
# Mesh extraction
# ----------------------------------------------------------------------------

def signed_volumes(points, tets):
    p0, p1, p2, p3 = (points[tets[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", p1 - p0, np.cross(p2 - p0, p3 - p0)) / 6.0


def classify_nodes(used):
    """Per node of `used` (sorted Gmsh tags): the dimension and tag of the
    entity it is classified on (its own, not its closure), from the
    lowest-dimensional entity up."""
    entity_dim = np.full(len(used), -1, dtype=np.int32)
    entity_tag = np.full(len(used), -1, dtype=np.int32)
    for dim in range(4):
        for _, tag in gmsh.model.getEntities(dim):
            ntags, _, _ = gmsh.model.mesh.getNodes(dim, tag, includeBoundary=False,
                                                   returnParametricCoord=False)
            ntags = np.asarray(ntags, dtype=np.int64)
            idx = np.searchsorted(used, ntags)
            keep = idx < len(used)
            keep[keep] = used[idx[keep]] == ntags[keep]  # nodes no cell uses are skipped
            idx = idx[keep]
            assert len(np.unique(idx)) == len(idx) and np.all(entity_dim[idx] == -1), (
                f"node classified twice (entity {dim}, {tag})")
            entity_dim[idx] = dim
            entity_tag[idx] = tag
    assert np.all(entity_dim >= 0), "unclassified node"
    return entity_dim, entity_tag


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

    def remap(tags):
        """Gmsh node tags -> 0-based indices into `used` (sorted)."""
        tags = np.asarray(tags, dtype=np.int64)
        idx = np.searchsorted(used, tags)
        assert np.all(idx < len(used)) and np.all(used[np.minimum(idx, len(used) - 1)] == tags), \
            "element uses a node no tet uses"
        return idx.astype(np.int64)

    tets = remap(tet_tags)

    # Gmsh's reference tet is (0,0,0),(1,0,0),(0,1,0),(0,0,1), the same
    # handedness as VTK's; still check every element and flip any negative one.
    vol6 = signed_volumes(points, tets)
    negative = int(np.count_nonzero(vol6 < 0))
    if negative:
        tets[vol6 < 0] = tets[vol6 < 0][:, [0, 1, 3, 2]]
    vol6 = signed_volumes(points, tets)
    assert np.all(vol6 > 0), "non-positive tet volume after orientation fix"

    entity_dim, entity_tag = classify_nodes(used)

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


def face_keys(rows, n_points):
    """One int64 key per row of 3 sorted vertex ids (21 bits each), or, for
    more than 2^21 points, dense ids from np.unique over all rows given."""
    rows = np.asarray(rows, dtype=np.int64)
    if n_points < (1 << 21):
        return (rows[:, 0] << 42) | (rows[:, 1] << 21) | rows[:, 2]
    _, inverse = np.unique(rows, axis=0, return_inverse=True)
    return inverse.astype(np.int64).reshape(-1)


def cad_face_labels(tets, triangles):
    """CADFace: per tet and local face i, the surface tag of the boundary face
    opposite vertex i, -1 for interior faces. Faces are matched as vertex
    sets (sorted ids); a boundary face is one that only one tet has."""
    n_tets = len(tets)
    n_points = int(tets.max()) + 1
    tet_faces = np.sort(tets[:, OPPOSITE_FACE], axis=2).reshape(-1, 3)  # slot = 4 t + i
    tri_list = [(stag, np.sort(tris, axis=1)) for stag, tris in triangles.items()]
    all_rows = np.vstack([tet_faces] + [t for _, t in tri_list])
    keys = face_keys(all_rows, n_points)
    face_key, tri_keys = keys[:len(tet_faces)], keys[len(tet_faces):]

    order = np.argsort(face_key, kind="stable")
    sk = face_key[order]
    differs = sk[1:] != sk[:-1]
    first = np.concatenate(([True], differs))
    last = np.concatenate((differs, [True]))
    single = first & last
    boundary_keys, boundary_slots = sk[single], order[single]

    labels = np.full(4 * n_tets, -1, dtype=np.int32)
    matched = 0
    offset = 0
    for stag, tris in tri_list:
        k = tri_keys[offset:offset + len(tris)]
        offset += len(tris)
        pos = np.minimum(np.searchsorted(boundary_keys, k), len(boundary_keys) - 1)
        ok = boundary_keys[pos] == k
        assert np.all(ok), (f"surface {stag} triangle {tris[np.argmin(ok)].tolist()} "
                            "is not a boundary tet face")
        slots = boundary_slots[pos]
        assert len(np.unique(slots)) == len(slots) and np.all(labels[slots] == -1), \
            "boundary face labelled twice"
        labels[slots] = stag
        matched += len(slots)
    assert matched == len(boundary_keys), (
        f"{len(boundary_keys) - matched} boundary tet faces without a CAD surface")
    return labels.reshape(n_tets, 4), len(boundary_keys)


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

def write_vtu(path, points, tets, cad_face, entity_dim, entity_tag, cell_type=VTK_TETRA_TYPE):
    if HAVE_VTK:
        write_vtu_vtk(path, points, tets, cad_face, entity_dim, entity_tag, cell_type)
    else:
        write_vtu_ascii(path, points, tets, cad_face, entity_dim, entity_tag, cell_type)


def int_array(name, values, components=1):
    arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.int32), deep=1)
    arr.SetName(name)
    arr.SetNumberOfComponents(components)
    return arr


def write_vtu_vtk(path, points, tets, cad_face, entity_dim, entity_tag,
                  cell_type=VTK_TETRA_TYPE):
    """`tets`: the cells, one row each, all of VTK type `cell_type`;
    `cad_face`: one component per cell face."""
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
    grid.SetPoints(pts)
    n, k = tets.shape
    conn = np.hstack([np.full((n, 1), k, dtype=np.int64), tets.astype(np.int64)]).ravel()
    cells = vtkCellArray()
    cells.SetCells(n, numpy_to_vtkIdTypeArray(conn, deep=1))
    grid.SetCells(cell_type, cells)
    grid.GetCellData().AddArray(int_array("CADFace", cad_face.reshape(-1), cad_face.shape[1]))
    grid.GetPointData().AddArray(int_array("CADEntityDim", entity_dim))
    grid.GetPointData().AddArray(int_array("CADEntityTag", entity_tag))
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(grid)
    w.SetCompressorTypeToZLib()
    w.SetDataModeToAppended()
    w.EncodeAppendedDataOff()
    assert w.Write() == 1, f"VTK could not write {path}"


def write_vtu_ascii(path, points, tets, cad_face, entity_dim, entity_tag,
                    cell_type=VTK_TETRA_TYPE):
    def rows(a, fmt):
        return "\n".join(" ".join(fmt % v for v in r) for r in np.atleast_2d(a))

    n, k = tets.shape
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
                'byte_order="LittleEndian" header_type="UInt64">\n<UnstructuredGrid>\n')
        f.write(f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{n}">\n')
        f.write('<PointData>\n')
        for name, a in (("CADEntityDim", entity_dim), ("CADEntityTag", entity_tag)):
            f.write(f'<DataArray type="Int32" Name="{name}" format="ascii">\n')
            f.write(rows(a.reshape(-1, 1), "%d") + "\n</DataArray>\n")
        f.write('</PointData>\n<CellData>\n')
        f.write(f'<DataArray type="Int32" Name="CADFace" NumberOfComponents="{cad_face.shape[1]}" '
                'format="ascii">\n')
        f.write(rows(cad_face, "%d") + "\n</DataArray>\n</CellData>\n")
        f.write('<Points>\n<DataArray type="Float64" NumberOfComponents="3" format="ascii">\n')
        f.write(rows(points, "%.17g") + "\n</DataArray>\n</Points>\n<Cells>\n")
        f.write('<DataArray type="Int64" Name="connectivity" format="ascii">\n')
        f.write(rows(tets, "%d") + "\n</DataArray>\n")
        f.write('<DataArray type="Int64" Name="offsets" format="ascii">\n')
        f.write(rows((np.arange(1, n + 1) * k).reshape(-1, 1), "%d") + "\n</DataArray>\n")
        f.write('<DataArray type="UInt8" Name="types" format="ascii">\n')
        f.write(rows(np.full((n, 1), cell_type), "%d") + "\n</DataArray>\n")
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


def scaled_sizes(size_options, scale):
    """The part's mesh sizes times `scale` (curvature sizing: elements per
    2 pi divided by it), for the fine versions of the parts."""
    size_options = dict(size_options)
    if scale == 1.0:
        return size_options
    for key in ("Mesh.MeshSizeMin", "Mesh.MeshSizeMax"):
        if key in size_options:
            size_options[key] = size_options[key] * scale
    if "Mesh.MeshSizeFromCurvature" in size_options:
        size_options["Mesh.MeshSizeFromCurvature"] = int(round(
            size_options["Mesh.MeshSizeFromCurvature"] / scale))
    if size_options.get("refine"):
        refine = dict(size_options["refine"])
        refine["size_near"] *= scale
        refine["size_far"] *= scale
        size_options["refine"] = refine
    return size_options


def setup_part(name, scale=1.0, overrides=None):
    """Build part `name` (with the dimensions `overrides` changed) in a new
    Gmsh model and set its mesh options (sizes times `scale`); returns the
    builder's output and the options set."""
    gmsh.model.add(name)
    if overrides is None:
        description, dims, candidates, size_options = PARTS[name]()
    else:
        description, dims, candidates, size_options = PARTS[name](overrides)
    gmsh.model.occ.synchronize()

    options = dict(COMMON_MESH_OPTIONS)
    size_options = scaled_sizes(size_options, scale)
    refine = size_options.pop("refine", None)
    options.update(size_options)
    for key, value in options.items():
        gmsh.option.setNumber(key, value)
    if refine:
        refine = refine_near_surfaces(**refine)
    return description, dims, candidates, options, refine


def surface_triangle_count(name, scale):
    """Boundary triangles of part `name` meshed (surfaces only) at `scale`."""
    setup_part(name, scale)
    gmsh.model.mesh.generate(2)
    count = 0
    for _, stag in gmsh.model.getEntities(2):
        _, elem_tags, _ = gmsh.model.mesh.getElements(2, stag)
        count += sum(len(t) for t in elem_tags)
    gmsh.model.remove()
    return count


def fine_scale(name, target_triangles):
    """Size scale giving about `target_triangles` boundary triangles. The
    count goes about as scale^-b (b near 2): two cheap surface-only meshings,
    at scale 1 and at a scale aimed at a quarter of the target, fit b and
    the constant, and the fit gives the scale."""
    history = []
    c0 = surface_triangle_count(name, 1.0)
    history.append({"scale": 1.0, "boundary_triangles": c0})
    s1 = math.sqrt(c0 / (0.25 * target_triangles))
    c1 = surface_triangle_count(name, s1)
    history.append({"scale": s1, "boundary_triangles": c1})
    b = math.log(c1 / c0) / math.log(1.0 / s1) if c1 != c0 and s1 != 1.0 else 2.0
    scale = s1 * (c1 / target_triangles) ** (1.0 / b)
    return scale, history


def generate(name, out_dir, scale=1.0, out_name=None, fine=None, overrides=None):
    """Mesh part `name` and write <out_name>.vtu/.json (out_name defaults to
    name). scale multiplies the part's mesh sizes (fine versions); `fine` is
    recorded in the JSON; `overrides` changes dimensions (a variant meshed
    with the part's own options, for the checker's self-test)."""
    out_name = out_name or name
    description, dims, candidates, options, refine = setup_part(name, scale, overrides)
    if fine is None:
        gmsh.model.mesh.generate(3)
    else:
        # Fine surfaces, coarse inside: mesh the surfaces with the scaled
        # sizes, then fill the volume without extending the surface sizes
        # inwards, up to the part's own maximum size, with Gmsh's fast HXT
        # algorithm (the Delaunay one takes minutes at this size). HXT's tets
        # vary slightly from run to run; the surface mesh does not.
        start = time.perf_counter()
        gmsh.model.mesh.generate(2)
        print(f"  surface mesh {time.perf_counter() - start:.1f} s", flush=True)
        volume_options = {"Mesh.MeshSizeExtendFromBoundary": 0,
                          "Mesh.MeshSizeMax": options["Mesh.MeshSizeMax"] / scale,
                          "Mesh.Algorithm3D": 10}
        for key, value in volume_options.items():
            gmsh.option.setNumber(key, value)
        fine["volume_mesh_options"] = volume_options
        start = time.perf_counter()
        gmsh.model.mesh.generate(3)
        print(f"  volume mesh {time.perf_counter() - start:.1f} s", flush=True)
        start = time.perf_counter()

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
        "name": out_name,
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
        "cad_volume": float(gmsh.model.occ.getMass(3, single_volume())),
        "orientation": {"gmsh_negative_tets_flipped": negative,
                        "convention": "(p1-p0).((p2-p0)x(p3-p0)) > 0 for every tet"},
        "max_node_distance_by_type": worst,
        "construction_surfaces_split_into_several_faces": split,
        "faces": faces,
        "curves": curves,
    }
    if fine is not None:
        info["fine"] = fine
    write_vtu(os.path.join(out_dir, out_name + ".vtu"), points, tets, cad_face,
              entity_dim, entity_tag)
    with open(os.path.join(out_dir, out_name + ".json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")
    if fine is not None:
        print(f"  arrays, checks and files {time.perf_counter() - start:.1f} s", flush=True)
    gmsh.model.remove()
    return info


# ----------------------------------------------------------------------------
# Changed-CAD variants (--variants): the CAD truth of a part with one
# dimension changed, for the tests of FEMorph Deform (thesis 2.5). No volume
# mesh: a fine triangle mesh of the variant's boundary (Gmsh 2D, the part's
# sizes times VARIANT_SAMPLE_SCALE) and the JSON of its faces.
# ----------------------------------------------------------------------------

def write_vtp(path, points, triangles, cad_face):
    """Triangles with the cell array CADFace (Gmsh surface tag), VTK XML
    PolyData, appended raw binary, zlib, 32-bit connectivity."""
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
    poly = vtkPolyData()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
    poly.SetPoints(pts)
    n = len(triangles)
    conn = np.hstack([np.full((n, 1), 3, dtype=np.int64), triangles.astype(np.int64)]).ravel()
    cells = vtkCellArray()
    cells.SetCells(n, numpy_to_vtkIdTypeArray(conn, deep=1))
    poly.SetPolys(cells)
    poly.GetCellData().AddArray(int_array("CADFace", cad_face))
    w = vtkXMLPolyDataWriter()
    w.SetFileName(path)
    w.SetInputData(poly)
    w.SetCompressorTypeToZLib()
    w.SetDataModeToAppended()
    w.EncodeAppendedDataOff()
    w.SetIdTypeToInt32()
    assert w.Write() == 1, f"VTK could not write {path}"


def generate_variant(name, variant, overrides, change, out_dir, base_labels=None):
    """Write <out_dir>/<name>__<variant>.json/.vtp: the part built with the
    dimensions `overrides` changed; returns the JSON's content. base_labels:
    the labels the faces must have (the base part's)."""
    out_name = f"{name}__{variant}"
    description, dims, candidates, options, refine = setup_part(
        name, VARIANT_SAMPLE_SCALE, overrides)
    gmsh.model.mesh.generate(2)
    triangles, nodes = {}, []
    for _, stag in gmsh.model.getEntities(2):
        types, _, ntags = gmsh.model.mesh.getElements(2, stag)
        assert list(types) == [GMSH_TRIANGLE], f"surface {stag}: element types {types}"
        triangles[stag] = np.asarray(ntags[0], dtype=np.int64).reshape(-1, 3)
        nodes.append(triangles[stag].ravel())
    used = np.unique(np.concatenate(nodes))
    all_tags, all_coords, _ = gmsh.model.mesh.getNodes()
    all_tags = np.asarray(all_tags, dtype=np.int64)
    order = np.argsort(all_tags)
    pos = np.searchsorted(all_tags[order], used)
    assert np.all(all_tags[order][pos] == used)
    points = np.asarray(all_coords, dtype=float).reshape(-1, 3)[order[pos]]
    triangles = {t: np.searchsorted(used, tris) for t, tris in triangles.items()}

    lo, hi = points.min(axis=0), points.max(axis=0)
    part_size = float(np.linalg.norm(hi - lo))
    faces, split = describe_surfaces(points, triangles, candidates, part_size)
    assert not split, f"{out_name}: construction surfaces split into several faces: {split}"
    labels = sorted(f["label"] for f in faces)
    assert base_labels is None or labels == sorted(base_labels), (
        f"{out_name}: face labels differ from the base part's")
    curves = describe_curves(part_size)
    tags = sorted(triangles)
    all_tris = np.vstack([triangles[t] for t in tags])
    cad_face = np.concatenate([np.full(len(triangles[t]), t, dtype=np.int32) for t in tags])
    by_type = {}
    for f in faces:
        by_type[f["primitive"]] = by_type.get(f["primitive"], 0) + 1
    info = {
        "name": out_name,
        "base_part": name,
        "variant": variant,
        "change": change,
        "changed_dimensions": {k: v for k, v in overrides.items()},
        "description": description,
        "units": "mm",
        "generator": "Data/generate_parts.py --variants (Gmsh OpenCASCADE kernel)",
        "gmsh_version": gmsh.option.getString("General.Version"),
        "dimensions": dims,
        "cad_volume": float(gmsh.model.occ.getMass(3, single_volume())),
        "bounding_box": {"min": lo.tolist(), "max": hi.tolist()},
        "sample": {"file": out_name + ".vtp",
                   "what": ("Gmsh surface mesh of the variant's CAD boundary, nodes on the CAD "
                            "surfaces; cell array CADFace = the face's tag below"),
                   "size_scale": VARIANT_SAMPLE_SCALE, "mesh_options": options,
                   "mesh_refinement": refine,
                   "points": int(len(points)), "triangles": int(len(all_tris))},
        "counts": {"surfaces": len(faces), "curves": len(curves), "surfaces_by_type": by_type},
        "faces": faces,
        "curves": curves,
    }
    write_vtp(os.path.join(out_dir, out_name + ".vtp"), points, all_tris, cad_face)
    with open(os.path.join(out_dir, out_name + ".json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")
    gmsh.model.remove()
    return info


def generate_variants(out_dir, parts=None):
    """The identity variant <part>__base and every variant of VARIANTS for
    the parts given (all by default), into out_dir."""
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    for name, variants in VARIANTS.items():
        if parts and name not in parts:
            continue
        base = generate_variant(name, "base", {}, "none (the base part's CAD)", out_dir)
        base_labels = [f["label"] for f in base["faces"]]
        rows.append(base)
        for variant, (overrides, change) in variants.items():
            rows.append(generate_variant(name, variant, overrides, change, out_dir, base_labels))
    return rows


# ----------------------------------------------------------------------------
# STEP files made by others (--step): import, mesh, and find what each face
# really is. Gmsh gives no parameters for an imported face, and it calls OCC
# surfaces of revolution or extrusion and B-splines "Unknown" even when they
# are exactly cylinders; so every face's nodes (which Gmsh puts on the CAD
# surface) are fitted, with the surface normals at the nodes (from the CAD
# surface) to find axes.
# ----------------------------------------------------------------------------

# A face is a primitive when all its nodes are within this fraction of the
# part's bounding box diagonal of the fitted surface.
STEP_FIT_TOLERANCE = 1e-7
# Default mesh sizes, as fractions of the bounding box diagonal and elements
# per 2 pi of curvature.
STEP_SIZE_MAX_FRACTION = 1.0 / 50.0
STEP_SIZE_MIN_RATIO = 1.0 / 20.0     # minimum size / maximum size
STEP_CURVATURE_ELEMENTS = 20
# Fits tried on a face Gmsh calls "Unknown" (or any type it has no primitive
# for), simplest first.
STEP_FIT_ORDER = ["plane", "sphere", "cylinder", "cone", "torus"]


def fit_circle_2d(p):
    """Algebraic (Kasa) circle fit to 2D points: centre and radius."""
    a = np.column_stack([2.0 * p, np.ones(len(p))])
    sol, *_ = np.linalg.lstsq(a, np.einsum("ij,ij->i", p, p), rcond=None)
    center = sol[:2]
    r2 = sol[2] + center @ center
    return center, math.sqrt(r2) if r2 > 0 else float("nan")


def perpendicular_basis(a):
    e1 = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 = unit(e1)
    return e1, np.cross(a, e1)


def fit_plane_nodes(x, n):
    c = x.mean(axis=0)
    normal = np.linalg.svd(x - c, full_matrices=False)[2][-1]
    return plane("", c, normal)


def fit_sphere_nodes(x, n):
    c0 = x.mean(axis=0)
    a = np.column_stack([2.0 * (x - c0), np.ones(len(x))])
    sol, *_ = np.linalg.lstsq(a, np.einsum("ij,ij->i", x - c0, x - c0), rcond=None)
    r2 = sol[3] + sol[:3] @ sol[:3]
    if not r2 > 0:
        return None
    return sphere("", c0 + sol[:3], math.sqrt(r2), "")


def fit_cylinder_nodes(x, n):
    """Axis: the direction all normals are perpendicular to; then a circle
    in the plane across it."""
    w, v = np.linalg.eigh(n.T @ n)
    a = v[:, 0]
    e1, e2 = perpendicular_basis(a)
    c0 = x.mean(axis=0)
    p = np.column_stack([(x - c0) @ e1, (x - c0) @ e2])
    center, r = fit_circle_2d(p)
    if not r > 0:
        return None
    return cylinder("", c0 + center[0] * e1 + center[1] * e2, a, r, "")


def fit_cone_nodes(x, n):
    """Axis: the normals make one angle with it (they lie on a circle of the
    unit sphere); apex: every normal is perpendicular to its generator, so
    n.(x - apex) = 0."""
    nm = n.mean(axis=0)
    a = np.linalg.svd(n - nm, full_matrices=False)[2][-1]
    s = float(nm @ a)
    if abs(s) < 1e-6:
        return None  # a cylinder (or plane)
    apex, *_ = np.linalg.lstsq(n, np.einsum("ij,ij->i", n, x), rcond=None)
    h, rho = axial_split(x, apex, a)
    if np.mean(h) < 0:
        a, h = -a, -h
    half_angle = math.degrees(math.atan2(float(np.mean(rho)), float(np.mean(h))))
    return cone("", apex, a, half_angle, "")


def fit_torus_nodes(x, n):
    """Axis: the line every normal line meets (surface of revolution). In
    Pluecker coordinates the axis (a, m = c x a) meets the normal line
    (n, x x n) when a.(x x n) + n.m = 0: linear, solved by SVD. Then the
    meridian profile (rho, h) is a circle."""
    c0 = x.mean(axis=0)
    xc = x - c0
    rows = np.column_stack([np.cross(xc, n), n])
    v = np.linalg.svd(rows, full_matrices=False)[2][-1]
    a, m = v[:3], v[3:]
    if np.linalg.norm(a) < 1e-9:
        return None
    m = m / np.linalg.norm(a)
    a = unit(a)
    foot = c0 + np.cross(a, m)
    h, rho = axial_split(x, foot, a)
    center, r = fit_circle_2d(np.column_stack([rho, h]))
    if not (r > 0 and center[0] > 0):
        return None
    return torus("", foot + center[1] * a, a, center[0], r, "")


FIT_OF_PRIMITIVE = {"plane": fit_plane_nodes, "sphere": fit_sphere_nodes,
                    "cylinder": fit_cylinder_nodes, "cone": fit_cone_nodes,
                    "torus": fit_torus_nodes}


def cad_normals(stag, x):
    """Unit normals of CAD surface stag at points x on it."""
    uv = gmsh.model.getParametrization(2, stag, x.ravel().tolist())
    n = np.asarray(gmsh.model.getNormal(stag, uv), dtype=float).reshape(-1, 3)
    return n / np.linalg.norm(n, axis=1)[:, None]


def boundary_face_geometry(points, tets, cad_face):
    """Per CAD surface tag: vertex triples, centroids and outward area
    vectors (half the cross product, pointing away from the tet) of its
    boundary tet faces."""
    t, i = np.nonzero(cad_face >= 0)
    opposite = np.asarray(OPPOSITE_FACE)[i]
    tri = tets[t[:, None], opposite]
    p0, p1, p2 = (points[tri[:, k]] for k in range(3))
    area_vec = np.cross(p1 - p0, p2 - p0) / 2.0
    inward = points[tets[t, i]] - p0
    flip = np.einsum("ij,ij->i", area_vec, inward) > 0
    area_vec[flip] *= -1.0
    centroid = (p0 + p1 + p2) / 3.0
    labels = cad_face[t, i]
    return {int(s): (tri[labels == s], centroid[labels == s], area_vec[labels == s])
            for s in np.unique(labels)}


def mesh_convexity(tri, area_vec, nodes, x, normals):
    """Convexity of a face seen from outside, from the CAD surface normals at
    its nodes (`nodes`, at positions x; turned to point out of the material
    like the triangles `tri`): along each mesh edge p-q the normals spread
    apart, (n_q - n_p).(q - p) > 0, on a convex surface and come together on
    a concave one. 'flat' when they never turn, 'mixed' unless one sign has
    99% of the sum of the normal curvatures |(n_q - n_p).(q - p)| / |q - p|^2."""
    index = {int(v): k for k, v in enumerate(nodes)}
    local = np.vectorize(index.__getitem__)(tri)
    n = np.asarray(normals, dtype=float)
    if np.sum(n[local].mean(axis=1) * area_vec) < 0:
        n = -n
    edges = np.unique(np.sort(np.vstack([local[:, [0, 1]], local[:, [1, 2]],
                                         local[:, [2, 0]]]), axis=1), axis=0)
    d = x[edges[:, 1]] - x[edges[:, 0]]
    kappa = np.einsum("ij,ij->i", n[edges[:, 1]] - n[edges[:, 0]], d) / np.einsum(
        "ij,ij->i", d, d)
    total = np.sum(np.abs(kappa))
    if total == 0:
        return "flat"
    if np.sum(kappa[kappa > 0]) > 0.99 * total:
        return "convex"
    if -np.sum(kappa[kappa < 0]) > 0.99 * total:
        return "concave"
    return "mixed"


def orient_fitted_surface(surf, centroid, area_vec):
    """Plane normal out of the material; convexity of curved faces seen from
    outside: convex when the outward normal points away from the axis /
    centre / tube circle. 'mixed' if the face's triangles disagree."""
    kind = surf["primitive"]
    if kind == "plane":
        if np.sum(area_vec @ np.asarray(surf["normal"])) < 0:
            surf["normal"] = [-c for c in surf["normal"]]
        surf["convexity"] = "flat"
        return surf
    if kind in ("cylinder", "cone", "torus"):
        origin = np.asarray(surf.get("axis_point", surf.get("apex", surf.get("center"))))
        a = np.asarray(surf["axis_direction"])
        v = centroid - origin
        radial = v - np.outer(v @ a, a)
        if kind == "torus":
            radial = v - unit_rows(radial) * surf["major_radius"]
    else:  # sphere
        radial = centroid - np.asarray(surf["center"])
    s = np.einsum("ij,ij->i", area_vec, unit_rows(radial))
    area = np.linalg.norm(area_vec, axis=1)
    if np.sum(area[s > 0]) > 0.999 * np.sum(area):
        surf["convexity"] = "convex"
    elif np.sum(area[s < 0]) > 0.999 * np.sum(area):
        surf["convexity"] = "concave"
    else:
        surf["convexity"] = "mixed"
    return surf


def unit_rows(v):
    return v / np.linalg.norm(v, axis=1)[:, None]


def describe_unknown_face(stag, x, n):
    """What can be said of a face no primitive fits: whether it is a general
    extrusion (all normals perpendicular to one direction) and the range of
    its curvature radii at the nodes (1 / the larger principal curvature,
    Gmsh's evaluation on the CAD surface)."""
    uv = gmsh.model.getParametrization(2, stag, x.ravel().tolist())
    k1, k2, _, _ = gmsh.model.getPrincipalCurvatures(stag, uv)
    k = np.maximum(np.abs(np.asarray(k1)), np.abs(np.asarray(k2)))
    radii = 1.0 / k[k > 0] if np.any(k > 0) else np.array([np.inf])
    shape = {"curvature_radius_range": [float(radii.min()), float(radii.max())]}
    w, v = np.linalg.eigh(n.T @ n)
    d = v[:, 0]
    off = float(np.max(np.abs(n @ d)))
    if off < 1e-7:
        shape.update({"kind": "general extrusion (normals perpendicular to one direction)",
                      "extrusion_direction": d.tolist(), "max_normal_component": off})
    else:
        shape["kind"] = "freeform"
    return shape


def identify_step_faces(points, triangles, cad_face, tets, part_size):
    """One JSON entry per CAD surface of an imported STEP: Gmsh's type, the
    primitive and its parameters from a fit of the face's nodes (the type
    Gmsh names, else the simplest that fits within the tolerance; else
    'unknown'), the deviations of the fits tried, and the largest distance
    of the nodes to the CAD surface itself (OCC's projection)."""
    tolerance = STEP_FIT_TOLERANCE * part_size
    geometry = boundary_face_geometry(points, tets, cad_face)
    faces = []
    for _, stag in gmsh.model.getEntities(2):
        gmsh_type = gmsh.model.getType(2, stag)
        tris = triangles[stag]
        nodes = np.unique(tris)
        x = points[nodes]
        n = cad_normals(stag, x)
        closest, _ = gmsh.model.getClosestPoint(2, stag, x.ravel().tolist())
        cad_distance = float(np.max(np.linalg.norm(
            np.asarray(closest).reshape(-1, 3) - x, axis=1)))
        named = PRIMITIVE_OF_GMSH_TYPE.get(gmsh_type)
        tried = {}
        found = None
        for kind in ([named] if named else STEP_FIT_ORDER):
            surf = FIT_OF_PRIMITIVE[kind](x, n)
            if surf is None:
                tried[kind] = None
                continue
            dev = float(np.max(distance_to_surface(surf, x)))
            tried[kind] = dev
            if dev < tolerance:
                found = (surf, dev)
                break
        if named:
            assert found, (f"surface {stag}: Gmsh type {gmsh_type}, but its nodes are "
                           f"{tried[named]:.3g} from the fitted {named} (> {tolerance:.3g})")
        tri, centroid, area_vec = geometry[stag]
        if found:
            surf, dev = found
            surf = orient_fitted_surface(surf, centroid, area_vec)
            source = "Gmsh type, parameters fitted" if named else "fit"
            assert surf["convexity"] != "mixed", f"surface {stag}: {surf['primitive']} of mixed sides"
            if surf["primitive"] in ("cylinder", "cone", "sphere"):
                seen = mesh_convexity(tri, area_vec, nodes, x, n)
                assert seen == surf["convexity"], (
                    f"surface {stag}: fitted {surf['primitive']} {surf['convexity']}, "
                    f"the CAD normals along the mesh edges say {seen}")
        else:
            surf = {"primitive": "unknown",
                    "convexity": mesh_convexity(tri, area_vec, nodes, x, n)}
            dev = cad_distance
            surf["shape"] = describe_unknown_face(stag, x, n)
            source = "no primitive fits"
        surf.pop("label", None)
        p0, p1, p2 = (points[tris[:, i]] for i in range(3))
        area = float(np.sum(np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)) / 2.0)
        entry = {"tag": int(stag), "gmsh_type": gmsh_type,
                 "label": f"face {stag} ({gmsh_type})"}
        entry.update(surf)
        entry.update({"primitive_from": source,
                      "fit_max_deviation": tried,
                      "triangle_count": int(len(tris)), "node_count": int(len(nodes)),
                      "area": area, "max_node_distance": dev,
                      "max_node_distance_to_cad_surface": cad_distance})
        faces.append(entry)
    return faces


def same_surface(f, g, tol):
    """Whether two fitted faces lie on one primitive surface."""
    if f["primitive"] != g["primitive"] or f["primitive"] == "unknown":
        return False
    kind = f["primitive"]
    if kind == "plane":
        return (abs(abs(np.dot(f["normal"], g["normal"])) - 1) < 1e-9 and
                abs(np.dot(np.subtract(g["point"], f["point"]), f["normal"])) < tol)
    axis_ok = lambda: abs(abs(np.dot(f["axis_direction"], g["axis_direction"])) - 1) < 1e-9
    if kind == "cylinder":
        return (axis_ok() and abs(f["radius"] - g["radius"]) < tol and
                axial_split(np.array([g["axis_point"]]), f["axis_point"],
                            f["axis_direction"])[1][0] < tol)
    if kind == "cone":
        return (axis_ok() and abs(f["half_angle_deg"] - g["half_angle_deg"]) < 1e-6 and
                np.linalg.norm(np.subtract(f["apex"], g["apex"])) < tol)
    if kind == "sphere":
        return (abs(f["radius"] - g["radius"]) < tol and
                np.linalg.norm(np.subtract(f["center"], g["center"])) < tol)
    return (axis_ok() and abs(f["major_radius"] - g["major_radius"]) < tol and
            abs(f["minor_radius"] - g["minor_radius"]) < tol and
            np.linalg.norm(np.subtract(f["center"], g["center"])) < tol)


def step_mesh_options(part_size, mesh_size=None):
    size_max = mesh_size if mesh_size else STEP_SIZE_MAX_FRACTION * part_size
    options = dict(COMMON_MESH_OPTIONS)
    options.update({"Mesh.MeshSizeMin": size_max * STEP_SIZE_MIN_RATIO,
                    "Mesh.MeshSizeMax": size_max,
                    "Mesh.MeshSizeFromCurvature": STEP_CURVATURE_ELEMENTS})
    return options


def generate_step(path, out_dir, mesh_size=None):
    """Import a STEP file with OCC, mesh it with linear tets and write
    <stem>.vtu/.json like the Data parts, the faces identified by fits."""
    import hashlib
    stem = os.path.splitext(os.path.basename(path))[0]
    start = time.perf_counter()
    gmsh.model.add(stem)
    gmsh.model.occ.importShapes(path)
    gmsh.model.occ.synchronize()
    single_volume()
    box = gmsh.model.getBoundingBox(-1, -1)
    cad_size = float(np.linalg.norm(np.subtract(box[3:], box[:3])))
    options = step_mesh_options(cad_size, mesh_size)
    for key, value in options.items():
        gmsh.option.setNumber(key, value)
    gmsh.model.mesh.generate(3)
    mesh_time = time.perf_counter() - start

    points, tets, entity_dim, entity_tag, triangles, negative = extract_mesh()
    cad_face, n_boundary = cad_face_labels(tets, triangles)
    n_tris = sum(len(t) for t in triangles.values())
    assert n_tris == n_boundary
    lo, hi = points.min(axis=0), points.max(axis=0)
    part_size = float(np.linalg.norm(hi - lo))
    faces = identify_step_faces(points, triangles, cad_face, tets, part_size)
    curves = describe_curves(part_size)

    # Adjacent faces on one primitive surface (a segmentation sees one region).
    by_tag = {f["tag"]: f for f in faces}
    shared = set()
    for c in curves:
        tags = sorted(set(c["surfaces"]))
        if len(tags) == 2 and not c["degenerate"] and same_surface(
                by_tag[tags[0]], by_tag[tags[1]], STEP_FIT_TOLERANCE * part_size * 10):
            shared.add(tuple(tags))

    by_type, gmsh_types, worst = {}, {}, {}
    for f in faces:
        by_type[f["primitive"]] = by_type.get(f["primitive"], 0) + 1
        gmsh_types[f["gmsh_type"]] = gmsh_types.get(f["gmsh_type"], 0) + 1
        worst[f["primitive"]] = max(worst.get(f["primitive"], 0.0), f["max_node_distance"])
    with open(path, "rb") as f:
        digest = hashlib.md5(f.read()).hexdigest()
    info = {
        "name": stem,
        "description": (f"STEP file {os.path.basename(path)} made by others, imported with "
                        "Gmsh's OpenCASCADE kernel; face primitives from fits of the nodes"),
        "units": "mm",
        "generator": "Data/generate_parts.py --step (Gmsh OpenCASCADE kernel)",
        "gmsh_version": gmsh.option.getString("General.Version"),
        "source": {"file": os.path.basename(path), "md5": digest},
        "dimensions": {},
        "mesh_options": options,
        "mesh_refinement": None,
        "fit": {"tolerance": STEP_FIT_TOLERANCE * part_size,
                "tolerance_note": (f"{STEP_FIT_TOLERANCE:g} x bounding box diagonal: a face "
                                   "is a primitive when all its nodes are this close to the "
                                   "fitted surface"),
                "order_for_unknown_gmsh_types": STEP_FIT_ORDER},
        "counts": {"points": int(len(points)), "tets": int(len(tets)),
                   "boundary_triangles": int(n_tris), "surfaces": len(faces),
                   "curves": len(curves), "surfaces_by_type": by_type,
                   "surfaces_by_gmsh_type": gmsh_types},
        "bounding_box": {"min": lo.tolist(), "max": hi.tolist()},
        "volume": float(signed_volumes(points, tets).sum()),
        "orientation": {"gmsh_negative_tets_flipped": negative,
                        "convention": "(p1-p0).((p2-p0)x(p3-p0)) > 0 for every tet"},
        "max_node_distance_by_type": worst,
        "adjacent_faces_on_one_surface": [list(p) for p in sorted(shared)],
        "faces": faces,
        "curves": curves,
    }
    write_vtu(os.path.join(out_dir, stem + ".vtu"), points, tets, cad_face,
              entity_dim, entity_tag)
    with open(os.path.join(out_dir, stem + ".json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")
    gmsh.model.remove()
    print(f"  {stem}: meshed in {mesh_time:.1f} s, {time.perf_counter() - start:.1f} s in all",
          flush=True)
    return info


# ----------------------------------------------------------------------------
# All-hexahedral parts (--hex): for Hex To Tet (thesis 4.4), an unstructured
# hex mesh of a CAD part. Gmsh meshes it with tets and splits each tet into
# four hexahedra (Mesh.SubdivisionAlgorithm 2: corners at a tet vertex, three
# edge midpoints, three face centres and the tet centre), so node valences
# vary as in any unstructured mesh. Written to <out-dir>/hex/, away from the
# tet parts the tests glob in Data/.
# ----------------------------------------------------------------------------

# VTK_HEXAHEDRON's faces, outward (VTK's face order), and each corner's three
# edge neighbours ordered as for the scaled Jacobian (thesis Eq. 4.2), so a
# positive hexahedron is positive at every corner.
HEX_FACES = [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)]
HEX_CORNER_EDGES = [(1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7),
                    (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3)]


def build_hex_block():
    occ = gmsh.model.occ
    d = {
        "block_size_x": 60.0, "block_size_y": 40.0, "block_size_z": 20.0,
        "block_origin": [0.0, 0.0, 0.0],
        "hole_center_x": 20.0, "hole_center_y": 20.0, "hole_radius": 8.0,
        "boss_center_x": 45.0, "boss_center_y": 20.0, "boss_radius": 7.0, "boss_height": 10.0,
    }
    L, W, H = d["block_size_x"], d["block_size_y"], d["block_size_z"]
    block = occ.addBox(0, 0, 0, L, W, H)
    hole = occ.addCylinder(d["hole_center_x"], d["hole_center_y"], -1.0, 0, 0, H + 2.0,
                           d["hole_radius"])
    occ.cut([(3, block)], [(3, hole)])
    solid = single_volume()
    boss = occ.addCylinder(d["boss_center_x"], d["boss_center_y"], H, 0, 0, d["boss_height"],
                           d["boss_radius"])
    occ.fuse([(3, solid)], [(3, boss)])
    mesh = {"Mesh.MeshSizeMin": 3.0, "Mesh.MeshSizeMax": 8.0, "Mesh.MeshSizeFromCurvature": 12}
    return "block with a through hole and a cylindrical boss, all hexahedra", d, mesh


HEX_PARTS = {
    "hex_block": build_hex_block,
}


def hex_scaled_jacobians(points, hexes):
    """Eq. 4.2 at the eight corners of every hexahedron, (n, 8)."""
    p = points[hexes]
    out = np.empty((len(hexes), 8))
    for i, (a, b, c) in enumerate(HEX_CORNER_EDGES):
        e1, e2, e3 = p[:, a] - p[:, i], p[:, b] - p[:, i], p[:, c] - p[:, i]
        num = np.einsum("ij,ij->i", e1, np.cross(e2, e3))
        den = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(e3, axis=1)
        out[:, i] = num / den
    return out


def hex_cad_faces(hexes, quads):
    """CADFace of a hex mesh: per hexahedron and face (HEX_FACES order), the
    surface tag of that face when it is on the boundary, else -1. Every
    boundary face must be a quad of exactly one surface and every quad a
    boundary face; no face may have more than two hexahedra."""
    n = len(hexes)
    faces = np.sort(hexes[:, HEX_FACES], axis=2).reshape(-1, 4)  # slot = 6 h + f
    quad_rows = [np.sort(q, axis=1) for q in quads.values()]
    _, inverse = np.unique(np.vstack([faces] + quad_rows), axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    face_id, quad_id = inverse[:len(faces)], inverse[len(faces):]
    count = np.bincount(face_id, minlength=int(inverse.max()) + 1)
    assert count.max() <= 2, "a quad face of more than two hexahedra"
    boundary_slots = np.nonzero(count[face_id] == 1)[0]
    slot_of = np.full(len(count), -1, dtype=np.int64)
    slot_of[face_id[boundary_slots]] = boundary_slots
    labels = np.full(len(faces), -1, dtype=np.int32)
    offset = 0
    for stag, rows in zip(quads.keys(), quad_rows):
        slots = slot_of[quad_id[offset:offset + len(rows)]]
        offset += len(rows)
        assert np.all(slots >= 0), f"surface {stag}: a quad that is not a boundary hex face"
        assert np.all(labels[slots] == -1), "boundary face labelled twice"
        labels[slots] = stag
    assert np.all(labels[boundary_slots] >= 0), "a boundary hex face on no CAD surface"
    return labels.reshape(n, 6), len(boundary_slots)


def generate_hex(name, out_dir):
    """Mesh hex part `name` (tets split into hexahedra) and write
    <out_dir>/<name>.vtu/.json."""
    gmsh.model.add(name)
    description, dims, size_options = HEX_PARTS[name]()
    gmsh.model.occ.synchronize()
    options = dict(COMMON_MESH_OPTIONS)
    options.update(size_options)
    options["Mesh.SubdivisionAlgorithm"] = 2  # all hexahedra
    for key, value in options.items():
        gmsh.option.setNumber(key, value)
    gmsh.model.mesh.generate(3)

    vol = single_volume()
    types, _, node_tags = gmsh.model.mesh.getElements(3, vol)
    assert list(types) == [GMSH_HEX], f"volume elements of types {types}"
    hex_tags = np.asarray(node_tags[0], dtype=np.int64).reshape(-1, 8)
    all_tags, all_coords, _ = gmsh.model.mesh.getNodes()
    all_tags = np.asarray(all_tags, dtype=np.int64)
    all_coords = np.asarray(all_coords, dtype=float).reshape(-1, 3)
    used = np.unique(hex_tags)  # nodes the hexahedra use, in Gmsh tag order
    order = np.argsort(all_tags)
    pos = np.searchsorted(all_tags[order], used)
    assert np.all(all_tags[order][pos] == used), "hexahedron uses an unknown node"
    points = all_coords[order[pos]]

    def remap(tags):
        idx = np.searchsorted(used, tags)
        assert np.all(idx < len(used)) and np.all(used[np.minimum(idx, len(used) - 1)] == tags), \
            "element uses a node no hexahedron uses"
        return idx.astype(np.int64)

    hexes = remap(hex_tags)
    # Gmsh's hexahedron has VTK's node order; flip any inside-out one.
    jac = hex_scaled_jacobians(points, hexes)
    inside_out = np.all(jac < 0, axis=1)
    hexes[inside_out] = hexes[inside_out][:, [4, 5, 6, 7, 0, 1, 2, 3]]
    jac = hex_scaled_jacobians(points, hexes)
    assert np.all(jac > 0), f"{int(np.sum(np.any(jac <= 0, axis=1)))} hexahedra not positive"
    entity_dim, entity_tag = classify_nodes(used)

    quads = {}
    for _, stag in gmsh.model.getEntities(2):
        qtypes, _, ntags = gmsh.model.mesh.getElements(2, stag)
        assert list(qtypes) == [GMSH_QUAD], f"surface {stag}: element types {qtypes}"
        quads[stag] = remap(np.asarray(ntags[0], dtype=np.int64).reshape(-1, 4))
    cad_face, n_boundary = hex_cad_faces(hexes, quads)
    assert n_boundary == sum(len(q) for q in quads.values())

    lo, hi = points.min(axis=0), points.max(axis=0)
    worst = jac.min(axis=1)
    info = {
        "name": name,
        "description": description,
        "units": "mm",
        "generator": ("Data/generate_parts.py --hex (Gmsh OpenCASCADE kernel; tets, each "
                      "split into four hexahedra)"),
        "gmsh_version": gmsh.option.getString("General.Version"),
        "dimensions": dims,
        "mesh_options": options,
        "counts": {"points": int(len(points)), "hexahedra": int(len(hexes)),
                   "boundary_quads": int(n_boundary), "surfaces": len(quads)},
        "bounding_box": {"min": lo.tolist(), "max": hi.tolist()},
        "cad_volume": float(gmsh.model.occ.getMass(3, vol)),
        "orientation": {"gmsh_hexahedra_flipped": int(np.sum(inside_out)),
                        "convention": ("VTK_HEXAHEDRON: (p0 p1 p2 p3) turns about the normal "
                                       "towards p4; every corner's scaled Jacobian > 0")},
        "scaled_jacobian": {"min": float(worst.min()), "mean": float(worst.mean()),
                            "note": "minimum over the corners of thesis Eq. 4.2, per hexahedron"},
        "faces": [{"tag": int(stag), "gmsh_type": gmsh.model.getType(2, stag),
                   "quad_count": int(len(q))} for stag, q in quads.items()],
    }
    write_vtu(os.path.join(out_dir, name + ".vtu"), points, hexes, cad_face, entity_dim,
              entity_tag, VTK_HEXAHEDRON_TYPE)
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")
    gmsh.model.remove()
    return info


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out-dir", default=None,
                        help="folder for <name>.vtu and <name>.json (default: this script's "
                             "folder; required with --fine and --step)")
    parser.add_argument("--only", choices=sorted(PARTS), action="append",
                        help="generate only this part (repeatable)")
    parser.add_argument("--fine", choices=sorted(PARTS), metavar="NAME",
                        help="write only a finer version of this part, <NAME>_fine.vtu/.json, "
                             "with about --target-boundary-triangles boundary triangles "
                             "(for benchmarks; not committed)")
    parser.add_argument("--target-boundary-triangles", type=int, default=200000,
                        help="boundary triangles of the --fine part (default 200000)")
    parser.add_argument("--step", action="append", metavar="PATH",
                        help="mesh this STEP file instead (repeatable): <stem>.vtu/.json in "
                             "--out-dir, each face's primitive found by fitting its nodes")
    parser.add_argument("--hex", action="store_true",
                        help="write only the all-hexahedral parts, into <out-dir>/hex/ "
                             f"({', '.join(sorted(HEX_PARTS))}; a run without options writes "
                             "them too)")
    parser.add_argument("--variants", action="store_true",
                        help="write only the changed-CAD variants, into <out-dir>/variants/ "
                             "(<part>__<variant>.json/.vtp; a run without options writes them "
                             "too; with --only, of those parts)")
    parser.add_argument("--mesh-size", type=float, default=None,
                        help="with --step: maximum element size in mm (default: 1/50 of the "
                             "bounding box diagonal; minimum 1/20 of it, plus curvature "
                             f"sizing, {STEP_CURVATURE_ELEMENTS} elements per 2 pi)")
    args = parser.parse_args()
    if args.hex and (args.fine or args.only or args.step):
        parser.error("--hex does not go with --fine, --only or --step")
    if args.variants and (args.fine or args.step or args.hex):
        parser.error("--variants does not go with --fine, --step or --hex")
    if args.step and (args.fine or args.only):
        parser.error("--step does not go with --fine or --only")
    if args.step and not args.out_dir:
        parser.error("--step needs --out-dir (meshes of STEP files are not kept in Data/)")
    if args.mesh_size is not None and not args.step:
        parser.error("--mesh-size goes with --step")
    if args.fine and args.only:
        parser.error("--fine and --only do not go together")
    if args.fine and not args.out_dir:
        parser.error("--fine needs --out-dir (fine parts are not kept in Data/)")
    if not args.out_dir:
        args.out_dir = os.path.dirname(os.path.abspath(__file__))
    os.makedirs(args.out_dir, exist_ok=True)

    gmsh.initialize(["generate_parts"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    rows, hex_rows, variant_rows = [], [], []
    try:
        if args.fine:
            start = time.perf_counter()
            scale, history = fine_scale(args.fine, args.target_boundary_triangles)
            print(f"fine {args.fine}: size scale {scale:.4f} from surface-only trials "
                  f"{history} ({time.perf_counter() - start:.1f} s)", flush=True)
            fine = {"part": args.fine, "target_boundary_triangles": args.target_boundary_triangles,
                    "size_scale": scale, "surface_only_trials": history}
            info = generate(args.fine, args.out_dir, scale, args.fine + "_fine", fine)
            print(f"fine {args.fine}: {time.perf_counter() - start:.1f} s in all")
            rows.append(info)
        for path in args.step or []:
            rows.append(generate_step(path, args.out_dir, args.mesh_size))
        for name in PARTS:
            if (args.fine or args.step or args.hex or args.variants
                    or (args.only and name not in args.only)):
                continue
            info = generate(name, args.out_dir)
            rows.append(info)
        if not (args.fine or args.step or args.only or args.variants):
            hex_dir = os.path.join(args.out_dir, "hex")
            os.makedirs(hex_dir, exist_ok=True)
            for name in HEX_PARTS:
                hex_rows.append(generate_hex(name, hex_dir))
        if args.variants or not (args.fine or args.step or args.only or args.hex):
            variant_rows = generate_variants(os.path.join(args.out_dir, "variants"), args.only)
    finally:
        gmsh.finalize()

    if rows:
        width = max([18] + [len(info["name"]) for info in rows])
        print(f"{'part':<{width}} {'points':>7} {'tets':>7} {'tris':>6}  {'faces by type':<44} "
              f"{'max dist':>9}  {'vtu KB':>7}")
        for info in rows:
            c = info["counts"]
            types = ", ".join(f"{n} {t}" for t, n in sorted(c["surfaces_by_type"].items()))
            dist = max(info["max_node_distance_by_type"].values())
            size = os.path.getsize(os.path.join(args.out_dir, info["name"] + ".vtu")) / 1024
            print(f"{info['name']:<{width}} {c['points']:>7} {c['tets']:>7} {c['boundary_triangles']:>6}  "
                  f"{types:<44} {dist:>9.2e}  {size:>7.0f}")
    for info in variant_rows:
        size = os.path.getsize(os.path.join(args.out_dir, "variants", info["name"] + ".vtp")) / 1024
        print(f"variants/{info['name']}: {info['sample']['triangles']} triangles, CAD volume "
              f"{info['cad_volume']:.3f}, {size:.0f} KB")
    for info in hex_rows:
        c = info["counts"]
        size = os.path.getsize(os.path.join(args.out_dir, "hex", info["name"] + ".vtu")) / 1024
        print(f"hex/{info['name']}: {c['points']} points, {c['hexahedra']} hexahedra, "
              f"{c['boundary_quads']} boundary quads, scaled Jacobian min "
              f"{info['scaled_jacobian']['min']:.3f}, {size:.0f} KB")
    print(f"written to {args.out_dir}" + ("" if HAVE_VTK else " (ascii .vtu: vtkmodules not found)"))


if __name__ == "__main__":
    main()
