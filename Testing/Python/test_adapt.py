"""FEMorph Adapt through paraview.simple (thesis chapter 3): the motion steps
as time steps.

Run with pvpython, the package femorph on PYTHONPATH:
  PYTHONPATH=build/lib/python3.11/dist-packages pvpython test_adapt.py --plugin FEMorph.so \
      --out DIR [--data Data]

Builds a block of 5 x 5 x 5 unit cubes (12 tetrahedra around each cube's
centre) with the middle cube as object 1 (cell array MaterialId), sets every
property by its name, and checks: TimestepValues 0..NumberOfSteps (also in
the animation's time keeper), the output at several times (requested out of
order): positive tetrahedra, the object's centre moved by the translation
(the rotation is about it), the steps table with one row per step up to the
time, a step asked again served from the cache (ComputedSteps), SaveData
with WriteTimeSteps writing NumberOfSteps + 1 files, and the error of a
missing material array (empty output). The checks are computed here. With
--data: Data/adapt/block_in_box_small moved by a Motion table (a CSV file),
every step checked by adapt_check.py.
"""
import argparse
import glob
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from paraview.simple import *  # noqa: F401,F403
from paraview import simple
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_TETRA, vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

N = 5
STEPS = 4
DZ = 0.05
CENTRE = (2.5, 2.5, 2.5)


def make_block(path):
    """N^3 unit cubes of 12 tets each; material 1 on the middle cube."""
    points = vtkPoints()
    points.SetDataTypeToDouble()

    def lattice(i, j, k):
        return (k * (N + 1) + j) * (N + 1) + i

    for k in range(N + 1):
        for j in range(N + 1):
            for i in range(N + 1):
                points.InsertNextPoint(i, j, k)
    grid = vtkUnstructuredGrid()
    material = vtkIntArray()
    material.SetName("MaterialId")
    faces = [[(0, 0, 0), (0, 1, 0), (0, 1, 1), (0, 0, 1)], [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)],
             [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)], [(0, 1, 0), (1, 1, 0), (1, 1, 1), (0, 1, 1)],
             [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]]
    tets = []
    for k in range(N):
        for j in range(N):
            for i in range(N):
                centre = points.InsertNextPoint(i + 0.5, j + 0.5, k + 0.5)
                obj = (i, j, k) == (N // 2, N // 2, N // 2)
                for face in faces:
                    q = [lattice(i + a, j + b, k + c) for a, b, c in face]
                    m = q.index(min(q))  # the diagonal from the lowest id: neighbours agree
                    tris = ((q[m], q[(m + 1) % 4], q[(m + 2) % 4]), (q[m], q[(m + 2) % 4], q[(m + 3) % 4]))
                    for tri in tris:
                        tet = [tri[0], tri[1], tri[2], centre]
                        if volume([points.GetPoint(v) for v in tet]) < 0:
                            tet[1], tet[2] = tet[2], tet[1]
                        tets.append(tet)
                        material.InsertNextValue(1 if obj else 0)
    grid.SetPoints(points)
    grid.AllocateExact(len(tets), 4)
    for tet in tets:
        grid.InsertNextCell(VTK_TETRA, 4, tet)
    grid.GetCellData().AddArray(material)
    temperature = vtkDoubleArray()
    temperature.SetName("Temperature")
    for p in range(grid.GetNumberOfPoints()):
        x = grid.GetPoint(p)
        temperature.InsertNextValue(x[0] + 2 * x[1] + 3 * x[2])
    grid.GetPointData().AddArray(temperature)
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(grid)
    assert writer.Write() == 1
    return grid


def volume(p):
    a, b, c, d = p
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    w = [d[i] - a[i] for i in range(3)]
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6


def object_centre(grid):
    """Mean of the points of the cells with MaterialId 1."""
    material = grid.GetCellData().GetArray("MaterialId")
    ids = set()
    for c in range(grid.GetNumberOfCells()):
        if material.GetValue(c) == 1:
            cell = grid.GetCell(c)
            ids.update(cell.GetPointId(k) for k in range(4))
    pts = [grid.GetPoint(p) for p in ids]
    return [sum(p[i] for p in pts) / len(pts) for i in range(3)], len(ids)


def check_block_in_box(data_dir, out_dir, rows=6):
    """Data/adapt/block_in_box_small with thesis 3.7.2's motion given as a
    Motion table (a CSV file of m00..m33, one row per step, read by
    ParaView's CSV reader): the time steps are capped at its rows, and every
    step written is checked by adapt_check.py (independent of FEMorph)."""
    import json
    import adapt_check
    case = os.path.join(data_dir, "adapt", "block_in_box_small")
    with open(case + ".json") as f:
        motion = json.load(f)["motion_3_7_2"]
    poses = [adapt_check.motion_pose(n, motion["translation_per_step"], motion["rotation_axis"],
                                     motion["rotation_center"], motion["rotation_degrees_per_step"])
             for n in range(rows + 1)]
    csv = os.path.join(out_dir, "motion.csv")
    with open(csv, "w") as f:
        f.write(",".join("m%d%d" % (r, c) for r in range(4) for c in range(4)) + "\n")
        for R, t in poses[1:]:
            m = [R[r][c] if c < 3 else t[r] for r in range(3) for c in range(4)] + [0, 0, 0, 1]
            f.write(",".join(repr(float(v)) for v in m) + "\n")
    reader = XMLUnstructuredGridReader(FileName=[case + ".vtu"])
    table = CSVReader(FileName=[csv])
    adapt = FEMorphAdapt(Input=reader, Motion=table, NumberOfSteps=10)
    adapt.UpdatePipelineInformation()
    assert list(adapt.TimestepValues) == [float(n) for n in range(rows + 1)], list(adapt.TimestepValues)
    pvd = os.path.join(out_dir, "block_in_box.pvd")
    SaveData(pvd, proxy=adapt, WriteTimeSteps=1)
    steps = sorted(glob.glob(os.path.join(out_dir, "block_in_box", "*.vtu")),
                   key=lambda p: int(p.rsplit("_", 1)[1].split(".")[0]))
    assert len(steps) == rows + 1, steps
    for n, path in enumerate(steps):
        R, t = poses[n]
        ok, results, _ = adapt_check.check(case + ".vtu", path, R, t)
        if not ok:
            adapt_check.print_rows(results)
        assert ok, "step %d of block_in_box_small fails adapt_check" % n
    print("block_in_box_small: %d steps from the Motion table pass adapt_check" % rows)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--out", default=None, help="folder for the files (default: a temporary one)")
    parser.add_argument("--data", default=None,
                        help="FEMorph's Data folder: also Data/adapt/block_in_box_small with a Motion table, "
                             "checked by adapt_check.py")
    args = parser.parse_args()
    LoadPlugin(args.plugin, ns=globals())
    out_dir = args.out or tempfile.mkdtemp(prefix="femorph_adapt_")
    os.makedirs(out_dir, exist_ok=True)
    for old in glob.glob(os.path.join(out_dir, "*.vtu")) + glob.glob(os.path.join(out_dir, "*", "*.vtu")):
        os.remove(old)

    block = os.path.join(out_dir, "block.vtu")
    make_block(block)
    reader = XMLUnstructuredGridReader(FileName=[block])
    adapt = FEMorphAdapt(Input=reader)
    adapt.MaterialArray = "MaterialId"
    adapt.MovingObject = 1
    adapt.TranslationPerStep = [0, 0, DZ]
    adapt.RotationAxis = [1, 0, 0]
    adapt.RotationCenter = list(CENTRE)
    adapt.RotationAnglePerStep = 2
    adapt.NumberOfSteps = STEPS
    adapt.DistanceThreshold = 3
    adapt.GridCellSize = 0
    adapt.Improve = 1
    adapt.QualityFloor = 0.3
    adapt.CacheMemoryLimit = 256
    adapt.UpdatePipelineInformation()
    times = list(adapt.TimestepValues)
    assert times == [float(n) for n in range(STEPS + 1)], times
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    keeper = list(GetTimeKeeper().TimestepValues)
    assert keeper == times, keeper

    # The wrapped class (the package femorph) gives the filter's own methods.
    import femorph  # noqa: F401
    algorithm = adapt.GetClientSideObject()
    input_centre, object_points = None, None
    for t in (2, 4, 1, 0, 3):
        adapt.UpdatePipeline(t)
        mesh = algorithm.GetOutputDataObject(0)
        table = algorithm.GetOutputDataObject(1)
        assert mesh.GetNumberOfCells() > 0, "time %g: empty output" % t
        assert table.GetNumberOfRows() == t + 1, (t, table.GetNumberOfRows())
        assert table.GetColumnByName("MinStretch") is not None
        for c in range(mesh.GetNumberOfCells()):
            cell = mesh.GetCell(c)
            assert cell.GetCellType() == VTK_TETRA
            v = volume([mesh.GetPoint(cell.GetPointId(k)) for k in range(4)])
            assert v > 0, "time %g: tet %d has volume %g" % (t, c, v)
        assert mesh.GetPointData().GetArray("Temperature") is not None
        centre, count = object_centre(mesh)
        if input_centre is None:
            input_centre, object_points = object_centre(reader.GetClientSideObject().GetOutput())
        assert count == object_points, (t, count, object_points)
        expected = [input_centre[0], input_centre[1], input_centre[2] + DZ * t]
        assert max(abs(centre[i] - expected[i]) for i in range(3)) < 1e-9, (t, centre, expected)
        print("time %g: %d tets, object centre z %.4f" % (t, mesh.GetNumberOfCells(), centre[2]))
    # Steps 1..4 once each: the later requests came from the cache.
    assert algorithm.GetComputedSteps() == STEPS, algorithm.GetComputedSteps()

    # Every time step written: a .pvd collection of one .vtu per step.
    SaveData(os.path.join(out_dir, "adapt.pvd"), proxy=adapt, WriteTimeSteps=1)
    written = sorted(glob.glob(os.path.join(out_dir, "adapt", "*.vtu")))
    assert len(written) == STEPS + 1, written
    with open(os.path.join(out_dir, "adapt.pvd")) as pvd:
        assert pvd.read().count("<DataSet ") == STEPS + 1
    assert algorithm.GetComputedSteps() == STEPS, algorithm.GetComputedSteps()

    if args.data:
        check_block_in_box(args.data, out_dir)

    # A missing material array: an error and an empty output.
    bad = FEMorphAdapt(Input=reader, MaterialArray="Nope", NumberOfSteps=2)
    bad.UpdatePipeline(1)
    assert bad.GetClientSideObject().GetOutputDataObject(0).GetNumberOfCells() == 0
    print("OK: FEMorph Adapt, %d steps, %d files" % (STEPS, len(written)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
