#!/usr/bin/python3
"""Self-test of deform_check.py (the checker of FEMorph Deform's output)
before any deformed mesh exists, on Data/ and Data/variants/:

(a) each base part against its own CAD (<part>__base) passes every check,
    its points all unchanged; with one tet flipped, validity counts one
    inverted tet; with one point of a fixed face moved by one ulp,
    fixed_unchanged fails;
(b) a fresh Gmsh mesh of each variant (Data/generate_parts.py's builder with
    the variant's changed dimensions, the part's own mesh options, in a
    temporary folder) is valid and on the variant's surfaces; its minimum
    stretch, CAD-to-mesh distance and volume error are reported against the
    thresholds (flagged when above, not failed: Gmsh's mesh of a larger
    radius has a larger chord and volume error than the base mesh);
(c) the base mesh against each changed variant fails the surface check, by
    as much as the CAD moved: per label, the base mesh's largest distance to
    the variant's surface is between 0.8 and 1 times that of the base CAD
    sample's vertices (0 for the faces that did not move).

    /usr/bin/python3 Testing/Python/test_deform_check.py --data Data [--only boss_block]

Exit 0 passed, 1 failed, 77 skipped (no gmsh module).
"""

import argparse
import glob
import importlib.util
import json
import os
import sys
import tempfile
import time

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
import deform_check as dc  # noqa: E402


def load_generator(data_dir):
    spec = importlib.util.spec_from_file_location(
        "generate_parts", os.path.join(data_dir, "generate_parts.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", required=True, help="the Data folder")
    parser.add_argument("--only", action="append", help="only this part (repeatable)")
    parser.add_argument("--work", default=None, help="folder for the fresh meshes (default: temp)")
    args = parser.parse_args()
    try:
        import gmsh  # noqa: F401
    except ImportError:
        print("SKIPPED: no gmsh module for this Python (Debian: python3-gmsh)")
        return 77
    gen = load_generator(args.data)
    import gmsh

    variants_dir = os.path.join(args.data, "variants")
    variants = sorted(p for p in glob.glob(os.path.join(variants_dir, "*__*.json"))
                      if not p.endswith("__base.json"))
    if not variants:
        print(f"FAILED: no variants in {variants_dir}")
        return 1
    failures = []

    def expect(condition, message):
        if not condition:
            failures.append(message)
            print("  FAILED: " + message)

    start = time.perf_counter()
    work = args.work or tempfile.mkdtemp(prefix="deform_check_")
    os.makedirs(work, exist_ok=True)
    gmsh.initialize(["test_deform_check"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    done_base = set()
    print(f"{'variant':<40} {'fresh: surf':>11} {'s min':>6} {'CAD-mesh':>9} {'limit':>7} "
          f"{'|dV|':>9} {'limit':>9}  {'base mesh: max dist':>19} {'CAD moved':>9}")
    try:
        for path in variants:
            info = dc.load_json(path)
            part = info["base_part"]
            if args.only and part not in args.only:
                continue
            base_vtu = os.path.join(args.data, part + ".vtu")
            base_json = dc.load_json(os.path.join(args.data, part + ".json"))
            stem = path[:-5]
            base_stem = os.path.join(variants_dir, part + "__base")

            # (a) the base part against its own CAD.
            if part not in done_base:
                done_base.add(part)
                labels = [f["label"] for f in base_json["faces"]]
                ok, rows, _ = dc.check(base_vtu, base_stem, base_vtu, labels)
                print(f"(a) {part} against {part}__base:")
                dc.print_rows(rows)
                expect(ok, f"(a) {part} fails against its own CAD")
                # The checks see one flipped tet and one fixed point moved by
                # one ulp.
                mesh = dc.read_mesh(base_vtu)
                mesh.tets[0] = mesh.tets[0][[1, 0, 2, 3]]
                expect(dc.validity(mesh)["inverted"] == 1, f"(a) {part}: flipped tet not seen")
                mesh = dc.read_mesh(base_vtu)
                ids = sorted(v for v, ls in dc.labels_of_points(mesh, base_json).items()
                             if ls == {labels[0]})
                mesh.points[ids[0], 0] = np.nextafter(mesh.points[ids[0], 0], np.inf)
                fx = dc.fixed_unchanged(base_vtu, mesh, labels[:1], base_json)
                expect(fx["changed"] == 1 and not fx["ok"],
                       f"(a) {part}: a fixed point moved by one ulp not seen")

            # (b) a fresh mesh of the variant.
            name = os.path.basename(stem)
            gen.generate(part, work, out_name=name, overrides=info["changed_dimensions"])
            fresh = os.path.join(work, name + ".vtu")
            ok, rows, det = dc.check(base_vtu, stem, fresh)
            by_name = {r[0]: r for r in rows}
            # Exact checks only: Gmsh's own mesh of a variant need not reach
            # the stretch, chord and volume limits made from the base mesh.
            strict = [r for r in rows
                      if not r[0].startswith(("CAD to mesh", "|V - V_cad|", "stretch"))]
            for r in strict:
                expect(r[3], f"(b) fresh mesh of {name}: {r[0]} = {r[1]} (limit {r[2]})")
            c2m = det["cad_to_mesh"]["max"]
            c2m_limit = det["cad_to_mesh_limit"]
            dv = abs(det["volume"] - det["cad_volume"])
            dv_limit = det["base_volume_error"] + dc.VOLUME_REL_SLACK * det["cad_volume"]

            # (c) the base mesh against the changed variant.
            base_mesh = dc.read_mesh(base_vtu)
            surf = dc.on_surfaces(base_mesh, info, base_json)
            moved = dc.cad_sample_deviation(base_stem + ".vtp",
                                            dc.load_json(base_stem + ".json"), info)
            expect(not surf["ok"], f"(c) the base mesh passes the surface check of {name}")
            for label, d_cad in moved.items():
                d_mesh = surf["per_label"].get(label, 0.0)
                if d_cad <= surf["tol"]:
                    expect(d_mesh <= surf["tol"],
                           f"(c) {name}: '{label}' did not move but is {d_mesh:.3g} off")
                else:
                    # The sample's vertices are denser than the mesh's but
                    # need not hit the face's farthest point exactly.
                    expect(0.8 * d_cad <= d_mesh <= 1.01 * d_cad + surf["tol"],
                           f"(c) {name}: '{label}' base mesh {d_mesh:.4g} off, CAD moved "
                           f"{d_cad:.4g}")
            smin = det["validity"]["stretch_min"]
            print(f"{name:<40} {det['on_surfaces']['max']:>11.1e} {smin:>6.3f} "
                  f"{c2m:>9.4f} {c2m_limit:>7.4f} "
                  f"{dv:>9.3f} {dv_limit:>9.3f}  {surf['max']:>19.4f} {max(moved.values()):>9.4f}"
                  f"{'' if c2m <= c2m_limit else '  (CAD-mesh above limit)'}"
                  f"{'' if dv <= dv_limit else '  (volume above limit)'}"
                  f"{'' if smin >= dc.MIN_STRETCH else '  (stretch below limit)'}")
            os.remove(fresh)
            os.remove(os.path.join(work, name + ".json"))
    finally:
        gmsh.finalize()
    print(f"{time.perf_counter() - start:.1f} s")
    if failures:
        print(f"FAILED: {len(failures)} check(s)")
        return 1
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
