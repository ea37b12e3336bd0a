"""Before/after pictures of FEMorph Deform on boss_block (thesis Figs. 2.50 and 2.52).

    xvfb-run -a -s "-noreset -screen 0 1280x1024x24" \\
      pvbatch Testing/Scripts/render_deform.py --plugin build/lib/femorph/FEMorph/FEMorph.so \\
      [--part Data/boss_block.vtu] [--output-dir docs/images] [--only NAME ...]

For each change below, segments the part (FEMorph Segment), deforms it
(FEMorph Deform, Improve on) and writes <output-dir>/deform_<NAME>.png: the
part before (left) and after (right), cut through the boss axis (the plane
y = boss centre, the half behind it kept), tets with their edges, the
deformed part coloured by the magnitude of its point array Displacement.

    boss_height     Distance on the boss top, 15 -> 20          (Fig. 2.50)
    boss_radius     CylinderRadius on the boss side, 12 -> 14   (Fig. 2.50)
    fillet_radius   FilletRadius on the torus, 3 -> 4           (Fig. 2.50)
    chamfer_angle   ChamferAngle, 45 -> 60                      (Fig. 2.50)
    chamfer_length  ChamferLength, 2 -> 3                       (Fig. 2.50)
    boss_position   Position, boss side, moved by (5, 10, 0)    (Fig. 2.52)

The filter is FEMorphDeform from paraview.simple when the plugin's XML has
it; otherwise the VTK class through the plugin's Python package (femorph,
in <build>/lib/python3.11/dist-packages, found next to the plugin or on
PYTHONPATH), its output shown through a TrivialProducer.
"""
import argparse
import os
import sys

import paraview.simple as simple
from paraview import servermanager

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# boss_block (Data/boss_block.json): boss axis x = 35, y = 30, top z = 35,
# radius 12, base fillet 3 (torus), top chamfer 2 at 45 degrees (cone).
BOSS_X, BOSS_Y = 35.0, 30.0
CASES = [
    # name, DeformationType, ControlPoint, TargetValue, Translation, title
    ("boss_height", 0, [35, 30, 35], 20.0, None, "Distance: boss height 15 -> 20"),
    ("boss_radius", 1, [47, 30, 28], 14.0, None, "CylinderRadius: boss radius 12 -> 14"),
    ("fillet_radius", 2, [47.88, 30, 20.88], 4.0, None, "FilletRadius: fillet 3 -> 4"),
    ("chamfer_angle", 3, [46, 30, 34], 60.0, None, "ChamferAngle: 45 -> 60 deg"),
    ("chamfer_length", 4, [46, 30, 34], 3.0, None, "ChamferLength: 2 -> 3"),
    ("boss_position", 6, [47, 30, 28], None, [5.0, 10.0, 0.0], "Position: boss moved by (5, 10, 0)"),
]
SIZE = [800, 500]


def python_package_dir(plugin):
    """<build>/lib/python3.11/dist-packages from <build>/lib/femorph/FEMorph/FEMorph.so."""
    lib = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(plugin))))
    return os.path.join(lib, "python%d.%d" % sys.version_info[:2], "dist-packages")


def deform(ns, reader, case, plugin):
    """The deformed grid (a data object) and its field data, with the proxy
    FEMorphDeform if the plugin has it, else the VTK class."""
    name, typ, point, target, translation, _ = case
    make = ns.get("FEMorphDeform") or getattr(simple, "FEMorphDeform", None)
    make_segment = ns.get("FEMorphSegment") or getattr(simple, "FEMorphSegment", None)
    if make is not None and make_segment is not None:
        seg = make_segment(Input=reader)
        d = make(Input=seg)
        d.DeformationType = typ
        d.UseControlPoint = 1
        d.ControlPoint = point
        if target is not None:
            d.TargetValue = target
        if translation is not None:
            d.Translation = translation
        d.UpdatePipeline()
        return servermanager.Fetch(d)
    package = python_package_dir(plugin) if plugin else None
    if package and os.path.isdir(package) and package not in sys.path:
        sys.path.insert(0, package)
    import femorph  # noqa: E402  (the plugin's VTK Python package)
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(reader.FileName[0])
    s = femorph.vtkFEMorphSegment()
    s.SetInputConnection(r.GetOutputPort())
    d = femorph.vtkFEMorphDeform()
    d.SetInputConnection(s.GetOutputPort(0))
    d.SetDeformationType(typ)
    d.SetUseControlPoint(1)
    d.SetControlPoint(*point)
    if target is not None:
        d.SetTargetValue(target)
    if translation is not None:
        d.SetTranslation(*translation)
    d.Update()
    out = d.GetOutput()
    copy = out.NewInstance()
    copy.ShallowCopy(out)
    return copy


def producer_of(grid):
    tp = simple.TrivialProducer()
    tp.GetClientSideObject().SetOutput(grid)
    tp.UpdatePipeline()
    return tp


def show_section(source, view, cut_y, color_by=None, lut_range=None):
    clip = simple.Clip(Input=source)
    clip.ClipType = "Plane"
    clip.ClipType.Origin = [BOSS_X, cut_y, 0.0]
    clip.ClipType.Normal = [0.0, 1.0, 0.0]
    clip.Invert = 0  # keep y >= cut_y: the cut face looks at the camera (-y)
    if hasattr(clip, "Crinkleclip"):
        clip.Crinkleclip = 0
    display = simple.Show(clip, view)
    display.SetRepresentationType("Surface With Edges")
    display.EdgeColor = [0.2, 0.2, 0.2]
    display.LineWidth = 0.5
    if color_by:
        simple.ColorBy(display, ("POINTS", color_by, "Magnitude"))
        lut = simple.GetColorTransferFunction(color_by)
        lut.ApplyPreset("Cool to Warm", True)
        lut.AutomaticRescaleRangeMode = "Never"
        lut.RescaleTransferFunction(*lut_range)
        display.SetScalarBarVisibility(view, True)
        bar = simple.GetScalarBar(lut, view)
        bar.Title = "|Displacement| mm"
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
        bar.TitleFontSize = 10
        bar.LabelFontSize = 9
        bar.ScalarBarLength = 0.3
        bar.WindowLocation = "Any Location"
        bar.Position = [0.84, 0.05]
        bar.RangeLabelFormat = "%-#.1f"
    else:
        display.ColorArrayName = ["POINTS", ""]
        display.AmbientColor = display.DiffuseColor = [0.78, 0.80, 0.84]
    return clip


def new_view(title):
    view = simple.CreateView("RenderView")
    view.ViewSize = [SIZE[0] // 2, SIZE[1]]
    view.OrientationAxesVisibility = 0
    view.Background = [1.0, 1.0, 1.0]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    text = simple.Text(Text=title)
    t = simple.Show(text, view)
    t.Color = [0.0, 0.0, 0.0]
    t.FontSize = 11
    t.WindowLocation = "Upper Center"
    return view


def place_camera(view, center):
    # Looking along +y at the cut face, the boss and the block around it.
    view.CameraFocalPoint = center
    view.CameraPosition = [center[0] - 20.0, center[1] - 160.0, center[2] + 35.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = 26.0


def shrink_png(png, colors=96):
    """A palette PNG (the pictures stay well under 150 KB); kept as it is
    without PIL."""
    try:
        from PIL import Image
    except ImportError:
        return
    image = Image.open(png).convert("RGB")
    image.quantize(colors=colors, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(png, optimize=True)


def render_case(ns, reader, case, plugin, out_dir):
    name, _, _, _, translation, title = case
    deformed = deform(ns, reader, case, plugin)
    if deformed is None or deformed.GetNumberOfCells() == 0:
        raise RuntimeError("FEMorph Deform gave no output for %s" % name)
    disp = deformed.GetPointData().GetArray("Displacement")
    top = disp.GetRange(-1)[1] if disp is not None else 1.0
    after_y = BOSS_Y + (translation[1] if translation else 0.0)
    after_x = BOSS_X + (translation[0] if translation else 0.0)

    layout = simple.CreateLayout(name)
    before_view = new_view("before")
    after_view = new_view("after: " + title)
    simple.AssignViewToLayout(view=before_view, layout=layout, hint=0)
    layout.SplitHorizontal(0, 0.5)
    simple.AssignViewToLayout(view=after_view, layout=layout, hint=2)

    show_section(reader, before_view, BOSS_Y)
    producer = producer_of(deformed)
    show_section(producer, after_view, after_y, "Displacement", (0.0, max(top, 1e-6)))
    for view, cx in ((before_view, BOSS_X), (after_view, after_x)):
        simple.Render(view)
        place_camera(view, [0.5 * (cx + BOSS_X), 30.0, 20.0])
        simple.Render(view)
    layout.SetSize(*SIZE)
    png = os.path.join(out_dir, "deform_%s.png" % name)
    simple.SaveScreenshot(png, layout, ImageResolution=SIZE, CompressionLevel="9")
    shrink_png(png)
    for view in (before_view, after_view):
        simple.Delete(view)
    simple.RemoveLayout(layout)
    counts = deformed.GetFieldData().GetArray("DeformCounts")
    tets = deformed.GetNumberOfCells()
    print("%-15s %s: %d tets after, max |displacement| %.3f mm, %d bytes -> %s" % (
        name, title, tets, top, os.path.getsize(png), png))
    return png, counts


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", help="path of FEMorph.so (default: build/lib/femorph/FEMorph/FEMorph.so)")
    parser.add_argument("--part", default=os.path.join(REPO, "Data", "boss_block.vtu"))
    parser.add_argument("--output-dir", default=os.path.join(REPO, "docs", "images"))
    parser.add_argument("--only", action="append", choices=[c[0] for c in CASES])
    args = parser.parse_args()
    plugin = args.plugin or os.path.join(REPO, "build", "lib", "femorph", "FEMorph", "FEMorph.so")
    ns = {}
    if os.path.isfile(plugin):
        simple.LoadPlugin(plugin, ns=ns)
    else:
        sys.exit("no plugin at %s: pass --plugin" % plugin)
    os.makedirs(args.output_dir, exist_ok=True)
    reader = simple.XMLUnstructuredGridReader(FileName=[os.path.abspath(args.part)])
    reader.UpdatePipeline()
    failed = []
    for case in CASES:
        if args.only and case[0] not in args.only:
            continue
        try:
            render_case(ns, reader, case, plugin, args.output_dir)
        except Exception as e:  # one failing change should not hide the others
            print("%s: FAILED: %s" % (case[0], e))
            failed.append(case[0])
    if failed:
        sys.exit("failed: " + ", ".join(failed))


if __name__ == "__main__":
    main()
