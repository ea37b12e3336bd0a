#!/usr/bin/env python3
"""Peer of the FEMorph Improve benchmark: Gmsh's own tetrahedral optimizers.

Reads a tetrahedral mesh (MSH 2.2 with its boundary triangles, written by
bench_improve), runs gmsh.model.mesh.optimize(METHOD) on it and writes the
result (MSH 2.2). Prints "seconds <wall time of optimize>" and a line
"nodes moved N of M (boundary K, max boundary move D); tets T0 -> T1" that
tells whether the volume was worked on and the boundary kept (node tags are
kept, so positions compare tag by tag). Debian 12's Gmsh
4.8 (python3-gmsh) has no Netgen optimizer; METHOD "" is the default
tetrahedral optimizer, "Relocate3D" the node relocation.

  /usr/bin/python3 gmsh_optimize_peer.py IN.msh OUT.msh [METHOD]
"""
import sys
import time

import gmsh


def main():
    path_in, path_out = sys.argv[1], sys.argv[2]
    method = sys.argv[3] if len(sys.argv) > 3 else ""
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 2)
    gmsh.open(path_in)
    before = node_positions()
    boundary = boundary_nodes()
    tets_before = tet_count()
    start = time.perf_counter()
    gmsh.model.mesh.optimize(method, force=True)
    seconds = time.perf_counter() - start
    after = node_positions()
    moved = [t for t, p in after.items() if t in before and p != before[t]]
    boundary_moves = [distance(before[t], after[t]) for t in moved if t in boundary]
    tets_after = tet_count()
    gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
    gmsh.option.setNumber("Mesh.SaveAll", 1)
    gmsh.write(path_out)
    gmsh.finalize()
    print("seconds %.6f" % seconds)
    print("nodes moved %d of %d (boundary %d, max boundary move %.3g); tets %d -> %d"
          % (len(moved), len(before), len(boundary_moves), max(boundary_moves, default=0.0),
             tets_before, tets_after))


def node_positions():
    tags, coords, _ = gmsh.model.mesh.getNodes()
    return {int(t): tuple(coords[3 * i:3 * i + 3]) for i, t in enumerate(tags)}


def boundary_nodes():
    """Nodes of the boundary triangles (the file's 2D elements)."""
    _, _, nodes = gmsh.model.mesh.getElements(2)
    return set(int(t) for block in nodes for t in block)


def tet_count():
    types, tags, _ = gmsh.model.mesh.getElements(3)
    return sum(len(t) for ty, t in zip(types, tags) if ty == 4)


def distance(p, q):
    return sum((a - b) ** 2 for a, b in zip(p, q)) ** 0.5


if __name__ == "__main__":
    main()
