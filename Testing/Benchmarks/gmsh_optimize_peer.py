#!/usr/bin/env python3
"""Peer of the FEMorph Improve benchmark: Gmsh's own tetrahedral optimizers.

Reads a tetrahedral mesh (MSH 2.2 with its boundary triangles, written by
bench_improve), runs gmsh.model.mesh.optimize(METHOD) on it and writes the
result (MSH 2.2). Prints "seconds <wall time of optimize>". Debian 12's Gmsh
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
    start = time.perf_counter()
    gmsh.model.mesh.optimize(method, force=True)
    seconds = time.perf_counter() - start
    gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
    gmsh.option.setNumber("Mesh.SaveAll", 1)
    gmsh.write(path_out)
    gmsh.finalize()
    print("seconds %.6f" % seconds)


if __name__ == "__main__":
    main()
