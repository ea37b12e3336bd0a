"""FEMorph Deform on a real part made by others (the gearbox shaft of
../shared/realparts, meshed from its STEP file by Data/generate_parts.py
--step): a bearing journal's length (Distance on its end face, 20 -> 25 mm)
and its radius (CylinderRadius, 10 -> 12 mm).

  pvbatch test_deform_realpart.py --plugin FEMorph.so --data DIR/welle_gearbox_shaft.vtu

Checks, with numpy and VTK only: no inverted or non-conforming tet; the
changed faces where the CAD of the changed part puts them (the end face at
x = 85; the journal's nodes at radius 12 from its axis, 1e-6 of the part);
every other CAD face's nodes bit for bit where they were; the volume changed
by the analytic amount (pi r^2 dL, pi (r'^2 - r^2) L) within 1.5% (the
mesh's polygonal section holds about 0.99 of the circle's area); minimum
stretch >= 0.2 and >= 0.8 x the input's. Exits 77 when the mesh is missing.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

import deform_check  # noqa: E402


def faces_of(mesh, tags):
    """Node ids of the boundary faces with CADFace in `tags`."""
    slots, tris, _ = mesh.boundary()
    t = mesh.cad_face.reshape(-1)[slots]
    return np.unique(tris[np.isin(t, list(tags))])


def run(args, props, changed_tags, check_changed, volume_change):
    reader = XMLUnstructuredGridReader(FileName=[args.data])
    seg = FEMorphSegment(Input=reader)
    d = FEMorphDeform(Input=seg)
    for k, v in props.items():
        setattr(d, k, v)
    d.UpdatePipeline()
    out = deform_check.read_mesh(servermanager.Fetch(d))
    base = deform_check.read_mesh(servermanager.Fetch(reader))
    failures = []
    if len(out.tets) == 0:
        return ["empty output"]
    val = deform_check.validity(out)
    vb = deform_check.validity(base)
    if val["inverted"] or val["faces_in_more_than_two_tets"] or val["boundary_edges_not_in_two_triangles"]:
        failures.append(f"invalid mesh {val}")
    if not (val["stretch_min"] >= 0.2 and val["stretch_min"] >= 0.8 * vb["stretch_min"]):
        failures.append(f"minimum stretch {val['stretch_min']:.3f} (input {vb['stretch_min']:.3f})")
    size = float(np.linalg.norm(base.points.max(0) - base.points.min(0)))
    # The changed faces, in the output (its own CADFace copies: faces of new
    # tets are checked through all their nodes on the changed surfaces).
    worst = check_changed(out.points[faces_of(out, changed_tags)])
    if not worst <= 1e-6 * size:
        failures.append(f"changed faces off their new surface by {worst:.3e}")
    # Every other face's nodes where they were, bit for bit.
    all_tags = set(int(t) for t in np.unique(base.cad_face) if t >= 0)
    near = set()
    for tag in changed_tags:
        near |= set(args.neighbors.get(tag, []))
    fixed_tags = all_tags - set(changed_tags) - near
    fixed = faces_of(base, fixed_tags)
    moving = set(faces_of(base, set(changed_tags) | near).tolist())
    fixed = np.array([v for v in fixed if v not in moving], dtype=np.int64)
    have = {row.tobytes() for row in np.ascontiguousarray(out.points)}
    moved = sum(1 for row in base.points[fixed] if np.ascontiguousarray(row).tobytes() not in have)
    if moved:
        failures.append(f"{moved} of {len(fixed)} nodes of the fixed faces moved")
    dv = deform_check.volume(out) - deform_check.volume(base)
    if abs(dv - volume_change) > 0.015 * abs(volume_change):
        failures.append(f"volume change {dv:.2f}, analytic {volume_change:.2f}")
    print(f"{props}: tets {len(base.tets)} -> {len(out.tets)}, stretch {vb['stretch_min']:.3f} -> "
          f"{val['stretch_min']:.3f}, changed faces off by {worst:.2e}, fixed nodes {len(fixed)} "
          f"({moved} moved), volume change {dv:.2f} (analytic {volume_change:.2f})")
    return failures


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--data", required=True)
    args = parser.parse_args()
    if not os.path.exists(args.data):
        print("missing", args.data)
        return 77
    LoadPlugin(args.plugin, ns=globals())
    info = json.load(open(os.path.splitext(args.data)[0] + ".json"))
    faces = {f["tag"]: f for f in info["faces"]}

    def find(kind, **near):
        for tag, f in faces.items():
            if f["primitive"] != kind:
                continue
            if kind == "plane" and abs(f["point"][0] - near["x"]) < 1e-6 and abs(abs(f["normal"][0]) - 1) < 1e-9:
                return tag
            if kind == "cylinder" and abs(f["radius"] - near["r"]) < 1e-3 and f["axis_point"][0] > near["x"]:
                return tag
        raise SystemExit(f"no {kind} {near} in {args.data}")

    end = find("plane", x=80.0)
    shoulder = find("plane", x=60.0)
    journal = find("cylinder", r=10.0, x=60.0)
    # The faces next to the changed ones move within their surfaces.
    args.neighbors = {end: [journal], journal: [end, shoulder]}
    failures = []
    failures += run(args, dict(DeformationType=0, UseControlPoint=1, ControlPoint=[80, 0, 5], TargetValue=25.0),
                    [end], lambda x: float(np.max(np.abs(x[:, 0] - 85.0))) if len(x) else 0.0,
                    math.pi * 10 ** 2 * 5)
    failures += run(args, dict(DeformationType=1, UseControlPoint=1, ControlPoint=[70, 10, 0], TargetValue=12.0),
                    [journal], lambda x: float(np.max(np.abs(np.hypot(x[:, 1], x[:, 2]) - 12.0))) if len(x) else 0.0,
                    math.pi * (12 ** 2 - 10 ** 2) * 20)
    for f in failures:
        print("FAILED:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
