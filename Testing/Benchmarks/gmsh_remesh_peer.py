#!/usr/bin/python3
"""Peer of bench_deform: Gmsh re-meshing the changed CAD part, the way a user
without FEMorph Deform gets the mesh of a changed dimension.

    /usr/bin/python3 gmsh_remesh_peer.py DATA_DIR PART SCALE THREADS [NAME=VALUE ...] [--out PATH.msh]

Builds PART with Data/generate_parts.py's builder, its dimensions NAME=VALUE
changed (e.g. boss_height=20), with the mesh sizes of a --fine part of size
scale SCALE (the `fine.size_scale` of the part's JSON) and the same volume
options generate_parts.py uses for fine parts (fine surfaces, coarse inside,
HXT), and meshes it with THREADS threads. Only Gmsh's meshing is timed (the
surface and the volume mesh; not the CAD construction, not the files). Prints
`surface S`, `volume S`, `tets N`, `nodes N` and last `seconds S`.
"""

import os
import sys
import time


def main():
    args = [a for a in sys.argv[1:]]
    out = None
    if "--out" in args:
        i = args.index("--out")
        out = args[i + 1]
        del args[i:i + 2]
    if len(args) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    data_dir, part, scale, threads = args[0], args[1], float(args[2]), int(args[3])
    overrides = {}
    for item in args[4:]:
        key, value = item.split("=", 1)
        overrides[key] = float(value)
    sys.path.insert(0, data_dir)
    import generate_parts as gp  # noqa: E402  (Data/ is not a package)
    import gmsh

    gmsh.initialize(["gmsh_remesh_peer"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", threads)
        _, _, _, options, _ = gp.setup_part(part, scale, overrides or None)
        start = time.perf_counter()
        gmsh.model.mesh.generate(2)
        surface = time.perf_counter() - start
        # generate_parts.generate's options for --fine parts.
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeMax", options["Mesh.MeshSizeMax"] / scale)
        gmsh.option.setNumber("Mesh.Algorithm3D", 10)
        start = time.perf_counter()
        gmsh.model.mesh.generate(3)
        volume = time.perf_counter() - start
        tets = 0
        for _, tag in gmsh.model.getEntities(3):
            types, elems, _ = gmsh.model.mesh.getElements(3, tag)
            tets += sum(len(e) for t, e in zip(types, elems) if t == 4)
        nodes = len(gmsh.model.mesh.getNodes()[0])
        if out:
            gmsh.write(out)
    finally:
        gmsh.finalize()
    print(f"surface {surface:.3f}")
    print(f"volume {volume:.3f}")
    print(f"tets {tets}")
    print(f"nodes {nodes}")
    print(f"seconds {surface + volume:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
