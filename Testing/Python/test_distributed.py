"""FEMorph's filters under MPI against their serial run (issue 29).

Run by pvbatch (one process): runs every case serially, then runs this script
again under `mpiexec -np 2 pvbatch ... --mpi`, and as the pvpython client of
`mpiexec -np 2 pvserver` for PVSERVER_CASES, and compares. Under MPI each
case's input is distributed by RedistributeDataSet (pieces without ghost
cells), by D3 (ghost cells), or left on process 0 (an empty piece on the
other). Compared, exactly: the cells (ghost cells left out), the regions
(distinct RegionId values), the minimum stretch of the tetrahedra, the
boundary faces (faces of one cell only, keyed by their points' coordinates:
a crack along a cut between pieces adds faces), and Mesh Quality's global
summary. No face may belong to more than two cells, and no process may
print an error.

The inputs carry vtkGlobalPointIds and vtkGlobalCellIds (numbered as in the
file) so the gathered mesh is the serial one, point for point.

Exit 77 (skipped) when mpiexec is missing.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
from paraview import servermanager
from paraview.simple import (D3, CSVReader, LoadPlugin, RedistributeDataSet, XMLUnstructuredGridReader,
                             XMLUnstructuredGridWriter)
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

# Faces of the linear 3D cells by VTK cell type (local point indices).
FACES = {
    10: [(0, 1, 3), (1, 2, 3), (2, 0, 3), (0, 2, 1)],
    12: [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)],
    13: [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)],
    14: [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
}


def cases(data):
    """(name, input file, filter builder, distributions) of each case."""
    boss = os.path.join(data, "boss_block.vtu")
    beam = os.path.join(data, "beam.vtu")
    hexes = os.path.join(data, "hex", "hex_block.vtu")
    adapt = os.path.join(data, "adapt", "block_in_box_small.vtu")
    both = ["redistribute", "d3"]
    return [
        ("MeshQuality", boss, lambda s: FEMorphMeshQuality(Input=s), both + ["rank0"]),  # noqa: F821
        ("Segment", boss, lambda s: FEMorphSegment(Input=s), both),  # noqa: F821
        ("Improve", beam, lambda s: FEMorphImprove(Input=s), both),  # noqa: F821
        # Two gathered grid inputs: the Reference is the same distributed mesh.
        ("ImproveReference", beam, lambda s: FEMorphImprove(Input=s, Reference=s), both),  # noqa: F821
        ("Deform", beam, lambda s: FEMorphDeform(  # noqa: F821
            Input=FEMorphSegment(Input=s), DeformationType=0, UseControlPoint=1,  # noqa: F821
            ControlPoint=[50, 10, 5], TargetValue=20), both),
        ("Adapt", adapt, lambda s: FEMorphAdapt(  # noqa: F821
            Input=s, MaterialArray="MaterialId", MovingObject=1,
            TranslationPerStep=[0, 0, 0.25], NumberOfSteps=2), both),
        ("AdaptMotion", adapt, lambda s: FEMorphAdapt(  # noqa: F821
            Input=s, Motion=CSVReader(FileName=[motion_csv(data)]), NumberOfSteps=2), both),
        ("HexToTet", hexes, lambda s: FEMorphHexToTet(Input=s), both + ["rank0"]),  # noqa: F821
        ("TetToHex", boss, lambda s: FEMorphTetToHex(Input=s), both),  # noqa: F821
    ]


def motion_csv(data):
    """A Motion table for Adapt (a CSV of m00..m33, one row per step): the
    block of block_in_box_small moved up by 0.25 per step, in the work folder."""
    path = os.path.join(WORK[0], "motion.csv")
    if not os.path.exists(path):
        with open(path, "w") as f:
            f.write(",".join("m%d%d" % (r, c) for r in range(4) for c in range(4)) + "\n")
            for n in (1, 2):
                m = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.25 * n, 0, 0, 0, 1]
                f.write(",".join(repr(float(v)) for v in m) + "\n")
    return path


WORK = [None]


def with_global_ids(src, dst):
    """A copy of `src` whose points and cells carry global ids in file order."""
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(src)
    r.Update()
    g = r.GetOutput()
    for dsa, n, name in ((g.GetPointData(), g.GetNumberOfPoints(), "vtkGlobalPointIds"),
                         (g.GetCellData(), g.GetNumberOfCells(), "vtkGlobalCellIds")):
        ids = numpy_to_vtk(np.arange(n, dtype=np.int64), deep=1)
        ids.SetName(name)
        dsa.SetGlobalIds(ids)
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(dst)
    w.SetInputData(g)
    w.Write()


def metrics(grid, time_value):
    """The compared properties of a fetched (appended) output."""
    n = grid.GetNumberOfCells()
    types = vtk_to_numpy(grid.GetCellTypesArray()) if n else np.zeros(0, dtype=np.uint8)
    keep = np.ones(n, dtype=bool)
    ghost = grid.GetCellData().GetArray("vtkGhostType")
    if ghost is not None:
        keep = (vtk_to_numpy(ghost) & vtkDataSetAttributes.DUPLICATECELL) == 0
    out = {"time": time_value, "cells": int(keep.sum())}
    region = grid.GetCellData().GetArray("RegionId")
    if region is not None:
        out["regions"] = int(len(np.unique(vtk_to_numpy(region)[keep])))
    fd = grid.GetFieldData()
    for name in ("TetraCount", "StretchMin", "InvalidCount", "ScaledJacobianMean"):
        a = fd.GetArray(name)
        if a is not None:
            out["field " + name] = a.GetComponent(0, 0)
    if n == 0:
        return out
    pts = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    # Points keyed by coordinates: the pieces' copies of a point are one.
    _, canon = np.unique(pts, axis=0, return_inverse=True)
    canon = canon.reshape(-1)
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    offs = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    faces = []
    stretch = []
    for t, local in FACES.items():
        sel = np.nonzero((types == t) & keep)[0]
        if len(sel) == 0:
            continue
        k = offs[sel + 1] - offs[sel]
        assert np.all(k == {10: 4, 12: 8, 13: 6, 14: 5}[t])
        cells = conn[offs[sel][:, None] + np.arange(k[0])[None, :]]
        for f in local:
            ids = np.sort(canon[cells[:, list(f)]], axis=1)
            if ids.shape[1] == 3:
                ids = np.hstack([np.full((len(ids), 1), -1), ids])
            faces.append(ids)
        if t == 10:
            p = pts[cells]
            a, b, c, d = p[:, 0], p[:, 1], p[:, 2], p[:, 3]
            vol = np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6
            edges = [b - a, c - a, d - a, c - b, d - b, d - c]
            lmax = np.max([np.linalg.norm(e, axis=1) for e in edges], axis=0)
            area = sum(np.linalg.norm(np.cross(q - o, r - o), axis=1) / 2
                       for o, q, r in ((a, b, c), (a, b, d), (a, c, d), (b, c, d)))
            stretch.append(6 * np.sqrt(6) * vol / (lmax * area))
    allf = np.vstack(faces)
    _, counts = np.unique(allf, axis=0, return_counts=True)
    out["boundary faces"] = int((counts == 1).sum())
    out["faces in more than two cells"] = int((counts > 2).sum())
    if stretch:
        out["min stretch"] = round(float(np.min(np.concatenate(stretch))), 12)
    return out


def fetch_all(proxy):
    """Every process's output in one grid (pvbatch's Fetch without a process
    brings process 0's only), and the number of cells outside process 0."""
    from vtkmodules.vtkFiltersCore import vtkAppendFilter
    n = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    append = vtkAppendFilter()
    others = 0
    for k in range(n):
        piece = servermanager.Fetch(proxy, k) if n > 1 else servermanager.Fetch(proxy)
        others += piece.GetNumberOfCells() if k > 0 else 0
        append.AddInputData(piece)
    append.Update()
    grid = append.GetOutput()
    first = servermanager.Fetch(proxy, 0) if n > 1 else None
    if first is not None:
        grid.GetFieldData().ShallowCopy(first.GetFieldData())
    elif append.GetNumberOfInputConnections(0):
        grid.GetFieldData().ShallowCopy(append.GetInput(0).GetFieldData())
    return grid, others


def run_case(builder, src, distribution):
    reader = XMLUnstructuredGridReader(FileName=[src])
    if distribution == "redistribute":
        source = RedistributeDataSet(Input=reader)
    elif distribution == "d3":
        source = D3(Input=reader)
    else:
        source = reader
    f = builder(source)
    f.UpdatePipelineInformation()
    steps = list(getattr(f, "TimestepValues", []) or [])
    t = steps[-1] if steps else 0.0
    f.UpdatePipeline(t)
    grid, others = fetch_all(f)
    out = metrics(grid, t)
    if f.GetNumberOfOutputPorts() == 3:  # Segment: its Regions table's rows
        out["regions"] = servermanager.Fetch(f, 0, None, 2).GetNumberOfRows()
    return out, others


def compute(args, distributions, only=None):
    if args.client:
        from paraview.simple import Connect
        Connect("localhost", args.client)
        LoadPlugin(args.plugin, remote=True, ns=globals())
    else:
        LoadPlugin(args.plugin, ns=globals())
    results = {}
    WORK[0] = args.work
    for name, src, builder, dists in cases(args.data):
        if only and name not in only:
            continue
        local = os.path.join(args.work, os.path.basename(src))
        if not os.path.exists(local):
            with_global_ids(src, local)
        for d in distributions:
            if only and only[name] and d not in only[name]:
                continue
            if d == "serial" or d in dists:
                start = time.time()
                results[name + " " + d], others = run_case(builder, local, d)
                # The gathered filters' output is on process 0 only.
                if name != "MeshQuality" and others:
                    results[name + " " + d]["cells outside process 0"] = others
                print("%s %s: %.1f s" % (name, d, time.time() - start), flush=True)
    return results


# The filters run through pvserver too: one per mode and the order-dependent
# gathered one with every distribution (None), the other gathered filters
# after RedistributeDataSet only, to keep the test short.
PVSERVER_CASES = {"MeshQuality": None, "Improve": None, "Segment": ["redistribute"],
                  "Deform": ["redistribute"], "Adapt": ["redistribute"],
                  "HexToTet": ["redistribute"], "TetToHex": ["redistribute"]}


def free_port():
    import socket
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def run_pvserver(args, mpiexec, env):
    """`mpiexec -np N pvserver` and this script as its pvpython client:
    the client's results (None on failure) and both logs."""
    import threading
    bindir = os.path.dirname(args.pvbatch)
    pvserver, pvpython = os.path.join(bindir, "pvserver"), os.path.join(bindir, "pvpython")
    port = free_port()
    out = os.path.join(args.work, "pvserver.json")
    server = subprocess.Popen([mpiexec, "--allow-run-as-root", "--oversubscribe", "-np",
                               str(args.processes), pvserver, "--server-port=%d" % port],
                              env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines = []
    ready = threading.Event()

    def read():
        for line in server.stdout:
            lines.append(line)
            if "Accepting connection" in line:
                ready.set()
        ready.set()
    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    ready.wait(120)
    client = subprocess.run([pvpython, os.path.abspath(__file__), "--plugin", args.plugin, "--data",
                             args.data, "--work", args.work, "--client", str(port), "--mpi", out],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            timeout=300)
    try:
        server.wait(60)
    except subprocess.TimeoutExpired:
        server.kill()
        server.wait()
    reader.join(10)
    log = "pvserver:\n" + "".join(lines) + "\npvpython client:\n" + client.stdout
    if client.returncode != 0 or not os.path.exists(out):
        return None, log
    return json.load(open(out)), log


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--data", required=True, help="FEMorph's Data folder")
    parser.add_argument("--mpiexec", default="mpiexec")
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--pvbatch", default=shutil.which("pvbatch"))
    parser.add_argument("--mpi", help="(internal) run the distributed cases, write their results here")
    parser.add_argument("--work", help="(internal) folder of the inputs with global ids")
    parser.add_argument("--client", type=int, help="(internal) pvpython client of a pvserver on this port")
    args = parser.parse_args()

    if args.mpi:
        only = PVSERVER_CASES if args.client else None
        results = compute(args, ["redistribute", "d3", "rank0"], only)
        with open(args.mpi, "w") as f:
            json.dump(results, f)
        if args.client:
            from paraview.simple import Disconnect
            Disconnect()
        return 0

    mpiexec = shutil.which(args.mpiexec)
    if mpiexec is None:
        print("SKIP: %s not found" % args.mpiexec)
        return 77
    args.work = tempfile.mkdtemp(prefix="femorph_distributed_")
    serial = compute(args, ["serial"])
    out = os.path.join(args.work, "mpi.json")
    # The child must not inherit this process's MPI singleton environment.
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_"))}
    cmd = [mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", str(args.processes),
           args.pvbatch, os.path.abspath(__file__), "--plugin", args.plugin, "--data", args.data,
           "--work", args.work, "--mpi", out]
    start = time.time()
    proc = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(proc.stdout)
    print("mpiexec -np %d: %.1f s" % (args.processes, time.time() - start))
    if proc.returncode != 0:
        print("FAIL: mpiexec returned %d" % proc.returncode)
        return 1
    errors = [line for line in proc.stdout.splitlines() if "ERROR" in line or "Error" in line]
    distributed = json.load(open(out))
    # The same filters in ParaView's client-server mode: pvpython connected to
    # `mpiexec -np 2 pvserver`.
    served, log = run_pvserver(args, mpiexec, env)
    print(log)
    if served is None:
        errors.append("the pvserver run gave no result")
    else:
        errors += [line for line in log.splitlines() if "ERROR" in line or "Error" in line]
        distributed.update({"pvserver " + k: v for k, v in served.items()})
    failures = list(errors)
    compared = 0
    for key, got in sorted(distributed.items()):
        name = key.split()[1] if key.startswith("pvserver ") else key.split()[0]
        want = serial[name + " serial"]
        compared += 1
        if got.get("faces in more than two cells", 0) != 0:
            failures.append("%s: %d faces in more than two cells" % (key, got["faces in more than two cells"]))
        # Means are sums in another order under MPI: equal to 1e-12.
        for k in list(got):
            if "Mean" in k and k in want and abs(got[k] - want[k]) <= 1e-12 * max(1, abs(want[k])):
                got[k] = want[k]
        if got != want:
            diff = {k: (want.get(k), got.get(k)) for k in set(want) | set(got) if want.get(k) != got.get(k)}
            failures.append("%s differs from serial (serial, distributed): %s" % (key, diff))
        else:
            print("OK %s: %s" % (key, got))
    expected = sum(len(d) + len([x for x in d if n in PVSERVER_CASES and
                                 (PVSERVER_CASES[n] is None or x in PVSERVER_CASES[n])])
                   for n, _, _, d in cases(args.data))
    if compared != expected:
        failures.append("%d distributed results, %d expected" % (compared, expected))
    shutil.rmtree(args.work, ignore_errors=True)
    for f in failures:
        print("FAIL:", f)
    print("%d comparisons with the serial run, %d failures" % (compared, len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    # Under MPI, sys.exit would end process 0 before MPI's finalize (the
    # other processes then wait for it): exit only with a failure.
    status = main()
    if status:
        sys.exit(status)
