#!/usr/bin/python3
"""A stand-in for FEMorph Deform, to exercise `calculix.py compare` until the
filter exists: it moves the nodes of a Data/fea part to the changed dimension
(no remeshing, no quality repair) and writes the .vtu with the input's arrays.

    mock_deform.py cantilever_width20 Data/fea/cantilever.vtu out.vtu
    mock_deform.py plate_hole_r10 Data/fea/plate_hole.vtu out.vtu

cantilever_width20: y scaled by 2 (the face y = 0 kept), an affine map, so
every tet is stretched sideways by 2.
plate_hole_r10: radial map about the hole's axis, rho -> rho + 5 w(rho),
w = 1 on the hole falling linearly to 0 at rho = 40 (monotone: d rho'/d rho
= 6/7); the hole's nodes land on radius 10, the nodes from rho = 40 out do
not move. Element sizes near the hole grow with the radius (twice the
circumferential size on the hole).
"""

import sys

import numpy as np

sys.path.append("/usr/lib/python3/dist-packages")
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402

HOLE_CENTER = (100.0, 50.0)
BLEND_RADIUS = 40.0


def deform(case, points):
    x = points.copy()
    if case == "cantilever_width20":
        x[:, 1] *= 2.0
        return x
    if case == "plate_hole_r10":
        r0, r1 = 5.0, 10.0
        v = x[:, :2] - np.asarray(HOLE_CENTER)
        rho = np.linalg.norm(v, axis=1)
        w = np.clip(1.0 - (rho - r0) / (BLEND_RADIUS - r0), 0.0, 1.0)
        scale = (rho + (r1 - r0) * w) / rho
        x[:, :2] = np.asarray(HOLE_CENTER) + v * scale[:, None]
        # Nodes on the hole exactly on the new radius (rounding).
        on = np.abs(rho - r0) < 1e-9 * r0
        x[on, :2] = np.asarray(HOLE_CENTER) + v[on] * (r1 / rho[on])[:, None]
        return x
    raise ValueError(f"unknown case {case}")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 3:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    case, src, dst = argv
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(src)
    reader.Update()
    grid = reader.GetOutput()
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    grid.GetPoints().SetData(numpy_to_vtk(np.ascontiguousarray(deform(case, points)), deep=1))
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(dst)
    writer.SetInputData(grid)
    writer.SetCompressorTypeToZLib()
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    if writer.Write() != 1:
        print(f"could not write {dst}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
