"""The ways a user loads the plugin, each checked by running the filter once.

  pvbatch|pvpython test_load_plugin.py --plugin path/FEMorph.so   LoadPlugin(path, ns=globals())
  PV_PLUGIN_PATH=dir pvbatch|pvpython test_load_plugin.py         autoload from the environment
  PV_PLUGIN_CONFIG_FILE=femorph.plugins.xml pvpython test_load_plugin.py   the same, by the plugins file

Also checks what the GUI shows: the proxy's label, menu category and the
StretchThreshold default, and that the XML documentation names the arrays.
"""
import argparse
import os

import paraview.simple as simple
from paraview import servermanager

EXPECTED_ARRAYS = ["Stretch", "ScaledJacobian", "MinDihedralAngle", "MaxDihedralAngle", "Inverted",
                   "Invalid"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", help="load this FEMorph.so with LoadPlugin; "
                        "without it the plugin must come from PV_PLUGIN_PATH")
    args = parser.parse_args()

    ns = globals()
    if args.plugin:
        simple.LoadPlugin(args.plugin, ns=ns)
    else:
        assert os.environ.get("PV_PLUGIN_PATH") or os.environ.get("PV_PLUGIN_CONFIG_FILE"), \
            "set PV_PLUGIN_PATH or PV_PLUGIN_CONFIG_FILE, or pass --plugin"
        # Autoloaded plugins are registered before the script runs; paraview.simple
        # creates its functions for them on import.
    if "FEMorphMeshQuality" in ns:
        make_filter = ns["FEMorphMeshQuality"]
    else:
        make_filter = getattr(simple, "FEMorphMeshQuality", None)
    assert make_filter is not None, "FEMorphMeshQuality is not defined: the plugin did not load"

    # A small tet mesh from ParaView's own sources.
    tets = simple.Tetrahedralize(Input=simple.Wavelet(WholeExtent=[0, 4, 0, 4, 0, 4]))
    quality = make_filter(Input=tets)
    assert quality.StretchThreshold == 0.05, quality.StretchThreshold
    quality.UpdatePipeline()
    out = servermanager.Fetch(quality)
    for name in EXPECTED_ARRAYS:
        assert out.GetCellData().GetArray(name) is not None, name
    assert out.GetFieldData().GetArray("TetraCount").GetTuple1(0) == out.GetNumberOfCells()

    # What the GUI reads from the XML.
    proxy = quality.SMProxy
    assert proxy.GetXMLLabel() == "FEMorph Mesh Quality", proxy.GetXMLLabel()
    hints = proxy.GetHints()
    menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
    assert menu is not None and menu.GetAttribute("category") == "FEMorph"
    doc = proxy.GetDocumentation().GetDescription()
    for name in EXPECTED_ARRAYS + ["StretchMin", "InvertedCount", "InvalidCount", "BelowThresholdCount"]:
        assert name in doc, "the filter's help does not mention %s" % name

    # Issue 29: counts and seeds get plain entries, not sliders. ParaView's
    # panel (pqIntVectorPropertyWidget) draws a slider for an IntRangeDomain
    # with both a minimum and a maximum, a line edit otherwise.
    segment = (ns.get("FEMorphSegment") or getattr(simple, "FEMorphSegment"))(Input=tets)
    for name in ("RansacIterations", "RandomSeed"):
        domain = segment.SMProxy.GetProperty(name).GetDomain("range")
        assert domain is not None, name
        assert domain.GetMinimumExists(0) and not domain.GetMaximumExists(0), \
            "%s would get a slider" % name
    print("OK: plugin loaded through %s" % ("LoadPlugin" if args.plugin else "PV_PLUGIN_PATH"))


if __name__ == "__main__":
    main()
