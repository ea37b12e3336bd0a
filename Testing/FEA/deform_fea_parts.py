"""The FEA parts changed by FEMorph Deform, for the CalculiX comparison
(thesis 2.7.4): the cantilever's width 10 -> 20 mm (Distance on its face
y = 10, the face y = 0 kept) and the plate's hole radius 5 -> 10 mm
(CylinderRadius). Writes <out>/cantilever_width20_deformed.vtu and
<out>/plate_hole_r10_deformed.vtu.

  pvbatch deform_fea_parts.py --plugin FEMorph.so --data Data/fea --out DIR
"""
import argparse
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

CHANGES = [
    ("cantilever", "cantilever_width20_deformed.vtu", dict(DeformationType=0, ControlPoint=[50, 10, 5],
                                                            TargetValue=20.0)),
    ("plate_hole", "plate_hole_r10_deformed.vtu", dict(DeformationType=1, ControlPoint=[105, 50, 1],
                                                        TargetValue=10.0)),
]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--data", required=True)
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    LoadPlugin(args.plugin, ns=globals())
    os.makedirs(args.out, exist_ok=True)
    for part, name, props in CHANGES:
        reader = XMLUnstructuredGridReader(FileName=[os.path.join(args.data, part + ".vtu")])
        deform = FEMorphDeform(Input=FEMorphSegment(Input=reader), UseControlPoint=1, **props)
        deform.UpdatePipeline()
        data = servermanager.Fetch(deform)
        if data.GetNumberOfCells() == 0:
            print(f"FEMorph Deform failed on {part}")
            return 1
        fd = data.GetFieldData()
        print(f"{part}: {fd.GetArray('CurrentDimension').GetValue(0)} -> "
              f"{fd.GetArray('TargetDimension').GetValue(0)}, {data.GetNumberOfCells()} tets")
        writer = vtkXMLUnstructuredGridWriter()
        writer.SetFileName(os.path.join(args.out, name))
        writer.SetInputData(data)
        if not writer.Write():
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
