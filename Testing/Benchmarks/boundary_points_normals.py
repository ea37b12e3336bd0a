#!/usr/bin/python3
"""Write the boundary vertices of a Data/ part, their normals and CAD truth as
text, for bench_cgal_peer (the benchmarks do not link VTK).

    /usr/bin/python3 Testing/Benchmarks/boundary_points_normals.py Data/boss_block.vtu out.txt

Normals: area-weighted averages of the outward normals of the boundary
triangles around the vertex (CADFace >= 0 marks them), normalized. Truth: the
CAD surface tag of vertices classified on a surface (CADEntityDim 2), -1 for
vertices on CAD curves and corners, and the face types from <part>.json.

Format (ascii):
    # FEMorph boundary points and normals v1 <part name>
    faces K
    <tag> <primitive> <size...>   K lines: plane nx ny nz offset (n.x = offset, n outwards),
                                  cylinder radius, cone half_angle_deg, sphere radius,
                                  torus major_radius minor_radius, unknown (nothing)
    points N
    x y z nx ny nz tag            N lines, %.17g
"""

import json
import os
import sys

import numpy as np

sys.path.append("/usr/lib/python3/dist-packages")
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

OPPOSITE_FACE = [(1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    vtu, out = sys.argv[1], sys.argv[2]
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu)
    reader.Update()
    grid = reader.GetOutput()
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)
    cad_face = vtk_to_numpy(grid.GetCellData().GetArray("CADFace")).reshape(-1, 4)
    entity_dim = vtk_to_numpy(grid.GetPointData().GetArray("CADEntityDim"))
    entity_tag = vtk_to_numpy(grid.GetPointData().GetArray("CADEntityTag"))

    sums = np.zeros_like(points)
    on_boundary = np.zeros(len(points), dtype=bool)
    for i, (a, b, c) in enumerate(OPPOSITE_FACE):
        rows = np.nonzero(cad_face[:, i] >= 0)[0]
        tri = conn[rows][:, [a, b, c]]
        opposite = points[conn[rows, i]]
        p0, p1, p2 = (points[tri[:, k]] for k in range(3))
        n = np.cross(p1 - p0, p2 - p0)  # twice the area times the unit normal
        inward = np.einsum("ij,ij->i", n, opposite - p0) > 0
        n[inward] *= -1.0
        for k in range(3):
            np.add.at(sums, tri[:, k], n)
        on_boundary[tri.ravel()] = True
    ids = np.nonzero(on_boundary)[0]
    normals = sums[ids] / np.linalg.norm(sums[ids], axis=1)[:, None]
    tags = np.where(entity_dim[ids] == 2, entity_tag[ids], -1)

    info_path = os.path.splitext(vtu)[0] + ".json"
    with open(info_path) as f:
        info = json.load(f)
    with open(out, "w") as f:
        f.write(f"# FEMorph boundary points and normals v1 {info['name']}\n")
        f.write(f"faces {len(info['faces'])}\n")
        for face in info["faces"]:
            f.write(f"{face['tag']} {face['primitive']}")
            kind = face["primitive"]
            if kind == "plane":
                n = np.asarray(face["normal"])
                values = list(n) + [float(n @ np.asarray(face["point"]))]
            elif kind in ("cylinder", "sphere"):
                values = [face["radius"]]
            elif kind == "cone":
                values = [face["half_angle_deg"]]
            elif kind == "torus":
                values = [face["major_radius"], face["minor_radius"]]
            else:
                values = []
            f.write("".join(" %.17g" % v for v in values) + "\n")
        f.write(f"points {len(ids)}\n")
        data = np.hstack([points[ids], normals])
        for row, tag in zip(data, tags):
            f.write(" ".join("%.17g" % v for v in row) + f" {int(tag)}\n")
    print(f"{out}: {len(ids)} boundary vertices, {len(info['faces'])} CAD faces")


if __name__ == "__main__":
    main()
