#!/usr/bin/python3
"""Build the parts of the FEA acceptance tests (cantilever, plate with a hole)
and mesh them with linear tetrahedra, in the layout of Data/generate_parts.py.

    /usr/bin/python3 Data/generate_fea_parts.py [--out-dir Data/fea] [--only NAME]
    /usr/bin/python3 Data/generate_fea_parts.py --variant cantilever_width20 --out-dir build/fea
    /usr/bin/python3 Data/generate_fea_parts.py --variant plate_hole_r10 --out-dir build/fea

Parts kept in Data/fea/ (a folder of their own, like Data/hex/: the tests
that take every Data/*.vtu as a segmentation part do not take these):
  cantilever   beam 100 x 10 x 10 mm (x = length 0..100, y = width 0..10,
               z = height 0..10), uniform mesh size CANTILEVER_SIZE.
  plate_hole   plate 200 x 100 x 2 mm (x 0..200, y 0..100, z 0..2) with a
               through hole of radius 5 at (100, 50), refined near the hole
               by a Distance/Threshold field on the cylinder.

Variants, the reference parts of the dimension changes (generated at test
time, not committed): `cantilever_width20` (y 0..20, the face y = 0 kept),
`plate_hole_r10` (hole radius 10, same centre). Each variant is meshed with
the same size rules as its base part (sizes do not follow the dimension).

Every part is written by generate_parts.generate (same arrays, checks and
JSON: CADFace per tet face, CADEntityDim/CADEntityTag per node, dimensions and
the exact faces), so the files are the same kind as the other Data parts.
Testing/FEA/calculix.py runs the CalculiX analyses on them; the mesh sizes
are chosen so that the 10-node tet analyses are converged
(Testing/FEA/README.md gives the convergence figures).
"""

import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import generate_parts as gp  # noqa: E402  (helpers, writers, checks)
import gmsh  # noqa: E402

# Mesh sizes (mm). The cantilever: 5 tet layers through the height.
CANTILEVER_SIZE = 2.0
# The plate: PLATE_SIZE_NEAR on the hole, growing to PLATE_SIZE_FAR between
# PLATE_DIST_NEAR and PLATE_DIST_FAR from the hole surface.
PLATE_SIZE_NEAR = 0.35
PLATE_SIZE_FAR = 6.0
PLATE_DIST_NEAR = 1.0
PLATE_DIST_FAR = 30.0


def build_cantilever(width=10.0):
    occ = gmsh.model.occ
    d = {"length": 100.0, "width": float(width), "height": 10.0,
         "axes": "x = length (0..length), y = width (0..width), z = height (0..height)",
         "clamped_face": "x = 0", "loaded_face": "x = length"}
    L, B, H = d["length"], d["width"], d["height"]
    occ.addBox(0, 0, 0, L, B, H)
    surfaces = [
        gp.plane("clamped end x=0", [0, 0, 0], [-1, 0, 0]),
        gp.plane("loaded end x=L", [L, 0, 0], [1, 0, 0]),
        gp.plane("side y=0", [0, 0, 0], [0, -1, 0]),
        gp.plane("side y=width", [0, B, 0], [0, 1, 0]),
        gp.plane("bottom z=0", [0, 0, 0], [0, 0, -1]),
        gp.plane("top z=height", [0, 0, H], [0, 0, 1]),
    ]
    mesh = {"Mesh.MeshSizeMin": CANTILEVER_SIZE, "Mesh.MeshSizeMax": CANTILEVER_SIZE}
    return (f"cantilever beam {L:g} x {B:g} x {H:g} mm (FEA acceptance test)", d, surfaces, mesh)


def build_plate_hole(radius=5.0, thickness=2.0):
    occ = gmsh.model.occ
    d = {"length": 200.0, "width": 100.0, "thickness": float(thickness),
         "hole_center_x": 100.0, "hole_center_y": 50.0, "hole_radius": float(radius),
         "axes": "x = length (loaded direction), y = width, z = thickness",
         "held_face": "x = 0", "loaded_face": "x = length"}
    L, W, T = d["length"], d["width"], d["thickness"]
    cx, cy, r = d["hole_center_x"], d["hole_center_y"], d["hole_radius"]
    plate = occ.addBox(0, 0, 0, L, W, T)
    hole = occ.addCylinder(cx, cy, -1.0, 0, 0, T + 2.0, r)
    occ.cut([(3, plate)], [(3, hole)])
    surfaces = [
        gp.plane("held end x=0", [0, 0, 0], [-1, 0, 0]),
        gp.plane("loaded end x=L", [L, 0, 0], [1, 0, 0]),
        gp.plane("side y=0", [0, 0, 0], [0, -1, 0]),
        gp.plane("side y=W", [0, W, 0], [0, 1, 0]),
        gp.plane("bottom z=0", [0, 0, 0], [0, 0, -1]),
        gp.plane("top z=T", [0, 0, T], [0, 0, 1]),
        gp.cylinder("hole", [cx, cy, 0], [0, 0, 1], r, "concave"),
    ]
    mesh = {"Mesh.MeshSizeMin": PLATE_SIZE_NEAR, "Mesh.MeshSizeMax": PLATE_SIZE_FAR,
            "refine": {"gmsh_types": ["Cylinder"], "size_near": PLATE_SIZE_NEAR,
                       "size_far": PLATE_SIZE_FAR, "dist_near": PLATE_DIST_NEAR,
                       "dist_far": PLATE_DIST_FAR}}
    return (f"plate {L:g} x {W:g} x {T:g} mm with a through hole of radius {r:g} at "
            f"({cx:g}, {cy:g}) (FEA acceptance test)", d, surfaces, mesh)


# Kept in Data/fea/.
FEA_PARTS = {
    "cantilever": build_cantilever,
    "plate_hole": build_plate_hole,
}
# The changed-dimension references, made at test time.
FEA_VARIANTS = {
    "cantilever_width20": lambda: build_cantilever(width=20.0),
    "plate_hole_r10": lambda: build_plate_hole(radius=10.0),
}


def generate_fea(name, out_dir, quiet=True):
    """Mesh FEA part or variant `name` into <out_dir>/<name>.vtu/.json; returns
    the JSON dictionary, in a Gmsh session of its own."""
    builders = dict(FEA_PARTS)
    builders.update(FEA_VARIANTS)
    gp.PARTS[name] = builders[name]  # generate_parts.generate looks parts up here
    os.makedirs(out_dir, exist_ok=True)
    gmsh.initialize(["generate_fea_parts"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0 if quiet else 1)
    gmsh.option.setNumber("General.NumThreads", 1)
    try:
        info = gp.generate(name, out_dir)
    finally:
        gmsh.finalize()
    # generate_parts.generate names itself; say which script made the part.
    info["generator"] = ("Data/generate_fea_parts.py (parts of the FEA tests, meshed and checked "
                         "by Data/generate_parts.py; Gmsh OpenCASCADE kernel)")
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")
    return info


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out-dir", default=os.path.join(HERE, "fea"),
                        help="output folder (default: Data/fea/)")
    parser.add_argument("--only", choices=sorted(FEA_PARTS), action="append",
                        help="generate only this part (repeatable)")
    parser.add_argument("--variant", choices=sorted(FEA_VARIANTS), action="append",
                        help="generate this changed-dimension reference instead (repeatable; "
                             "not kept in Data/fea/)")
    args = parser.parse_args()
    names = args.variant or args.only or list(FEA_PARTS)
    for name in names:
        info = generate_fea(name, args.out_dir)
        c = info["counts"]
        size = os.path.getsize(os.path.join(args.out_dir, name + ".vtu")) / 1024
        print(f"{name}: {c['points']} points, {c['tets']} tets, {c['boundary_triangles']} "
              f"boundary triangles, {size:.0f} KB")


if __name__ == "__main__":
    main()
