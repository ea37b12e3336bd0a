#!/usr/bin/python3
"""Peer of the Adapt benchmark: Gmsh re-meshing the whole domain at every
step, the way a user without FEMorph Adapt gets the mesh of a moved object.

    /usr/bin/python3 Testing/Benchmarks/adapt_gmsh_peer.py            # thesis 3.7.2, 10 steps
    /usr/bin/python3 Testing/Benchmarks/adapt_gmsh_peer.py --cells 6 6 8 --object 2 2 1 \
        --steps 2 --stride 1 [--out-dir /tmp/peer]

The case of thesis 3.7.2: a box of --cells cubes of edge --edge (default
20 x 20 x 50 of edge 1) and a block of --object cubes (3 x 5 x 1) that moves
0.1 edge along z and turns 1 degree about the x axis through its centre per
step: x_n = c + n t + R(x, n deg) (x_0 - c), as Data/generate_adapt_cases.py's
motion_3_7_2 and FEMorph's RigidMotion. The block starts centred in x and y;
along z so that the path of --path-steps steps (the thesis's 360) is
centred when the block then stays in the box all along it (the 20 x 20 x 50
case: lowest cube (8, 7, 6), as Data/README.md's command for this case),
else centred as in Data/generate_adapt_cases.py (the Data/adapt cases);
--object-at overrides.

At step 0 and at the --steps sampled steps n = stride, 2 stride, ... (default
10 steps every 36th of 360), it builds the exact geometry with OpenCASCADE
(the box, the block turned and moved, fragmented so that both volumes share
the block's faces: a conformal mesh) and meshes it from scratch with a
uniform size (Frontal-Delaunay surfaces, Delaunay volume, Gmsh's optimizer,
--threads threads, one by default). The size is the edge times a factor
found at step 0 so that the tet count is about the 12 tets per cube of the
jittered grid (two meshings, power-law fit tets ~ size^-3), unless --size.

Prints one row per step: tets, vertices, the seconds (geometry, meshing,
total), the minimum and mean stretch (thesis Eq. 1.1, as adapt_check.stretch)
and the fraction of the vertices found (within 1e-9 of the box diagonal) at
the same position in the previous row's mesh, all of them and the inner
ones (not on the box); then the median seconds per step over the sampled
steps. --out-dir writes each step as step_NNNN.vtu (MaterialId 1 on the
block, 0 in space), for Testing/Python/adapt_check.py --object-remeshed.

--case cylinder-half-tube: thesis 3.7.3's contact case, as
Testing/Cxx/test_adapt_meshes.h's make_cylinder_half_tube: a cylinder of
radius --r and length --Lc, its front cap at z = -gap + n translation at
step n, and a half tube (y <= 0, radii r to --R, z in [0, Lt]) in the box
|x|, |y| <= R + margin, z from -Lc - gap - margin to max(Lt, travel - gap) +
margin; the three volumes fragmented (the cylinder's side shares the tube's
inner surface where they touch: a conformal contact). Sizes: --size on the
cylinder and the tube, growing to --size-box at the box (a distance
threshold field over the margin). Rows at step --first-step (untimed in the
median) and the --steps steps every --stride after it; MaterialId 1 the
cylinder, 2 the tube, 0 space; the contact area (faces shared by 1 and 2).

    /usr/bin/python3 Testing/Benchmarks/adapt_gmsh_peer.py --case cylinder-half-tube \
        --r 5 --R 8 --Lc 20 --Lt 45 --gap 0.5 --margin 4 --travel 45 --size 0.55 \
        --size-box 2.2 --first-step 21 --steps 3 --stride 1
"""

import argparse
import math
import os
import sys
import time

import numpy as np
import gmsh

GMSH_TET = 4

# The checker's measures (Testing/Python/adapt_check.py): one definition of
# the stretch (thesis Eq. 1.1) and of the motion for the peer and the checks.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "Python"))
from adapt_check import rotation, signed_volumes, stretch  # noqa: E402


class Case:
    """The box, the block at step 0 and the motion per step."""

    def __init__(self, cells, obj, edge, object_at, path_steps):
        self.size = np.asarray(cells, dtype=float) * edge
        self.edge = edge
        self.translation = np.array([0.0, 0.0, 0.1]) * edge
        self.axis = np.array([1.0, 0.0, 0.0])
        self.degrees = 1.0
        obj = np.asarray(obj)
        cells = np.asarray(cells)
        if object_at is None:
            # Centred; along z, so that the path of path_steps is centred
            # when the block then stays in the box all along it.
            lo = (cells - obj) // 2
            centred = lo.copy()
            # (bench_adapt.cpp's placement: travel in whole cubes, rounded up.)
            travel = int(math.ceil(path_steps * self.translation[2] / edge - 1e-9))
            lo[2] = int(min(max((cells[2] - obj[2] - travel) // 2, 0), cells[2] - obj[2]))
            self.place(lo, obj)
            if not all(self.fits(n) for n in range(path_steps + 1)):
                lo = centred
        else:
            lo = np.asarray(object_at)
        self.place(lo, obj)

    def place(self, lo, obj):
        self.cube_lo = np.array(lo)
        self.lo, self.hi = self.cube_lo * self.edge, (self.cube_lo + obj) * self.edge
        self.center = 0.5 * (self.lo + self.hi)

    def pose(self, n):
        R = rotation(self.axis, n * self.degrees)
        return R, self.center + n * self.translation - R @ self.center

    def corners(self, n):
        R, t = self.pose(n)
        c = np.array([[x, y, z] for x in (self.lo[0], self.hi[0]) for y in (self.lo[1], self.hi[1])
                      for z in (self.lo[2], self.hi[2])])
        return c @ R.T + t

    def gap(self, n):
        """Smallest distance of the moved block's corners to the box faces
        (negative when outside)."""
        c = self.corners(n)
        return float(min(c.min(), (self.size - c).min()))

    def fits(self, n):
        return self.gap(n) > 0


def set_options(threads):
    for name, value in (("General.Terminal", 0), ("General.NumThreads", threads),
                        ("Mesh.MaxNumThreads1D", threads), ("Mesh.MaxNumThreads2D", threads),
                        ("Mesh.MaxNumThreads3D", threads), ("Mesh.Algorithm", 6),
                        ("Mesh.Algorithm3D", 1), ("Mesh.Optimize", 1),
                        ("Mesh.OptimizeNetgen", 0), ("Mesh.ElementOrder", 1),
                        ("Mesh.MeshSizeFromPoints", 0), ("Mesh.MeshSizeFromCurvature", 0),
                        ("Mesh.MeshSizeExtendFromBoundary", 1), ("Mesh.RandomSeed", 1)):
        gmsh.option.setNumber(name, value)


def build(case, n):
    """The box and the block at step n, fragmented; returns the block's
    volume tag."""
    occ = gmsh.model.occ
    gmsh.model.add(f"step{n}")
    box = occ.addBox(0, 0, 0, *case.size)
    block = occ.addBox(*case.lo, *(case.hi - case.lo))
    R, t = case.pose(n)
    angle = math.radians(n * case.degrees)
    if angle:
        occ.rotate([(3, block)], *case.center, *case.axis, angle)
    occ.translate([(3, block)], *(n * case.translation))
    occ.fragment([(3, box)], [(3, block)])
    occ.synchronize()
    vols = [tag for _, tag in gmsh.model.getEntities(3)]
    assert len(vols) == 2, f"step {n}: {len(vols)} volumes after the fragment"
    # The block is the volume whose centre of mass is the moved centre.
    moved_centre = R @ case.center + t
    com = {v: np.array(occ.getCenterOfMass(3, v)) for v in vols}
    block_tag = min(vols, key=lambda v: np.linalg.norm(com[v] - moved_centre))
    return block_tag


def mesh(size):
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.model.mesh.generate(3)


def kept_fractions(points, on_box, previous, tol):
    """Percent of all points and of the points off the box that kept their
    position since the previous mesh (its coordinate keys; None: "-"), and
    this mesh's keys for the next step."""
    if previous is None:
        kept = kept_inner = "-"
    else:
        keys = np.round(points / tol).astype(np.int64)
        same = np.array([tuple(k) in previous for k in keys.tolist()])
        kept = f"{100.0 * same.mean():.2f}"
        kept_inner = f"{100.0 * same[~on_box].mean():.2f}"
    return kept, kept_inner, coordinate_keys(points, tol)


def extract(block_tag):
    """Points, tets (positively oriented) and MaterialId of the current mesh."""
    return extract_materials({vol: 1 if vol == block_tag else 0 for _, vol in gmsh.model.getEntities(3)})


def tet_count(case, size):
    """Tets of a step 0 meshing with the given size."""
    gmsh.clear()
    build(case, 0)
    mesh(size)
    n = 0
    for _, vol in gmsh.model.getEntities(3):
        types, elems, _ = gmsh.model.mesh.getElements(3, vol)
        n += sum(len(e) for t, e in zip(types, elems) if t == GMSH_TET)
    return n


def calibrate(case, target):
    """A size giving about `target` tets: tets ~ size^-3 from the edge,
    corrected once by a power law through two meshings."""
    s1 = case.edge
    n1 = tet_count(case, s1)
    s2 = s1 * (n1 / target) ** (1 / 3)
    n2 = tet_count(case, s2)
    p = math.log(n2 / n1) / math.log(s2 / s1) if abs(s2 - s1) > 1e-12 * s1 else -3.0
    s3 = s2 * (target / n2) ** (1 / p)
    return s3, [(s1, n1), (s2, n2)]


class CylinderHalfTube:
    """Thesis 3.7.3: the cylinder (moving, 1 per step along z by default)
    and the half tube in their box."""

    def __init__(self, args):
        self.r, self.R, self.Lc, self.Lt = args.r, args.R, args.Lc, args.Lt
        self.gap, self.margin = args.gap, args.margin
        self.translation = args.translation
        travel = args.travel if args.travel >= 0 else args.Lt + args.gap
        w = self.R + self.margin
        z0 = -self.Lc - self.gap
        self.lo = np.array([-w, -w, z0 - self.margin])
        self.hi = np.array([w, w, max(self.Lt, -self.gap + travel) + self.margin])
        self.travel = travel

    def front(self, n):
        return -self.gap + n * self.translation

    def build(self, n):
        """The box, cylinder and half tube at step n, fragmented; returns
        {volume tag: material}."""
        occ = gmsh.model.occ
        gmsh.model.add(f"step{n}")
        box = occ.addBox(*self.lo, *(self.hi - self.lo))
        front = self.front(n)
        cyl = occ.addCylinder(0, 0, front - self.Lc, 0, 0, self.Lc, self.r)
        outer = occ.addCylinder(0, 0, 0, 0, 0, self.Lt, self.R)
        inner = occ.addCylinder(0, 0, 0, 0, 0, self.Lt, self.r)
        ring, _ = occ.cut([(3, outer)], [(3, inner)])
        half = occ.addBox(-2 * self.R, -2 * self.R, -1, 4 * self.R, 2 * self.R, self.Lt + 2)  # y <= 0
        tube, _ = occ.intersect(ring, [(3, half)])
        _, pieces = occ.fragment([(3, box)], [(3, cyl)] + tube)
        occ.synchronize()
        material = {}
        for dim, tag in pieces[0]:
            material[tag] = 0
        for dim, tag in pieces[1]:
            material[tag] = 1
        for piece in pieces[2:]:
            for dim, tag in piece:
                material[tag] = 2
        vols = [tag for _, tag in gmsh.model.getEntities(3)]
        assert set(vols) == set(material), f"step {n}: volumes {vols}, pieces {material}"
        return material


def set_sizes(material, size, size_box, distance):
    """--size on the objects' surfaces, growing to size_box at `distance`."""
    surfaces = set()
    for tag, m in material.items():
        if m:
            for dim, s in gmsh.model.getBoundary([(3, tag)], oriented=False):
                surfaces.add(s)
    field = gmsh.model.mesh.field
    d = field.add("Distance")
    # (Gmsh 4.8 names the surfaces FacesList; later ones SurfacesList.)
    try:
        field.setNumbers(d, "SurfacesList", sorted(surfaces))
    except Exception:  # noqa: BLE001 (gmsh raises a plain Exception)
        field.setNumbers(d, "FacesList", sorted(surfaces))
    t = field.add("Threshold")
    field.setNumber(t, "InField", d)
    field.setNumber(t, "SizeMin", size)
    field.setNumber(t, "SizeMax", size_box)
    field.setNumber(t, "DistMin", 0)
    field.setNumber(t, "DistMax", distance)
    field.setAsBackgroundMesh(t)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size_box)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)


def extract_materials(material):
    """Points, tets (positively oriented) and material of the current mesh."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    points = coords.reshape(-1, 3)
    tets, mats = [], []
    for _, vol in gmsh.model.getEntities(3):
        types, _, nodes = gmsh.model.mesh.getElements(3, vol)
        for typ, nd in zip(types, nodes):
            if typ == GMSH_TET:
                t = index[nd.astype(np.int64)].reshape(-1, 4)
                tets.append(t)
                mats.append(np.full(len(t), material[vol], dtype=np.int32))
    tets = np.vstack(tets)
    mats = np.concatenate(mats)
    used = np.unique(tets)
    remap = np.full(len(points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    points, tets = points[used], remap[tets]
    flip = signed_volumes(points, tets) < 0
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    return points, tets, mats


def shared_area(points, tets, mats, a, b):
    """Area of the faces shared by a tet of material a and one of b."""
    faces = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])

    def keyed(m):
        f = np.sort(tets[mats == m][:, faces].reshape(-1, 3), axis=1)
        return set(map(tuple, f.tolist()))
    common = np.array(sorted(keyed(a) & keyed(b)), dtype=np.int64).reshape(-1, 3)
    if not len(common):
        return 0.0
    p = points[common]
    return float(0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum())


def run_cylinder_half_tube(args):
    case = CylinderHalfTube(args)
    steps = [args.first_step + k * args.stride for k in range(args.steps + 1)]
    if max(case.front(n) for n in steps) > case.hi[2] - case.margin + 1e-9:
        print(f"the cylinder leaves the box's travel ({case.travel:g}) before step {steps[-1]}",
              file=sys.stderr)
        return 2
    size = args.size if args.size else 2 * case.r * math.sin(math.pi / 64)
    size_box = args.size_box if args.size_box else 4 * size
    gmsh.initialize(["adapt_gmsh_peer"], readConfigFiles=False)
    try:
        set_options(args.threads)
        print(f"3.7.3 cylinder r {case.r:g} length {case.Lc:g} into half tube R {case.R:g} length "
              f"{case.Lt:g} (gap {case.gap:g}, {case.translation:g} per step), box "
              f"{case.lo.tolist()} to {case.hi.tolist()}; size {size:.4f} on the objects, "
              f"{size_box:.4f} at the box; steps {steps[0]} (untimed) and {steps[1:]}; "
              f"Gmsh {gmsh.__version__}, {args.threads} thread(s)"
              + (f"; FEMorph's input {args.target_tets} tets" if args.target_tets else ""))
        tol = 1e-9 * float(np.linalg.norm(case.hi - case.lo))
        print(f"{'step':>5} {'tets':>8} {'vertices':>8} {'geom s':>7} {'mesh s':>7} {'total s':>7} "
              f"{'min stretch':>11} {'mean':>6} {'contact':>9} {'kept %':>7} {'kept inner %':>12}")
        previous = None
        totals = []
        for i, n in enumerate(steps):
            gmsh.clear()
            start = time.perf_counter()
            material = case.build(n)
            set_sizes(material, size, size_box, case.margin)
            geom = time.perf_counter() - start
            gmsh.model.mesh.generate(3)
            total = time.perf_counter() - start
            points, tets, mats = extract_materials(material)
            s = stretch(points, tets)
            area = shared_area(points, tets, mats, 1, 2)
            on_box = np.any((np.abs(points - case.lo) <= tol) | (np.abs(points - case.hi) <= tol), axis=1)
            kept, kept_inner, previous = kept_fractions(points, on_box, previous, tol)
            if i:
                totals.append(total)
            print(f"{n:>5} {len(tets):>8} {len(points):>8} {geom:>7.3f} {total - geom:>7.3f} "
                  f"{total:>7.3f} {s.min():>11.4f} {s.mean():>6.4f} {area:>9.3f} {kept:>7} {kept_inner:>12}",
                  flush=True)
        if totals:
            print(f"median s/step {float(np.median(totals)):.3f} over {len(totals)} steps "
                  f"(mean {float(np.mean(totals)):.3f})")
    finally:
        gmsh.finalize()
    return 0


def coordinate_keys(points, tol):
    return set(map(tuple, np.round(points / tol).astype(np.int64).tolist()))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, nargs=3, default=(20, 20, 50),
                        metavar=("NX", "NY", "NZ"), help="box in cubes (default 20 20 50)")
    parser.add_argument("--object", type=int, nargs=3, default=(3, 5, 1),
                        metavar=("OX", "OY", "OZ"), help="block in cubes (default 3 5 1)")
    parser.add_argument("--object-at", type=int, nargs=3, default=None, metavar=("I", "J", "K"),
                        help="the block's lowest cube at step 0")
    parser.add_argument("--path-steps", type=int, default=360,
                        help="steps of the whole path, for the default placement (default 360)")
    parser.add_argument("--edge", type=float, default=1.0, help="cube edge (default 1)")
    parser.add_argument("--steps", type=int, default=10, help="sampled steps (default 10)")
    parser.add_argument("--stride", type=int, default=36,
                        help="steps between samples (default 36: 10 x 36 = 360)")
    parser.add_argument("--size", type=float, default=None,
                        help="mesh size (default: calibrated to 12 tets per cube)")
    parser.add_argument("--threads", type=int, default=1, help="Gmsh threads (default 1)")
    parser.add_argument("--out-dir", default=None, help="write step_NNNN.vtu here")
    parser.add_argument("--case", choices=("block", "cylinder-half-tube"), default="block",
                        help="thesis 3.7.2's block (default) or 3.7.3's cylinder into a half tube")
    for name, default, what in (("r", 5.0, "cylinder radius = tube inner radius"),
                                ("R", 8.0, "tube outer radius"), ("Lc", 20.0, "cylinder length"),
                                ("Lt", 45.0, "tube length"), ("gap", 0.5, "front cap to tube at step 0"),
                                ("margin", 4.0, "space around the objects' path"),
                                ("travel", -1.0, "the box holds this travel (< 0: Lt + gap)"),
                                ("translation", 1.0, "along z per step")):
        parser.add_argument(f"--{name}", type=float, default=default, help=f"3.7.3: {what} ({default:g})")
    parser.add_argument("--size-box", type=float, default=None, help="3.7.3: size at the box (4 x --size)")
    parser.add_argument("--first-step", type=int, default=0, help="3.7.3: first (untimed) row's step")
    parser.add_argument("--target-tets", type=int, default=0, help="3.7.3: FEMorph's input tets, printed")
    args = parser.parse_args()
    if args.case == "cylinder-half-tube":
        return run_cylinder_half_tube(args)

    last = args.steps * args.stride
    case = Case(args.cells, args.object, args.edge, args.object_at, args.path_steps)
    bad = [n for n in range(0, last + 1) if not case.fits(n)]
    if bad:
        print(f"the block leaves the box at step {bad[0]} (of {last}): fewer --steps, a "
              f"smaller --stride or a longer box", file=sys.stderr)
        return 2
    target = 12 * int(np.prod(args.cells))
    write_vtu = None
    if args.out_dir:
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                        "..", "..", "Data"))
        from generate_adapt_cases import write_vtu  # noqa: E402
        os.makedirs(args.out_dir, exist_ok=True)

    gmsh.initialize(["adapt_gmsh_peer"], readConfigFiles=False)
    try:
        set_options(args.threads)
        print(f"box {' x '.join(map(str, args.cells))} cubes of edge {args.edge:g}, block "
              f"{' x '.join(map(str, args.object))} at cube {case.cube_lo.tolist()}, "
              f"centre {case.center.tolist()}; {args.steps} steps every {args.stride} "
              f"(last {last}, smallest gap to the box {min(case.gap(n) for n in range(last + 1)):.3f}); "
              f"Gmsh {gmsh.__version__}, {args.threads} thread(s)")
        if args.size is None:
            start = time.perf_counter()
            size, trials = calibrate(case, target)
            print(f"size {size:.4f} x edge for about {target} tets (12 per cube); trials "
                  + ", ".join(f"{s:.4f} -> {n}" for s, n in trials)
                  + f" ({time.perf_counter() - start:.1f} s)")
        else:
            size = args.size
        tol = 1e-9 * float(np.linalg.norm(case.size))
        print(f"{'step':>5} {'tets':>8} {'vertices':>8} {'geom s':>7} {'mesh s':>7} {'total s':>7} "
              f"{'min stretch':>11} {'mean':>6} {'kept %':>7} {'kept inner %':>12}")
        previous = None
        totals = []
        for n in [0] + [k * args.stride for k in range(1, args.steps + 1)]:
            gmsh.clear()
            start = time.perf_counter()
            block_tag = build(case, n)
            geom = time.perf_counter() - start
            mesh(size)
            total = time.perf_counter() - start
            points, tets, material = extract(block_tag)
            s = stretch(points, tets)
            on_box = np.any((np.abs(points) <= tol) | (np.abs(points - case.size) <= tol), axis=1)
            kept, kept_inner, previous = kept_fractions(points, on_box, previous, tol)
            if n:
                totals.append(total)
            print(f"{n:>5} {len(tets):>8} {len(points):>8} {geom:>7.3f} {total - geom:>7.3f} "
                  f"{total:>7.3f} {s.min():>11.4f} {s.mean():>6.4f} {kept:>7} {kept_inner:>12}",
                  flush=True)
            if write_vtu:
                write_vtu(os.path.join(args.out_dir, f"step_{n:04d}.vtu"), points, tets, material)
        if totals:
            # "median s/step X" is what bench_adapt.cpp reads.
            print(f"median s/step {float(np.median(totals)):.3f} over {len(totals)} steps "
                  f"(mean {float(np.mean(totals)):.3f})")
    finally:
        gmsh.finalize()
    return 0


if __name__ == "__main__":
    sys.exit(main())
