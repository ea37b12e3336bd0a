"""FEMorph's main job: change one dimension of a part on its mesh.

Reads a part (default Data/boss_block.vtu), segments it (FEMorph Segment),
changes the boss height 15 -> 20 mm (FEMorph Deform, Distance on the boss
top, with the built-in improvement), checks the result (FEMorph Mesh
Quality: no inverted tetrahedron) and writes
  <output-dir>/<name>_deformed.vtu   the deformed mesh
  <output-dir>/<name>_deform.png     before and after, cut through the boss
and prints the current and new dimension, the valid range, the quality
before and after, the time, and the time Gmsh takes to re-mesh the changed
CAD part (for the default part, when Gmsh's Python module is there).

Another part or change: --control-point X Y Z (a point on the face to
change), --type (Distance, CylinderRadius, FilletRadius, ChamferAngle,
ChamferLength, SphereRadius, Position), --target VALUE.

Run with pvbatch; the picture needs an X display, e.g.
  xvfb-run -a -s "-noreset -screen 0 1280x1024x24" pvbatch demo_deform.py
The plugin is found with --plugin, else in the build folder, else from
PV_PLUGIN_PATH.
"""
import argparse
import os
import subprocess
import sys
import time

import paraview.simple as simple
from paraview import servermanager
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLUGIN_IN_BUILD = os.path.join("lib", "femorph", "FEMorph", "FEMorph.so")
TYPES = ["Distance", "CylinderRadius", "FilletRadius", "ChamferAngle", "ChamferLength", "SphereRadius",
         "Position"]


def field(data, name, component=0):
    array = data.GetFieldData().GetArray(name)
    return array.GetComponent(0, component) if array is not None else float("nan")


def gmsh_seconds(target):
    """Seconds Gmsh (OpenCASCADE) takes to mesh boss_block with the boss
    height `target` at the part's own sizes, or None."""
    code = ("import sys, time; sys.path.insert(0, %r); import generate_parts as g, gmsh\n"
            "gmsh.initialize(); gmsh.option.setNumber('General.Terminal', 0)\n"
            "t0 = time.time(); g.setup_part('boss_block', 1.0, {'boss_height': %r})\n"
            "gmsh.model.mesh.generate(3); print(time.time() - t0)\n") % (os.path.join(REPO, "Data"), target)
    try:
        out = subprocess.run(["/usr/bin/python3", "-c", code], capture_output=True, text=True, timeout=600)
        return float(out.stdout.strip().splitlines()[-1]) if out.returncode == 0 else None
    except (OSError, ValueError, IndexError, subprocess.TimeoutExpired):
        return None


def render(before, after, png, title, shift):
    view = simple.CreateView("RenderView")
    view.ViewSize = [1280, 720]
    view.OrientationAxesVisibility = 0
    view.Background = [1.0, 1.0, 1.0]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    lut = simple.GetColorTransferFunction("Stretch")
    lut.ApplyPreset("Turbo", True)
    lut.InvertTransferFunction()
    lut.RescaleTransferFunction(0.0, 1.0)
    lut.AutomaticRescaleRangeMode = "Never"
    for source, dx in ((before, 0.0), (after, shift)):
        clip = simple.Clip(Input=source)
        clip.ClipType = "Plane"
        clip.ClipType.Origin = [35.0, 30.0, 0.0]
        clip.ClipType.Normal = [0.0, -1.0, 0.0]  # keeps y > 30: the cut faces the camera
        clip.Crinkleclip = 1
        moved = simple.Transform(Input=clip)
        moved.Transform.Translate = [dx, 0.0, 0.0]
        display = simple.Show(moved, view)
        display.SetRepresentationType("Surface With Edges")
        display.EdgeColor = [0.15, 0.15, 0.15]
        simple.ColorBy(display, ("CELLS", "Stretch"))
    display.SetScalarBarVisibility(view, True)
    bar = simple.GetScalarBar(lut, view)
    bar.Title = "Stretch"
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    text = simple.Text(Text=title)
    shown = simple.Show(text, view)
    shown.Color = [0.0, 0.0, 0.0]
    shown.FontSize = 14
    shown.WindowLocation = "Upper Left Corner"
    simple.Render(view)
    view.CameraPosition = [0.6, -1.6, 0.7]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera()
    view.GetActiveCamera().Dolly(1.3)
    simple.Render(view)
    simple.SaveScreenshot(png, view, ImageResolution=[1280, 720])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("part", nargs="?", default=os.path.join(REPO, "Data", "boss_block.vtu"))
    parser.add_argument("--type", choices=TYPES, default="Distance")
    parser.add_argument("--control-point", nargs=3, type=float, default=[35.0, 30.0, 35.0])
    parser.add_argument("--target", type=float, default=20.0)
    parser.add_argument("--output-dir", default="out")
    parser.add_argument("--plugin")
    parser.add_argument("--build-dir", default=os.path.join(REPO, "build"))
    parser.add_argument("--no-picture", action="store_true", help="skip the PNG (no X needed)")
    parser.add_argument("--no-gmsh", action="store_true", help="skip the Gmsh re-meshing time")
    args = parser.parse_args()

    plugin = args.plugin or os.path.join(args.build_dir, PLUGIN_IN_BUILD)
    ns = {}
    if os.path.isfile(plugin):
        simple.LoadPlugin(plugin, ns=ns)
    if "FEMorphDeform" not in ns and not hasattr(simple, "FEMorphDeform"):
        sys.exit("FEMorph plugin not found: pass --plugin path/FEMorph.so, build into %s, or set "
                 "PV_PLUGIN_PATH" % args.build_dir)
    get = lambda name: ns.get(name) or getattr(simple, name)  # noqa: E731
    if not os.path.isfile(args.part):
        sys.exit("no such part: %s" % args.part)
    name = os.path.splitext(os.path.basename(args.part))[0]
    os.makedirs(args.output_dir, exist_ok=True)

    reader = simple.XMLUnstructuredGridReader(FileName=[args.part])
    segment = get("FEMorphSegment")(Input=reader)
    segment.UpdatePipeline()
    deform = get("FEMorphDeform")(Input=segment)
    deform.DeformationType = TYPES.index(args.type)
    deform.UseControlPoint = 1
    deform.ControlPoint = args.control_point
    deform.TargetValue = args.target
    t0 = time.time()
    deform.UpdatePipeline()
    seconds = time.time() - t0
    result = servermanager.Fetch(deform)
    if result.GetNumberOfCells() == 0:
        sys.exit("FEMorph Deform produced no result (see the messages above)")
    quality_in = servermanager.Fetch(get("FEMorphMeshQuality")(Input=reader))
    quality_out = servermanager.Fetch(get("FEMorphMeshQuality")(Input=deform))
    if field(quality_out, "InvertedCount") != 0 or field(quality_out, "ZeroVolumeCount") != 0:
        sys.exit("the deformed mesh has inverted or flat tetrahedra")

    vtu = os.path.join(args.output_dir, name + "_deformed.vtu")
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(vtu)
    writer.SetInputData(result)
    writer.SetDataModeToAppended()
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        sys.exit("failed to write %s" % vtu)

    unit = " deg" if args.type == "ChamferAngle" else " mm"
    print("FEMorph Deform of %s: %s of region %d" % (os.path.relpath(args.part), args.type,
                                                      int(field(result, "ControlRegion"))))
    print()
    print("%-34s %12.4f%s" % ("current dimension", field(result, "CurrentDimension"), unit))
    print("%-34s %12.4f%s" % ("new dimension", field(result, "TargetDimension"), unit))
    print("%-34s [%.4f, %.4f]%s" % ("valid range", field(result, "ValidRange", 0),
                                     field(result, "ValidRange", 1), unit))
    print("%-34s %12d" % ("steps", field(result, "DeformSteps")))
    print("%-34s %12d -> %d" % ("tetrahedra", quality_in.GetNumberOfCells(), result.GetNumberOfCells()))
    print("%-34s %12.4f -> %.4f" % ("minimum stretch (Eq. 1.1)", field(quality_in, "StretchMin"),
                                     field(quality_out, "StretchMin")))
    print("%-34s %12.4f -> %.4f" % ("mean stretch", field(quality_in, "StretchMean"),
                                     field(quality_out, "StretchMean")))
    print("%-34s %12d" % ("inverted tetrahedra", field(quality_out, "InvertedCount")))
    print("%-34s %12.2f s (in the filter %.2f s)" % ("time, deform + improve", seconds,
                                                       field(result, "DeformTimes", 5)))
    if name == "boss_block" and args.type == "Distance" and not args.no_gmsh:
        g = gmsh_seconds(args.target)
        if g is not None:
            print("%-34s %12.2f s" % ("Gmsh re-meshing the changed CAD", g))
    print()
    written = [vtu]
    if not args.no_picture:
        png = os.path.join(args.output_dir, name + "_deform.png")
        render(get("FEMorphMeshQuality")(Input=reader), deform, png, "%s: %s %.4g -> %.4g%s (left: before, right: after), Stretch" % (
            name, args.type, field(result, "CurrentDimension"), args.target, unit), 110.0)
        written.append(png)
    for path in written:
        if not os.path.isfile(path) or os.path.getsize(path) == 0:
            sys.exit("failed to write %s" % path)
        print("wrote %s" % path)


if __name__ == "__main__":
    main()
