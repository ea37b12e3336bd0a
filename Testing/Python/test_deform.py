"""FEMorph Deform against the CAD of the changed part (thesis 2.5, Table 2.7).

Run with pvbatch:
  pvbatch test_deform.py --plugin FEMorph.so --data DIR --case NAME [--out DIR]
  pvbatch test_deform.py --plugin FEMorph.so --data DIR --errors

A case deforms a Data/ part (FEMorph Segment, then FEMorph Deform with the
case's type, control point and target) and checks the output with
deform_check.py (numpy and VTK only, not FEMorph's code) against the variant
Data/variants/<part>__<variant> made by the CAD kernel: no inverted or
non-conforming tet, minimum stretch >= 0.2 and >= 0.8 x the input's, every
boundary vertex on the variant's exact surfaces (1e-6 of the part), the
variant's CAD within 1.1 x the base mesh's chord error of the mesh, the
volume within the base mesh's own volume error (scaled by (r'/r)^2 for a
radius: the chord error grows with it), the fixed faces' points bit for bit,
and the filter's field data (CurrentDimension, TargetDimension, a ValidRange
holding the target). --errors checks the bad-input messages. Exits 77 when
the data is missing.
"""
import argparse
import math
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter  # noqa: E402

BLOCK = ["block bottom", "block side x=0", "block side x=L", "block side y=0", "block side y=W"]
BOSS = ["boss top", "boss side", "boss top chamfer", "boss base fillet"]
TOP, SIDE = [35, 30, 35], [47, 30, 28]
FILLET, CHAMFER, HOLE = [47.879, 30, 20.879], [46, 30, 34], [81, 30, 10]

# name: (part, variant, type, control point, target, fixed labels, volume scale, extra)
CASES = {
    "boss_height_20": ("boss_block", "boss_height_20", 0, TOP, 20,
                       BLOCK + ["block top", "through hole", "boss base fillet"], 1.1, {}),
    "boss_height_10": ("boss_block", "boss_height_10", 0, TOP, 10,
                       BLOCK + ["block top", "through hole", "boss base fillet"], 1.1, {}),
    "boss_radius_14": ("boss_block", "boss_radius_14", 1, SIDE, 14, BLOCK + ["through hole"], (14 / 12) ** 2, {}),
    "boss_radius_10": ("boss_block", "boss_radius_10", 1, SIDE, 10, BLOCK + ["through hole"], 1.1, {}),
    "fillet_radius_4": ("boss_block", "boss_fillet_radius_4", 2, FILLET, 4,
                        BLOCK + ["through hole", "boss top", "boss top chamfer"], (4 / 3) ** 2, {}),
    "fillet_radius_2": ("boss_block", "boss_fillet_radius_2", 2, FILLET, 2,
                        BLOCK + ["through hole", "boss top", "boss top chamfer"], 1.1, {}),
    "chamfer_length_3": ("boss_block", "boss_chamfer_length_3", 4, CHAMFER, 3,
                         BLOCK + ["through hole", "block top", "boss base fillet"], 1.1, {}),
    "chamfer_angle_60": ("boss_block", "boss_chamfer_angle_60", 3, CHAMFER, 60,
                         BLOCK + ["through hole", "block top", "boss base fillet"], 1.1, {}),
    "hole_radius_8": ("boss_block", "hole_radius_8", 1, HOLE, 8, BLOCK[1:] + BOSS, (8 / 6) ** 2, {}),
    "hole_radius_4": ("boss_block", "hole_radius_4", 1, HOLE, 4, BLOCK[1:] + BOSS, 1.1, {}),
    "boss_moved": ("boss_block", "boss_moved", 6, SIDE, 0, BLOCK + ["through hole"], 1.1,
                   {"Translation": [5, 10, 0]}),
    "sphere_radius_11": ("cone_sphere_torus", "cap_sphere_radius_11", 5, [0, 0, 46.877], 11,
                         ["base top", "base rim", "base bottom", "shaft", "shaft fillet"]
                         + ["bolt hole %d" % i for i in range(4)], 1.1, {}),
    "shaft_radius_13": ("cone_sphere_torus", "shaft_radius_13", 1, [12, 0, 22], 13,
                        ["base rim", "base bottom", "spherical cap"] + ["bolt hole %d" % i for i in range(4)],
                        (13 / 12) ** 2, {}),
    "edge_fillet_8": ("filleted_box", "edge_fillet_radius_8", 2, [1.757, 1.757, 15], 8, [], (8 / 6) ** 2, {}),
    "beam_width_20": ("beam", "width20", 0, [50, 10, 5], 20, ["face y=0"], 1.1, {}),
}


def field(data, name, component=0):
    a = data.GetFieldData().GetArray(name)
    return None if a is None else a.GetComponent(0, component)


def deform(plugin_data, part, props):
    reader = XMLUnstructuredGridReader(FileName=[os.path.join(plugin_data, part + ".vtu")])
    seg = FEMorphSegment(Input=reader)
    d = FEMorphDeform(Input=seg)
    for k, v in props.items():
        setattr(d, k, v)
    d.UpdatePipeline()
    return servermanager.Fetch(d), servermanager.Fetch(reader)


def min_stretch(grid):
    from deform_check import read_mesh, validity
    return validity(read_mesh(grid))["stretch_min"]


def run_case(args, name):
    import deform_check
    part, variant, dtype, point, target, fixed, vscale, extra = CASES[name]
    props = dict(DeformationType=dtype, UseControlPoint=1, ControlPoint=point, TargetValue=target)
    props.update(extra)
    out, base = deform(args.data, part, props)
    failures = []
    if out.GetNumberOfCells() == 0:
        print(f"{name}: the filter gave an empty output")
        return 1
    path = os.path.join(args.out, f"deform_{name}.vtu")
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(out)
    w.Write()
    ok, rows, _ = deform_check.check(os.path.join(args.data, part + ".vtu"),
                                     os.path.join(args.data, "variants", f"{part}__{variant}"), path,
                                     fixed_labels=fixed or None, volume_scale=vscale)
    deform_check.print_rows(rows)
    if not ok:
        failures.append("deform_check")
    s_in, s_out = min_stretch(base), min_stretch(out)
    print(f"minimum stretch {s_in:.4f} -> {s_out:.4f}")
    if not s_out >= 0.8 * s_in:
        failures.append(f"minimum stretch {s_out:.4f} below 0.8 x the input's {s_in:.4f}")
    current, tgt = field(out, "CurrentDimension"), field(out, "TargetDimension")
    lo, hi = field(out, "ValidRange", 0), field(out, "ValidRange", 1)
    print(f"CurrentDimension {current}, TargetDimension {tgt}, ValidRange [{lo}, {hi}], "
          f"steps {field(out, 'DeformSteps')}, seconds {field(out, 'DeformTimes', 5)}")
    want = target if dtype != 6 else math.sqrt(sum(x * x for x in extra.get("Translation", [0, 0, 0])))
    if tgt is None or abs(tgt - want) > 1e-9 * max(1, abs(want)):
        failures.append(f"TargetDimension {tgt}, expected {want}")
    if not (lo is not None and lo <= want <= hi):
        failures.append(f"ValidRange [{lo}, {hi}] does not hold the target {want}")
    for f in failures:
        print("FAILED:", f)
    return 1 if failures else 0


def expect_error(args, part, props, words):
    """The filter refuses with a message holding `words` and gives an empty output."""
    from paraview import vtk  # noqa: F401
    from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
    window = vtkStringOutputWindow()
    previous = vtkOutputWindow.GetInstance()
    vtkOutputWindow.SetInstance(window)
    try:
        out, _ = deform(args.data, part, props)
    finally:
        vtkOutputWindow.SetInstance(previous)
    text = window.GetOutput()
    ok = out.GetNumberOfCells() == 0 and all(w in text for w in words)
    print(("ok     " if ok else "FAILED ") + f"{props} -> {words}")
    if not ok:
        print("  cells:", out.GetNumberOfCells(), "messages:", text[-600:])
    return 0 if ok else 1


def run_errors(args):
    bad = 0
    # A control region of the wrong type, naming both.
    bad += expect_error(args, "boss_block", dict(DeformationType=1, UseControlPoint=1, ControlPoint=TOP,
                                                 TargetValue=5), ["is a plane", "CylinderRadius needs a cylinder"])
    # A target outside the valid range, with the range.
    bad += expect_error(args, "boss_block", dict(DeformationType=0, UseControlPoint=1, ControlPoint=TOP,
                                                 TargetValue=3), ["outside the valid range", "[5.0"])
    bad += expect_error(args, "boss_block", dict(DeformationType=1, UseControlPoint=1, ControlPoint=HOLE,
                                                 TargetValue=40), ["outside the valid range"])
    # Position with a translation out of the plane.
    bad += expect_error(args, "boss_block", dict(DeformationType=6, UseControlPoint=1, ControlPoint=SIDE,
                                                 Translation=[0, 0, 5]), ["Position"])
    # A region id that names nothing; no control region at all.
    bad += expect_error(args, "boss_block", dict(DeformationType=0, ControlRegion=99, TargetValue=5),
                        ["ControlRegion 99 names no region"])
    bad += expect_error(args, "boss_block", dict(DeformationType=0, TargetValue=5), ["no control region"])
    # Measure only (no target): the input unchanged, with the dimension.
    out, base = deform(args.data, "boss_block", dict(DeformationType=0, UseControlPoint=1, ControlPoint=TOP))
    same = out.GetNumberOfPoints() == base.GetNumberOfPoints() and out.GetNumberOfCells() == base.GetNumberOfCells()
    if same:
        for i in range(0, base.GetNumberOfPoints(), 97):
            same = same and out.GetPoint(i) == base.GetPoint(i)
    current = field(out, "CurrentDimension")
    ok = same and current is not None and abs(current - 15) < 1e-9 and out.GetCellData().GetArray("RegionRole")
    print(("ok     " if ok else "FAILED ") + f"measure only: unchanged {same}, CurrentDimension {current}")
    bad += 0 if ok else 1
    return 1 if bad else 0


def run_sweep(args):
    """Parameterise once, reposition many: with Improve off, a sweep of the
    boss height over several targets parameterises on the first and only
    repositions on the others (DeformTimes), each output exact."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data, "boss_block.vtu")])
    seg = FEMorphSegment(Input=reader)
    d = FEMorphDeform(Input=seg, DeformationType=0, UseControlPoint=1, ControlPoint=TOP, Improve=0)
    base = vtk_to_numpy(servermanager.Fetch(reader).GetPoints().GetData())
    top = np.nonzero(np.abs(base[:, 2] - 35) < 1e-12)[0]
    bad = 0
    for i, target in enumerate((17.0, 16.0, 16.5, 15.5)):
        d.TargetValue = target
        d.UpdatePipeline()
        out = servermanager.Fetch(d)
        p = vtk_to_numpy(out.GetPoints().GetData())
        param, repos = field(out, "DeformTimes", 2), field(out, "DeformTimes", 3)
        exact = len(top) > 0 and np.all(np.abs(p[top, 2] - (20 + target)) < 1e-12)
        ok = exact and ((param > 0) if i == 0 else (param == 0 and repos > 0))
        print(("ok     " if ok else "FAILED ") + f"target {target}: parameterize {param:.4f} s, "
              f"reposition {repos:.4f} s, boss top at {20 + target}: {exact}")
        bad += 0 if ok else 1
    return 1 if bad else 0


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--data", required=True)
    parser.add_argument("--case", choices=sorted(CASES))
    parser.add_argument("--errors", action="store_true")
    parser.add_argument("--sweep", action="store_true")
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    if not os.path.isdir(os.path.join(args.data, "variants")):
        print("no variants in", args.data)
        return 77
    LoadPlugin(args.plugin, ns=globals())
    if args.out is None:
        args.out = tempfile.mkdtemp(prefix="femorph_deform_")
    os.makedirs(args.out, exist_ok=True)
    if args.errors:
        return run_errors(args)
    if args.sweep:
        return run_sweep(args)
    return run_case(args, args.case)


if __name__ == "__main__":
    sys.exit(main())
