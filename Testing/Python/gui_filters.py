"""Runs inside the ParaView GUI (`paraview --script=gui_filters.py`, started
by test_gui.py under Xvfb): applies every FEMorph filter from its proxy with
its default properties to a Data/ mesh, shows each output in the render view
and saves a screenshot per filter into FEMORPH_GUI_OUT; then opens Segment's Regions
table in a spreadsheet view and keeps its header's column order and the
screen (RegionsTable.xwd). The messages VTK sends to the output
window (what the GUI's Output Messages shows) are captured; the results go to
FEMORPH_GUI_OUT/result.json. Ends the application with os._exit (the GUI has
no way to quit from a startup script otherwise).
"""
import json
import os
import shutil
import threading
import time
import traceback

out = os.environ["FEMORPH_GUI_OUT"]
result = {"filters": {}, "messages": [], "failures": []}


def write_result():
    with open(os.path.join(out, "result.json"), "w") as f:
        json.dump(result, f, indent=1)


def give_up():
    """A step that never returns (a modal dialog, a hung render): end with
    what was done."""
    result["failures"].append("the GUI script did not finish within 240 s")
    write_result()
    os._exit(1)


watchdog = threading.Timer(240, give_up)
watchdog.daemon = True
watchdog.start()
try:
    from paraview.simple import (AssignViewToLayout, CreateView, GetActiveViewOrCreate,
                                 GetColorTransferFunction, GetLayout, Hide, LoadPlugin, OutputPort, Render,
                                 ResetCamera, SaveScreenshot, Show, XMLUnstructuredGridReader)
    from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

    # The GUI's output window routes every vtkErrorMacro / vtkWarningMacro to
    # Output Messages; a string window in its place keeps them for the check.
    messages = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(messages)

    LoadPlugin(os.environ["FEMORPH_PLUGIN"], ns=globals())
    data = os.environ["FEMORPH_DATA"]

    def read(name):
        return XMLUnstructuredGridReader(FileName=[os.path.join(data, name)])

    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [1024, 768]
    segment_input = read("boss_block.vtu")
    cases = [
        ("MeshQuality", lambda: FEMorphMeshQuality(Input=read("boss_block.vtu"))),  # noqa: F821
        ("Segment", lambda: FEMorphSegment(Input=segment_input)),  # noqa: F821
        ("Improve", lambda: FEMorphImprove(Input=read("beam.vtu"))),  # noqa: F821
        # Deform has no default control region (it says so): the beam's end face.
        ("Deform", lambda: FEMorphDeform(Input=FEMorphSegment(Input=read("beam.vtu")),  # noqa: F821
                                         UseControlPoint=1, ControlPoint=[50, 10, 5])),
        ("Adapt", lambda: FEMorphAdapt(Input=read(os.path.join("adapt", "block_in_box_small.vtu")))),  # noqa: F821
        ("HexToTet", lambda: FEMorphHexToTet(Input=read(os.path.join("hex", "hex_block.vtu")))),  # noqa: F821
        ("TetToHex", lambda: FEMorphTetToHex(Input=read("beam.vtu"))),  # noqa: F821
    ]
    shown = None
    for name, make in cases:
        before = len(messages.GetOutput())
        f = make()
        f.UpdatePipeline()
        info = f.GetDataInformation()
        if shown is not None:
            Hide(shown, view)
        # Segment: its Surface output by region, as a user looks at it.
        shown = OutputPort(f, 1) if name == "Segment" else f
        display = Show(shown, view)
        if name == "Segment":
            # No ColorBy: the colouring the Surface output comes up with.
            segment = f
            colour = display.ColorArrayName
            result["segment_colouring"] = {
                "array": [colour[0], colour[1]],
                "categorical": bool(GetColorTransferFunction("RegionId").InterpretValuesAsCategories)}
        view.CameraPosition = [1, -1.5, 1.2]
        view.CameraFocalPoint = [0, 0, 0]
        view.CameraViewUp = [0, 0, 1]
        ResetCamera(view)
        png = os.path.join(out, "%s.png" % name)
        SaveScreenshot(png, view, ImageResolution=[1024, 768])
        print("FEMorph GUI test:", name, "done", flush=True)
        text = messages.GetOutput()[before:]
        errors = [line for line in text.splitlines() if "ERROR" in line]
        result["filters"][name] = {"cells": info.GetNumberOfCells(), "errors": errors,
                                   "screenshot": png if os.path.exists(png) else None}
    # Segment's Regions table in a spreadsheet view, as a user opens it. The
    # plugin's GUI part orders the header's sections once the spreadsheet's
    # model has its columns, in the Qt event loop; changing the layout makes
    # ParaView process pending events (pqMultiViewWidget::reload).
    sheet = CreateView("SpreadSheetView")
    AssignViewToLayout(view=sheet)
    Show(OutputPort(segment, 2), sheet)
    Render(sheet)
    layout = GetLayout(sheet)
    key = "FEMorph.ColumnOrder"
    painted = 0
    for i in range(30):
        # Once ordered, a few more rounds to let the table paint.
        painted += sheet.SMProxy.HasAnnotation(key)
        if painted > 5:
            break
        time.sleep(0.2)
        layout.SetSplitFraction(0, 0.15 + 0.01 * (i % 2))
    order = sheet.SMProxy.GetAnnotation(key) if sheet.SMProxy.HasAnnotation(key) else ""
    result["regions_table"] = {"columns": order.split(",") if order else []}
    # The whole screen as the user sees it: SaveScreenshot captures only
    # render views; Xvfb keeps its screen in an XWD file (-fbdir).
    screen = os.path.join(os.environ.get("FEMORPH_GUI_FBDIR", ""), "Xvfb_screen0")
    if os.path.exists(screen):
        shutil.copy(screen, os.path.join(out, "RegionsTable.xwd"))
    result["messages"] = messages.GetOutput().splitlines()
except Exception:
    result["failures"].append(traceback.format_exc())

watchdog.cancel()
write_result()
os._exit(0)
