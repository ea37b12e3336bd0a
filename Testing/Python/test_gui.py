"""FEMorph in the ParaView GUI (issue 29): starts `paraview --script=gui_filters.py`
under Xvfb, which applies every filter from its proxy with its defaults on a
Data/ mesh and saves a screenshot of each into --out (kept by CI as
artifacts). Fails when a filter gives an empty output, when the GUI's output
window (Output Messages) received an error, or when a screenshot is
missing. Exit 77 (skipped) without `paraview` or `xvfb-run`.
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

FILTERS = ["MeshQuality", "Segment", "Improve", "Deform", "Adapt", "HexToTet", "TetToHex"]


def colours(png):
    """Distinct colours of a picture: a view without the mesh has a few."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader
    import numpy as np
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    pixels = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars())
    return len(np.unique(pixels.reshape(len(pixels), -1), axis=0))


def xwd_to_png(xwd, png):
    """An X window dump (Xvfb's -fbdir screen, 32 bits per pixel) as a PNG."""
    import struct
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter
    data = open(xwd, "rb").read()
    h = struct.unpack(">25I", data[:100])
    header_size, width, height, byte_order, bpp, bpl, ncolors = (
        h[0], h[4], h[5], h[7], h[11], h[12], h[19])
    if bpp != 32:
        raise ValueError("%s: %d bits per pixel" % (xwd, bpp))
    px = np.frombuffer(data, dtype=np.uint8, count=bpl * height, offset=header_size + 12 * ncolors)
    px = px.reshape(height, bpl)[:, :4 * width].reshape(height, width, 4)
    rgb = px[:, :, [2, 1, 0]] if byte_order == 0 else px[:, :, [1, 2, 3]]
    img = vtkImageData()
    img.SetDimensions(width, height, 1)
    img.GetPointData().SetScalars(numpy_to_vtk(np.ascontiguousarray(rgb[::-1]).reshape(-1, 3), deep=1))
    w = vtkPNGWriter()
    w.SetFileName(png)
    w.SetInputData(img)
    w.Write()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--data", required=True, help="FEMorph's Data folder")
    parser.add_argument("--out", required=True, help="folder of the screenshots")
    parser.add_argument("--paraview", default="paraview")
    parser.add_argument("--xvfb-run", default="xvfb-run")
    args = parser.parse_args()
    paraview, xvfb = shutil.which(args.paraview), shutil.which(args.xvfb_run)
    if not paraview or not xvfb:
        print("SKIP: %s not found" % (args.paraview if not paraview else args.xvfb_run))
        return 77
    os.makedirs(args.out, exist_ok=True)
    for old in glob.glob(os.path.join(args.out, "*")):
        os.remove(old)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_"))}
    fbdir = tempfile.mkdtemp(prefix="femorph_gui_screen_")
    env.update(FEMORPH_PLUGIN=args.plugin, FEMORPH_DATA=args.data, FEMORPH_GUI_OUT=args.out,
               FEMORPH_GUI_FBDIR=fbdir)
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "gui_filters.py")
    # --dr: no user settings (a user's saved RegionId colour map would hide
    # the plugin's) and no welcome dialog (modal, it would stop the script).
    cmd = [xvfb, "-a", "-s", "-noreset -screen 0 1280x1024x24 -fbdir " + fbdir, paraview, "--dr",
           "--script=" + script]
    try:
        proc = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, timeout=400)
    finally:
        shutil.rmtree(fbdir, ignore_errors=True)
    result_path = os.path.join(args.out, "result.json")
    if not os.path.exists(result_path):
        print(proc.stdout)
        print("FAIL: the GUI script wrote no result (paraview returned %d)" % proc.returncode)
        return 1
    result = json.load(open(result_path))
    failures = list(result["failures"])
    for name in FILTERS:
        r = result["filters"].get(name)
        if r is None:
            failures.append("%s was not applied" % name)
            continue
        print("%s: %d cells, screenshot %s" % (name, r["cells"], r["screenshot"]))
        if r["cells"] == 0:
            failures.append("%s: empty output" % name)
        if r["errors"]:
            failures.append("%s: Output Messages has errors: %s" % (name, r["errors"]))
        if not r["screenshot"] or colours(r["screenshot"]) < 8:
            failures.append("%s: no screenshot, or one without the mesh" % name)
    # Segment's Surface comes up coloured by RegionId with a categorical map.
    colouring = result.get("segment_colouring", {})
    print("Segment Surface colouring: %s" % colouring)
    if colouring.get("array") != ["CELLS", "RegionId"]:
        failures.append("Segment's Surface is not coloured by RegionId: %s" % colouring)
    if not colouring.get("categorical"):
        failures.append("RegionId's colour map does not interpret values as categories")
    # The Regions table reads like a CAD feature list: id, type, dimensions.
    table = result.get("regions_table", {})
    # Header labels left to right, the spreadsheet's own "Row ID" first.
    columns = [c for c in table.get("columns", []) if c != "Row ID"]
    print("Regions table columns in the spreadsheet: %s" % columns)
    if columns[:3] != ["RegionId", "TypeName", "Radius"]:
        failures.append("Regions table columns not in the table's order: %s" % columns)
    elif "Apex" in columns and columns.index("Apex") < columns.index("Axis"):
        failures.append("Regions table: Apex before Axis: %s" % columns)
    xwd = os.path.join(args.out, "RegionsTable.xwd")
    png = os.path.join(args.out, "RegionsTable.png")
    if os.path.exists(xwd):
        xwd_to_png(xwd, png)
        os.remove(xwd)
    if not os.path.exists(png) or colours(png) < 8:
        failures.append("no screenshot of the Regions table")
    errors = [m for m in result["messages"] if "ERROR" in m]
    if errors:
        failures.append("errors in Output Messages: %s" % errors)
    for f in failures:
        print("FAIL:", f)
    print("screenshots in %s" % args.out)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
