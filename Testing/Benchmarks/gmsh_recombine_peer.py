#!/usr/bin/python3
"""Gmsh's 3D recombination as the peer of FEMorph Tet To Hex (bench_tet_to_hex).

Modes (one per run, so that a crash of Gmsh does not end the benchmark):

  given IN            Gmsh's recombination (Mesh.Recombine3DAll, levels 0-2)
                      on the tet mesh in IN (the binary layout below), loaded
                      as a discrete volume with its boundary triangles.
  own SIZE            Gmsh meshes the unit cube itself with Mesh.Algorithm3D 9
                      (R-tree, the only 3D algorithm after which Gmsh 4.8
                      recombines) and Recombine3DAll at level 2.
  delaunay SIZE OUT   the unit cube's Delaunay tet mesh (Gmsh's default), to
                      OUT: an unstructured input for FEMorph.

Binary layout: int64 #points, int64 #tets, float64 xyz per point, int32 four
0-based node ids per tet. Prints one line "gmsh <mode>: key=value ...".
Needs Debian's python3-gmsh (run with /usr/bin/python3).
"""
import sys
import time

import gmsh
import numpy as np

# 3D element types of Gmsh: 4 tetrahedron, 5 hexahedron, 6 prism, 7 pyramid.
NAMES = {4: "tets", 5: "hexes", 6: "prisms", 7: "pyramids"}


def read_mesh(path):
    with open(path, "rb") as f:
        n_points, n_tets = np.fromfile(f, dtype=np.int64, count=2)
        points = np.fromfile(f, dtype=np.float64, count=3 * n_points).reshape(-1, 3)
        tets = np.fromfile(f, dtype=np.int32, count=4 * n_tets).reshape(-1, 4)
    return points, tets


def write_mesh(path, points, tets):
    with open(path, "wb") as f:
        np.array([len(points), len(tets)], dtype=np.int64).tofile(f)
        np.asarray(points, dtype=np.float64).tofile(f)
        np.asarray(tets, dtype=np.int32).tofile(f)


def volume_of(points, cells):
    """Volume of Gmsh cells by a fan of tets from the centroid over the
    faces (faces split at their centroid: exact for planar faces)."""
    faces = {4: [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)],
             5: [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6),
                 (3, 0, 4, 7)],
             6: [(0, 2, 1), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)],
             7: [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]}
    total = 0.0
    for kind, nodes in cells.items():
        if len(nodes) == 0:
            continue
        x = points[nodes]
        c = x.mean(axis=1)
        for f in faces[kind]:
            fc = x[:, list(f)].mean(axis=1)
            for a, b in zip(f, f[1:] + f[:1]):
                total += abs(np.einsum("ij,ij->i", x[:, a] - c,
                                       np.cross(x[:, b] - c, fc - c))).sum() / 6.0
    return total


def report(mode, seconds, points, cells):
    counts = {k: len(v) for k, v in cells.items()}
    hex_volume = volume_of(points, {5: cells.get(5, [])})
    all_volume = volume_of(points, cells)
    print("gmsh %s: status=ok seconds=%.3f %s hex_volume_ratio=%.4f" % (
        mode, seconds, " ".join("%s=%d" % (NAMES[k], counts.get(k, 0)) for k in NAMES),
        hex_volume / all_volume if all_volume > 0 else 0.0), flush=True)


def mesh_cells():
    nodes, coords, _ = gmsh.model.mesh.getNodes()
    order = np.argsort(nodes)
    points = coords.reshape(-1, 3)[order]
    index = {int(t): i for i, t in enumerate(nodes[order])}
    cells = {}
    for kind in gmsh.model.mesh.getElementTypes(3):
        n = gmsh.model.mesh.getElementProperties(kind)[3]
        _, conn = gmsh.model.mesh.getElementsByType(kind)
        cells[int(kind)] = np.array([index[int(t)] for t in conn], dtype=np.int64).reshape(-1, n)
    return points, cells


def main():
    mode = sys.argv[1]
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    if mode == "given":
        points, tets = read_mesh(sys.argv[2])
        count = {}
        for t in tets:
            for i in range(4):
                key = tuple(sorted(np.delete(t, i)))
                count[key] = count.get(key, 0) + 1
        boundary = np.array([k for k, c in count.items() if c == 1])
        on_boundary = np.zeros(len(points), dtype=bool)
        on_boundary[boundary.ravel()] = True
        gmsh.model.add("given")
        gmsh.model.addDiscreteEntity(2, 1)
        gmsh.model.addDiscreteEntity(3, 1, [1])
        ids = np.arange(1, len(points) + 1)
        gmsh.model.mesh.addNodes(2, 1, ids[on_boundary].tolist(), points[on_boundary].ravel().tolist())
        gmsh.model.mesh.addNodes(3, 1, ids[~on_boundary].tolist(), points[~on_boundary].ravel().tolist())
        gmsh.model.mesh.addElementsByType(1, 2, [], (boundary + 1).ravel().tolist())
        gmsh.model.mesh.addElementsByType(1, 4, [], (tets + 1).ravel().tolist())
        gmsh.option.setNumber("Mesh.Recombine3DAll", 1)
        gmsh.option.setNumber("Mesh.Recombine3DLevel", 2)
        start = time.perf_counter()
        try:
            gmsh.model.mesh.generate(3)
        except Exception as e:  # Gmsh reports through exceptions
            print("gmsh given: status=error message=%r" % str(e))
            return
        points, cells = mesh_cells()
        report(mode, time.perf_counter() - start, points, cells)
    elif mode in ("own", "delaunay"):
        size = float(sys.argv[2])
        gmsh.model.add(mode)
        gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        if mode == "own":
            gmsh.option.setNumber("Mesh.Algorithm3D", 9)
            gmsh.option.setNumber("Mesh.Recombine3DAll", 1)
            gmsh.option.setNumber("Mesh.Recombine3DLevel", 2)
        start = time.perf_counter()
        gmsh.model.mesh.generate(3)
        seconds = time.perf_counter() - start
        points, cells = mesh_cells()
        if mode == "own":
            report(mode, seconds, points, cells)
        else:
            write_mesh(sys.argv[3], points, cells[4])
            print("gmsh delaunay: status=ok seconds=%.3f tets=%d" % (seconds, len(cells[4])))
    else:
        sys.exit("unknown mode %s" % mode)
    gmsh.finalize()


if __name__ == "__main__":
    main()
