#!/usr/bin/python3
"""ctest FEA.Harness: the CalculiX harness (calculix.py) on fresh Gmsh meshes
of the FEA parts against the analytic values (Testing/FEA/README.md).

    /usr/bin/python3 Testing/FEA/test_fea.py --work-dir build/fea

First a patch test on Data/fea/cantilever.vtu (uniform tension, statically
determinate supports: the end face's ux must be sigma L / E at every node,
which checks the C3D10 node order and the consistent face loads). Then it
meshes cantilever, cantilever_width20, plate_hole and plate_hole_r10 with
Data/generate_fea_parts.py into --work-dir, runs the analyses and asserts:
  - tip deflection within 1 % of F L^3 / (3 E I) (widths 10 and 20);
  - plate: the through-thickness mean of sigma_xx at the hole within 1 % of
    Heywood's peak, the peak nodal sigma_xx (mid-plane, a 3D effect above
    the plane-stress value) within 1.5 %;
  - the fresh cantilever and plate_hole meshes are the ones in Data/fea/
    (same counts), and `compare` of Data/fea/cantilever.vtu against the fresh
    mesh gives a zero difference and passes.
Exit 77 (skipped) when ccx, gmsh or vtkmodules is missing.
"""

import argparse
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SKIP = 77

CANTILEVER_BOUND = 0.01
PLATE_MEAN_BOUND = 0.01
PLATE_PEAK_BOUND = 0.015


def patch_test(calculix):
    """Uniform tension 100 MPa on the cantilever mesh held like the plate:
    end-face ux at every node and its exact value."""
    import tempfile
    import numpy as np
    points, tets = calculix.read_vtu(os.path.join(calculix.FEA_DATA, "cantilever.vtu"))
    nodes, elements, tris6 = calculix.to_c3d10(points, tets)
    lo, hi = points.min(axis=0), points.max(axis=0)
    tol = 1e-6 * np.linalg.norm(hi - lo)
    held = np.flatnonzero(np.abs(nodes[:, 0] - lo[0]) < tol)
    c0 = np.flatnonzero(np.linalg.norm(nodes - lo, axis=1) < tol)
    c1 = np.flatnonzero(np.linalg.norm(nodes - [lo[0], hi[1], lo[2]], axis=1) < tol)
    ids, w = calculix.tri6_weights(nodes, calculix.triangles_on_plane(nodes, tris6, 0, hi[0], tol))
    with tempfile.TemporaryDirectory(prefix="femorph_patch_") as work:
        calculix.write_inp(os.path.join(work, "job.inp"), nodes, elements,
                           fixed=[(held, 1, 1), (c0, 2, 3), (c1, 3, 3)],
                           loads=[(ids, 1, 100.0 * w)], print_sets={"NEND": ids})
        calculix.run_ccx(work)
        u = calculix.parse_dat_displacements(os.path.join(work, "job.dat"))["NEND"]
    ux = np.array([u[i + 1][0] for i in ids])
    return ux, 100.0 * (hi[0] - lo[0]) / calculix.E_MODULUS


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work-dir", required=True)
    args = parser.parse_args()
    try:
        import numpy  # noqa: F401
        import gmsh  # noqa: F401
        sys.path.append("/usr/lib/python3/dist-packages")
        import vtkmodules  # noqa: F401
    except ImportError as e:
        print(f"SKIP: {e}")
        return SKIP
    sys.path.insert(0, HERE)
    import calculix
    if not calculix.ccx_available():
        print("SKIP: ccx (CalculiX) not found")
        return SKIP
    sys.path.insert(0, calculix.DATA)
    import generate_fea_parts

    os.makedirs(args.work_dir, exist_ok=True)
    failures = []

    def check(ok, message):
        print(("ok    " if ok else "FAIL  ") + message, flush=True)
        if not ok:
            failures.append(message)

    start = time.perf_counter()
    ux, exact = patch_test(calculix)
    check(abs(ux.min() / exact - 1) < 1e-5 and abs(ux.max() / exact - 1) < 1e-5,
          f"patch test: end-face ux {ux.min():.8f} .. {ux.max():.8f} mm, sigma L / E = {exact:.8f} mm")
    for case in ("cantilever_width10", "cantilever_width20", "plate_hole_r5", "plate_hole_r10"):
        kind, part, dims = calculix.CASES[case]
        info = generate_fea_parts.generate_fea(part, args.work_dir)
        vtu = os.path.join(args.work_dir, part + ".vtu")
        ref = calculix.analytic(case)
        if kind == "cantilever":
            r = calculix.cantilever(vtu)
            calculix.print_cantilever(r)
            err = r["tip_deflection"] / ref["value"] - 1.0
            check(abs(err) <= CANTILEVER_BOUND,
                  f"{case}: tip deflection {r['tip_deflection']:.6f} mm vs F L^3/(3EI) "
                  f"{ref['value']:.6f} mm: {100 * err:+.3f} % (bound {100 * CANTILEVER_BOUND:g} %)")
        else:
            r = calculix.plate_tension(vtu, dims["radius"])
            calculix.print_plate(r)
            err_mean = r["thickness_mean_sxx"] / ref["value"] - 1.0
            err_peak = r["peak_sxx"] / ref["value"] - 1.0
            check(abs(err_mean) <= PLATE_MEAN_BOUND,
                  f"{case}: through-thickness mean sigma_xx {r['thickness_mean_sxx']:.3f} MPa vs "
                  f"Heywood {ref['value']:.3f} MPa: {100 * err_mean:+.3f} % "
                  f"(bound {100 * PLATE_MEAN_BOUND:g} %)")
            check(abs(err_peak) <= PLATE_PEAK_BOUND,
                  f"{case}: peak sigma_xx {r['peak_sxx']:.3f} MPa vs Heywood {ref['value']:.3f} MPa: "
                  f"{100 * err_peak:+.3f} % (bound {100 * PLATE_PEAK_BOUND:g} %)")
        kept = os.path.join(calculix.FEA_DATA, part + ".json")
        if os.path.isfile(kept):
            with open(kept) as f:
                counts = json.load(f)["counts"]
            check(counts == info["counts"],
                  f"{part}: fresh mesh has the counts of Data/fea/{part}.json")
        print(flush=True)

    # compare(): the kept cantilever against a fresh one (identical meshes).
    r = calculix.compare(os.path.join(calculix.FEA_DATA, "cantilever.vtu"),
                         os.path.join(args.work_dir, "cantilever.vtu"), "cantilever_width10")
    check(r["ok"] and abs(r["difference"]) < 1e-9,
          f"compare cantilever_width10, Data/fea/cantilever.vtu vs fresh: difference "
          f"{100 * r['difference']:+.2e} %, errors {100 * r['deformed']['error']:+.3f} % / "
          f"{100 * r['fresh']['error']:+.3f} %")
    # compare() on meshes whose nodes were moved to the new dimension.
    import mock_deform
    for case, src in (("cantilever_width20", "cantilever.vtu"), ("plate_hole_r10", "plate_hole.vtu")):
        moved = os.path.join(args.work_dir, "mock_" + case + ".vtu")
        assert mock_deform.main([case, os.path.join(calculix.FEA_DATA, src), moved]) == 0
        r = calculix.compare(moved, os.path.join(args.work_dir, calculix.CASES[case][1] + ".vtu"), case)
        check(r["ok"], f"compare {case}, mock_deform of Data/fea/{src} vs fresh: figures "
              f"{r['deformed']['value']:.6g} / {r['fresh']['value']:.6g}, difference "
              f"{100 * r['difference']:+.3f} %, analytic errors {100 * r['deformed']['error']:+.3f} % / "
              f"{100 * r['fresh']['error']:+.3f} %")
    print(f"{time.perf_counter() - start:.0f} s in all")
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
