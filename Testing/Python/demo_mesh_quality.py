"""FEMorph's main job today: the quality of a part's tetrahedral mesh.

Reads a part (default Data/boss_block.vtu), runs FEMorph Mesh Quality, writes
  <output-dir>/<name>_quality.vtu   the mesh with the quality arrays
  <output-dir>/<name>_stretch.png   the part coloured by Stretch
and prints the quality summary.

Run with pvbatch; the picture needs an X display (Debian's ParaView has no
offscreen-only build), e.g.:
  xvfb-run -a -s "-noreset -screen 0 1280x1024x24" pvbatch demo_mesh_quality.py [part.vtu]
The plugin is found with --plugin, else in the build folder (build/ by
default), else from PV_PLUGIN_PATH.
"""
import argparse
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLUGIN_IN_BUILD = os.path.join("lib", "femorph", "FEMorph", "FEMorph.so")


def find_plugin(args):
    if args.plugin:
        return args.plugin
    candidate = os.path.join(args.build_dir, PLUGIN_IN_BUILD)
    if os.path.isfile(candidate):
        return candidate
    return None  # rely on PV_PLUGIN_PATH


def summary_table(data):
    """The filter's field-data summary as printable lines."""
    fd = data.GetFieldData()

    def value(name):
        array = fd.GetArray(name)
        return array.GetTuple1(0) if array is not None else float("nan")

    rows = [
        ("Stretch (Eq. 1.1)", "Stretch", ""),
        ("Scaled Jacobian (Eq. 4.2)", "ScaledJacobian", ""),
        ("Min dihedral angle", "MinDihedralAngle", " deg"),
        ("Max dihedral angle", "MaxDihedralAngle", " deg"),
    ]
    lines = ["%-26s %10s %10s %10s" % ("measure", "min", "mean", "max")]
    lines.append("-" * len(lines[0]))
    for label, name, unit in rows:
        if name == "MinDihedralAngle":
            low, mean, high = value(name + "Min"), value(name + "Mean"), float("nan")
        elif name == "MaxDihedralAngle":
            low, mean, high = float("nan"), value(name + "Mean"), value(name + "Max")
        else:
            low, mean, high = value(name + "Min"), value(name + "Mean"), value(name + "Max")
        cells = ["%10s" % ("-" if v != v else "%.4f" % v) for v in (low, mean, high)]
        lines.append("%-26s %s%s" % (label, " ".join(cells), unit))
    lines.append("")
    counts = [
        ("tetrahedra", "TetraCount"),
        ("hexahedra", "HexahedronCount"),
        ("wedges", "WedgeCount"),
        ("pyramids", "PyramidCount"),
        ("cells not evaluated", "SkippedCellCount"),
        ("inverted cells", "InvertedCount"),
        ("zero-volume tetrahedra", "ZeroVolumeCount"),
        ("tetrahedra with stretch < %.3g" % value("StretchThreshold"), "BelowThresholdCount"),
    ]
    for label, name in counts:
        count = value(name)
        if name in ("HexahedronCount", "WedgeCount", "PyramidCount", "SkippedCellCount") and not count:
            continue
        lines.append("%-34s %10d" % (label, count))
    return lines


def render(quality, png, title):
    view = simple.CreateView("RenderView")
    view.ViewSize = [1280, 960]
    view.OrientationAxesVisibility = 1
    view.Background = [1.0, 1.0, 1.0]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    display = simple.Show(quality, view)
    display.SetRepresentationType("Surface With Edges")
    display.EdgeColor = [0.15, 0.15, 0.15]
    simple.ColorBy(display, ("CELLS", "Stretch"))
    lut = simple.GetColorTransferFunction("Stretch")
    lut.ApplyPreset("Turbo", True)
    lut.InvertTransferFunction()  # low stretch (bad) in red
    lut.RescaleTransferFunction(0.0, 1.0)  # the same scale for every part
    lut.AutomaticRescaleRangeMode = "Never"
    display.SetScalarBarVisibility(view, True)
    bar = simple.GetScalarBar(lut, view)
    bar.Title = "Stretch"
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    bar.RangeLabelFormat = "%-#.2f"
    text = simple.Text(Text=title)
    text_display = simple.Show(text, view)
    text_display.Color = [0.0, 0.0, 0.0]
    text_display.FontSize = 14
    text_display.WindowLocation = "Upper Left Corner"

    # The first render resets the camera: render once, then place it.
    simple.Render(view)
    # An isometric view from the front right, above.
    view.CameraPosition = [1.0, -1.2, 0.9]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera()
    view.GetActiveCamera().Dolly(1.15)  # ResetCamera leaves a wide margin
    simple.Render(view)
    simple.SaveScreenshot(png, view, ImageResolution=[1280, 960])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("part", nargs="?", default=os.path.join(REPO, "Data", "boss_block.vtu"),
                        help="tetrahedral mesh (.vtu); default Data/boss_block.vtu")
    parser.add_argument("--output-dir", default="out", help="where to write (default out/)")
    parser.add_argument("--plugin", help="path of FEMorph.so")
    parser.add_argument("--build-dir", default=os.path.join(REPO, "build"),
                        help="build folder to find the plugin in (default build/)")
    parser.add_argument("--stretch-threshold", type=float, default=None,
                        help="StretchThreshold property (default: the filter's, 0.05)")
    parser.add_argument("--no-picture", action="store_true", help="skip the PNG (no X needed)")
    args = parser.parse_args()

    plugin = find_plugin(args)
    ns = {}
    if plugin:
        simple.LoadPlugin(plugin, ns=ns)
    make_quality = ns.get("FEMorphMeshQuality") or getattr(simple, "FEMorphMeshQuality", None)
    if make_quality is None:
        sys.exit("FEMorph plugin not found: pass --plugin path/FEMorph.so, build into %s, or set "
                 "PV_PLUGIN_PATH" % args.build_dir)
    if not os.path.isfile(args.part):
        sys.exit("no such part: %s" % args.part)

    name = os.path.splitext(os.path.basename(args.part))[0]
    os.makedirs(args.output_dir, exist_ok=True)
    vtu = os.path.join(args.output_dir, name + "_quality.vtu")
    png = os.path.join(args.output_dir, name + "_stretch.png")

    reader = simple.XMLUnstructuredGridReader(FileName=[args.part])
    quality = make_quality(Input=reader)
    if args.stretch_threshold is not None:
        quality.StretchThreshold = args.stretch_threshold
    quality.UpdatePipeline()
    # Fetch gathers the result on this process (all pieces under MPI), and
    # VTK's own writer writes it: ParaView's .vtu writer is serial only.
    data = servermanager.Fetch(quality)
    if data.GetNumberOfCells() == 0 or data.GetFieldData().GetArray("TetraCount") is None:
        sys.exit("FEMorph Mesh Quality produced no result for %s (see the messages above)"
                 % args.part)
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(vtu)
    writer.SetInputData(data)
    writer.SetDataModeToAppended()
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        sys.exit("failed to write %s" % vtu)

    shown = os.path.relpath(args.part)
    if shown.startswith(".."):
        shown = args.part
    print("FEMorph Mesh Quality of %s (%d points, %d cells)" % (
        shown, data.GetNumberOfPoints(), data.GetNumberOfCells()))
    print()
    for line in summary_table(data):
        print(line)
    print()
    written = [vtu]
    if not args.no_picture:
        render(quality, png, "%s: FEMorph Mesh Quality, Stretch (Eq. 1.1)" % name)
        written.append(png)
    for path in written:
        if not os.path.isfile(path) or os.path.getsize(path) == 0:
            sys.exit("failed to write %s" % path)
        print("wrote %s" % path)


if __name__ == "__main__":
    main()
