#!/usr/bin/python3
"""CalculiX (ccx) harness of the FEA acceptance tests of FEMorph Deform.

The same linear static analysis runs on a linear tet mesh (.vtu, the layout of
Data/README.md) made by FEMorph Deform and on a fresh Gmsh mesh of the changed
CAD part; both are turned into 10-node tetrahedra (C3D10) the same way.

    calculix.py cantilever mesh.vtu [--keep DIR]
    calculix.py plate mesh.vtu --radius 10 [--keep DIR]
    calculix.py compare --case cantilever_width20 --mesh deformed.vtu [--work-dir DIR]

`compare` meshes the fresh reference part of the case itself
(Data/generate_fea_parts.py), runs the analysis on both meshes, prints both
results, their relative difference and the errors against the analytic value,
and exits with 1 when the difference exceeds 0.5 % or an error exceeds 1 %
(2 for usage errors, 77 when ccx or gmsh is missing).

Units: mm, N, MPa. Testing/FEA/README.md describes the boundary conditions
and the formulas. Needs numpy and vtkmodules (python3-paraview); `compare`
also gmsh (python3-gmsh). Use /usr/bin/python3.
"""

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.append("/usr/lib/python3/dist-packages")
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DATA = os.path.join(REPO, "Data")
FEA_DATA = os.path.join(DATA, "fea")

E_MODULUS = 206000.0   # MPa (steel)
POISSON = 0.3
CANTILEVER_FORCE = 100.0   # N, total, in -z on the end face
PLATE_STRESS = 100.0       # MPa, tension on the x = length face
CCX_TIMEOUT = 600.0        # s, per run

SKIP = 77  # ctest's SKIP_RETURN_CODE

# C3D10 (CalculiX manual, "Three-dimensional elements", the 10-node
# tetrahedron, same as Abaqus): corners 1-4, then the mid-edge nodes
# 5: 1-2, 6: 2-3, 7: 3-1, 8: 1-4, 9: 2-4, 10: 3-4. The corner order has a
# positive Jacobian when (p2-p1).((p3-p1)x(p4-p1)) > 0, as VTK's tets
# and Data/README.md's convention.
C3D10_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))
# Faces of a tet, as corner triples (the face opposite local corner i).
TET_FACES = ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))

# Fractional tolerance on positions (of the part size) for "on a plane".
PLANE_TOLERANCE = 1e-6


# ----------------------------------------------------------------------------
# Mesh input and the 10-node conversion
# ----------------------------------------------------------------------------

def read_vtu(path):
    """Points (n x 3) and tets (m x 4, 0-based) of a .vtu of linear tets."""
    if not os.path.isfile(path):
        raise FileNotFoundError(path)
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    types = vtk_to_numpy(grid.GetCellTypesArray())
    if grid.GetNumberOfCells() == 0 or not np.all(types == 10):
        raise ValueError(f"{path}: expected linear tetrahedra (VTK_TETRA) only")
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).astype(np.int64)
    return points, conn.reshape(-1, 4)


def tet_volumes6(points, tets):
    p0, p1, p2, p3 = (points[tets[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", p1 - p0, np.cross(p2 - p0, p3 - p0))


def boundary_triangles(tets):
    """Boundary faces (k x 3 corner ids, outward by the right-hand rule) of a
    positively oriented tet mesh: the faces only one tet has."""
    # Outward orientation of the face opposite corner i for a positive tet.
    outward = np.array([(1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)])
    faces = tets[:, outward].reshape(-1, 3)
    keys = np.sort(faces, axis=1)
    _, inverse, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    return faces[counts[inverse.reshape(-1)] == 1]


def project_to_cylinder(x, surf):
    """Closest points on the (infinite) cylinder surf of points x."""
    c = np.asarray(surf["point"], dtype=float)
    a = np.asarray(surf["axis"], dtype=float)
    a = a / np.linalg.norm(a)
    v = x - c
    h = v @ a
    radial = v - np.outer(h, a)
    rho = np.linalg.norm(radial, axis=1)
    return c + np.outer(h, a) + radial * (surf["radius"] / rho)[:, None]


def distance_to_cylinder(x, surf):
    c = np.asarray(surf["point"], dtype=float)
    a = np.asarray(surf["axis"], dtype=float)
    a = a / np.linalg.norm(a)
    v = x - c
    h = v @ a
    return np.abs(np.linalg.norm(v - np.outer(h, a), axis=1) - surf["radius"])


def to_c3d10(points, tets, boundary_surfaces=None, tolerance=None):
    """Linear tets -> 10-node tets in CalculiX's C3D10 node order.

    Returns (nodes, elements, tris6): the corner points followed by one
    mid-edge node per edge (shared by the tets around the edge, at the
    edge's midpoint), the elements (m x 10, 0-based) and the boundary faces
    as 6-node triangles (corners a b c, then mid-nodes of ab, bc, ca; outward
    by the right-hand rule). Negatively oriented tets are turned over.

    boundary_surfaces: analytic surfaces [{"type": "cylinder", "point": p,
    "axis": a, "radius": r}, ...]. The mid-edge nodes of the boundary edges
    of the triangles lying on such a surface (all three corners within
    `tolerance`, default 1e-3 r, and the triangle's normal perpendicular to
    the axis within 60 degrees, so that a flat face's triangle touching the
    rim with three corners is not taken) are projected onto it: a curved
    10-node boundary, as a CAD-aware mesher would give. Applied the same
    way to a deformed mesh and a fresh mesh.
    """
    points = np.asarray(points, dtype=float)
    tets = np.array(tets, dtype=np.int64)
    negative = tet_volumes6(points, tets) < 0
    tets[negative] = tets[negative][:, [0, 2, 1, 3]]
    if np.any(tet_volumes6(points, tets) <= 0):
        raise ValueError("tet of zero volume")
    n = len(points)
    edges = np.stack([tets[:, list(e)] for e in C3D10_EDGES], axis=1).reshape(-1, 2)
    keys = np.sort(edges, axis=1)
    unique_edges, edge_of = np.unique(keys, axis=0, return_inverse=True)
    edge_of = edge_of.reshape(-1)
    mids = 0.5 * (points[unique_edges[:, 0]] + points[unique_edges[:, 1]])
    elements = np.hstack([tets, n + edge_of.reshape(-1, 6)])

    tris = boundary_triangles(tets)
    tri_edge_keys = np.sort(np.stack([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]],
                                     axis=1).reshape(-1, 2), axis=1)
    tri_edge_ids = edge_index(unique_edges, tri_edge_keys).reshape(-1, 3)

    for surf in boundary_surfaces or []:
        if surf.get("type") != "cylinder":
            raise ValueError(f"unsupported boundary surface {surf}")
        tol = tolerance if tolerance is not None else 1e-3 * surf["radius"]
        on = distance_to_cylinder(points, surf) < tol
        a = np.asarray(surf["axis"], dtype=float)
        a = a / np.linalg.norm(a)
        p0, p1, p2 = (points[tris[:, i]] for i in range(3))
        normal = np.cross(p1 - p0, p2 - p0)
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        sel = np.all(on[tris], axis=1) & (np.abs(normal @ a) < 0.5)
        ids = np.unique(tri_edge_ids[sel])
        mids[ids] = project_to_cylinder(mids[ids], surf)

    nodes = np.vstack([points, mids])
    tris6 = np.hstack([tris, n + tri_edge_ids])
    return nodes, elements, tris6


def edge_index(unique_edges, keys):
    """Row of each key (sorted pair) in unique_edges (sorted lexicographically)."""
    big = int(unique_edges.max()) + 1
    code = unique_edges[:, 0] * big + unique_edges[:, 1]
    k = keys[:, 0] * big + keys[:, 1]
    pos = np.searchsorted(code, k)
    assert np.all(code[pos] == k), "boundary edge not found"
    return pos


def tri6_weights(nodes, tris6):
    """Consistent nodal weights of a uniform field on flat 6-node triangles:
    integral of each shape function, 0 at the corners and area / 3 at the
    mid-edge nodes. Returns (node ids, weights), summed per node."""
    p0, p1, p2 = (nodes[tris6[:, i]] for i in range(3))
    area = 0.5 * np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)
    ids = tris6[:, 3:].reshape(-1)
    w = np.repeat(area / 3.0, 3)
    uniq, inv = np.unique(ids, return_inverse=True)
    return uniq, np.bincount(inv, weights=w)


def triangles_on_plane(nodes, tris6, axis, value, tol):
    return tris6[np.all(np.abs(nodes[tris6[:, :3], axis] - value) < tol, axis=1)]


# ----------------------------------------------------------------------------
# CalculiX input, run and output
# ----------------------------------------------------------------------------

def ccx_available():
    return shutil.which("ccx") is not None


def write_inp(path, nodes, elements, fixed, loads, print_sets, file_sets=None):
    """fixed: list of (node ids 0-based, first dof, last dof); loads: (node
    ids, dof, values); print_sets: {name: node ids} printed with U into the
    .dat; file_sets: {name: node ids}, nodal stresses written to the .frd."""
    with open(path, "w") as f:
        f.write("** FEMorph FEA harness (Testing/FEA/calculix.py)\n*NODE, NSET=NALL\n")
        f.write("".join(f"{i + 1},{x:.15g},{y:.15g},{z:.15g}\n"
                        for i, (x, y, z) in enumerate(nodes)))
        f.write("*ELEMENT, TYPE=C3D10, ELSET=EALL\n")
        el = elements + 1
        f.write("".join(f"{k + 1}," + ",".join(str(v) for v in row) + "\n"
                        for k, row in enumerate(el)))
        for name, ids in list(print_sets.items()) + list((file_sets or {}).items()):
            f.write(f"*NSET, NSET={name}\n")
            ids = np.asarray(ids) + 1
            for s in range(0, len(ids), 16):
                f.write(",".join(str(v) for v in ids[s:s + 16]) + "\n")
        f.write(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E_MODULUS:g}, {POISSON:g}\n")
        f.write("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
        f.write("*STEP\n*STATIC\n*BOUNDARY\n")
        for ids, first, last in fixed:
            f.write("".join(f"{i + 1},{first},{last}\n" for i in ids))
        f.write("*CLOAD\n")
        for ids, dof, values in loads:
            f.write("".join(f"{i + 1},{dof},{v:.15g}\n" for i, v in zip(ids, values)))
        for name in print_sets:
            f.write(f"*NODE PRINT, NSET={name}\nU\n")
        if file_sets:
            for name in file_sets:
                f.write(f"*NODE FILE, NSET={name}\nU\n*EL FILE, NSET={name}\nS\n")
        else:
            f.write("*NODE FILE\nU\n")
        f.write("*END STEP\n")


def run_ccx(workdir, job="job", timeout=CCX_TIMEOUT):
    """Run ccx on <workdir>/<job>.inp with one thread; returns seconds."""
    if not ccx_available():
        raise RuntimeError("ccx (CalculiX) not found")
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_STIFFNESS="1",
               CCX_NPROC_EQUATION_SOLVER="1")
    start = time.perf_counter()
    proc = subprocess.run(["ccx", "-i", job], cwd=workdir, env=env, capture_output=True,
                          text=True, timeout=timeout)
    seconds = time.perf_counter() - start
    log = proc.stdout + proc.stderr
    with open(os.path.join(workdir, job + ".log"), "w") as f:
        f.write(log)
    if proc.returncode != 0 or "*ERROR" in log:
        errors = [line for line in log.splitlines() if "ERROR" in line]
        raise RuntimeError(f"ccx failed (exit {proc.returncode}) in {workdir}: "
                           + "; ".join(errors[:5]))
    return seconds


def parse_dat_displacements(path):
    """{set name: {node id 1-based: (ux, uy, uz)}} from *NODE PRINT U blocks."""
    out = {}
    current = None
    header = re.compile(r"^\s*displacements \(vx,vy,vz\) for set (\S+)")
    with open(path) as f:
        for line in f:
            m = header.match(line)
            if m:
                current = out.setdefault(m.group(1), {})
                continue
            parts = line.split()
            if current is not None and len(parts) == 4:
                try:
                    current[int(parts[0])] = tuple(float(v) for v in parts[1:])
                    continue
                except ValueError:
                    pass
            if parts and current is not None and not re.match(r"^-?\d", parts[0]):
                current = None
    return out


def parse_frd_block(path, name):
    """{node id 1-based: values} of the last nodal result block `name`
    (e.g. "STRESS": sxx syy szz sxy syz szx) of an ascii .frd."""
    result = None
    with open(path) as f:
        inside = False
        for line in f:
            if line.startswith(" -4"):
                inside = line.split()[1] == name
                if inside:
                    result = {}
                continue
            if inside:
                if line.startswith(" -3"):
                    inside = False
                elif line.startswith(" -1"):
                    node = int(line[3:13])
                    body = line[13:].rstrip("\n")
                    result[node] = [float(body[i:i + 12]) for i in range(0, len(body), 12)]
    if result is None:
        raise ValueError(f"{path}: no {name} block")
    return result


# ----------------------------------------------------------------------------
# Analytic values
# ----------------------------------------------------------------------------

def euler_bernoulli_deflection(force, length, width, height, e=E_MODULUS):
    inertia = width * height ** 3 / 12.0
    return force * length ** 3 / (3.0 * e * inertia)


def timoshenko_deflection(force, length, width, height, e=E_MODULUS, nu=POISSON):
    """Euler-Bernoulli plus the shear term F L / (k G A), with Cowper's
    shear coefficient of a rectangle k = 10 (1 + nu) / (12 + 11 nu)."""
    g = e / (2.0 * (1.0 + nu))
    k = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)
    return (euler_bernoulli_deflection(force, length, width, height, e)
            + force * length / (k * g * width * height))


def heywood_peak(stress, radius, width):
    """Peak hoop stress at a central hole in a finite-width plate in tension
    (Heywood 1952): Kt_net = 2 + (1 - d/W)^3 on sigma_net = sigma W / (W - d)."""
    d = 2.0 * radius
    kt_net = 2.0 + (1.0 - d / width) ** 3
    return kt_net * stress * width / (width - d), kt_net


def howland_fit_peak(stress, radius, width):
    """The same from the curve fitted to Howland's solution (Peterson's
    Stress Concentration Factors, chapter 4): Kt_net = 2 + 0.284 a - 0.600
    a^2 + 1.32 a^3, a = 1 - d/W. For comparison only."""
    a = 1.0 - 2.0 * radius / width
    kt_net = 2.0 + 0.284 * a - 0.600 * a ** 2 + 1.32 * a ** 3
    return kt_net * stress * width / (width - 2.0 * radius), kt_net


# ----------------------------------------------------------------------------
# The two analyses
# ----------------------------------------------------------------------------

def _workdir(keep):
    if keep:
        os.makedirs(keep, exist_ok=True)
        return keep, None
    tmp = tempfile.TemporaryDirectory(prefix="femorph_ccx_")
    return tmp.name, tmp


def cantilever(vtu, keep=None, force=CANTILEVER_FORCE, clamp="full"):
    """Tip deflection (mm, positive down) of the beam in `vtu` clamped at
    x = min x (all dofs of every node of the face), `force` N in -z spread
    uniformly over the face x = max x (consistent nodal loads of the
    quadratic face: area/3 on each mid-edge node). The deflection is the
    area-weighted mean of -uz over the loaded face, with the same consistent
    weights (the work-conjugate of the load). clamp="free_y" (a diagnostic
    of the clamp's stiffening) holds the face's nodes in x and z only and
    one corner in y, leaving the face free to contract sideways. Returns a
    dict."""
    points, tets = read_vtu(vtu)
    nodes, elements, tris6 = to_c3d10(points, tets)
    lo, hi = points.min(axis=0), points.max(axis=0)
    size = float(np.linalg.norm(hi - lo))
    tol = PLANE_TOLERANCE * size
    clamp_nodes = np.flatnonzero(np.abs(nodes[:, 0] - lo[0]) < tol)
    end_tris = triangles_on_plane(nodes, tris6, 0, hi[0], tol)
    load_ids, weights = tri6_weights(nodes, end_tris)
    area = weights.sum()
    work, tmp = _workdir(keep)
    try:
        write_inp(os.path.join(work, "job.inp"), nodes, elements,
                  fixed=([(clamp_nodes, 1, 3)] if clamp == "full" else
                         [(clamp_nodes, 1, 1), (clamp_nodes, 3, 3), (clamp_nodes[:1], 2, 2)]),
                  loads=[(load_ids, 3, -force * weights / area)],
                  print_sets={"NEND": load_ids})
        seconds = run_ccx(work)
        u = parse_dat_displacements(os.path.join(work, "job.dat"))["NEND"]
        uz = np.array([u[i + 1][2] for i in load_ids])
        all_end = np.flatnonzero(np.abs(nodes[:, 0] - hi[0]) < tol)
    finally:
        if tmp:
            tmp.cleanup()
    length, width, height = hi - lo
    return {"mesh": vtu, "tets": int(len(tets)), "nodes": int(len(nodes)),
            "length": float(length), "width": float(width), "height": float(height),
            "force": force, "clamp": clamp, "end_area": float(area), "end_nodes": int(len(all_end)),
            "tip_deflection": float(-(weights @ uz) / area),
            "tip_deflection_min": float(-uz.max()), "tip_deflection_max": float(-uz.min()),
            "ccx_seconds": seconds}


# The through-thickness mean of sigma_xx at the hole: the hole nodes within
# MEAN_WINDOW_DEG of the y axis through the centre (both sides), in MEAN_BINS
# equal z bins.
MEAN_WINDOW_DEG = 8.0
MEAN_BINS = 10


def thickness_mean_at_peak(x, sxx, center, z0, z1):
    """Through-thickness mean of sigma_xx on the hole where the hoop stress
    peaks (angle phi = 0 from the y axis through the centre): the plane-
    stress figure the 2D formulas describe. The nodes within MEAN_WINDOW_DEG
    are fitted with sigma = a_k + b phi^2 (a_k per z bin k, a common
    curvature b, phi in radians: the stress falls off quadratically from the
    peak), and the mean of the a_k is returned (NaN when no bin has nodes)."""
    phi = np.arctan2(x[:, 0] - center[0], np.abs(x[:, 1] - center[1]))
    near = np.abs(phi) < math.radians(MEAN_WINDOW_DEG)
    bins = np.minimum(((x[:, 2] - z0) / (z1 - z0) * MEAN_BINS).astype(int), MEAN_BINS - 1)
    used = [k for k in range(MEAN_BINS) if np.any(near & (bins == k))]
    if not used:
        return float("nan")
    rows = np.flatnonzero(near)
    a = np.zeros((len(rows), len(used) + 1))
    for j, k in enumerate(used):
        a[bins[rows] == k, j] = 1.0
    a[:, -1] = phi[rows] ** 2
    coef = np.linalg.lstsq(a, sxx[rows], rcond=None)[0]
    return float(np.mean(coef[:-1]))


def find_hole_axis(points):
    """Axis point of the through hole (along z) of the plate: the centre of
    the part's bounding box in x and y (our plates are symmetric)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    return [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.0]


def plate_tension(vtu, radius, stress=PLATE_STRESS, keep=None, center=None, curved=True):
    """Peak sigma_xx (MPa) at the hole of the plate in `vtu` under a uniform
    tension `stress` on the face x = max x (consistent nodal loads). The
    supports are statically determinate: ux = 0 on every node of the face
    x = min x, uy = uz = 0 at its corner (min x, min y, min z), uz = 0 at its
    corner (min x, max y, min z). The hole's mid-edge nodes are put on the
    cylinder. The peak is the largest nodal sigma_xx (ccx's extrapolated and
    averaged nodal stresses) over the nodes on the hole (curved=False, a
    diagnostic, leaves the hole's mid-edge nodes on the straight edges).
    Returns a dict."""
    points, tets = read_vtu(vtu)
    lo, hi = points.min(axis=0), points.max(axis=0)
    center = center or find_hole_axis(points)
    hole = {"type": "cylinder", "point": center, "axis": [0.0, 0.0, 1.0], "radius": float(radius)}
    nodes, elements, tris6 = to_c3d10(points, tets, [hole] if curved else None)
    size = float(np.linalg.norm(hi - lo))
    tol = PLANE_TOLERANCE * size
    held = np.flatnonzero(np.abs(nodes[:, 0] - lo[0]) < tol)

    def corner(target):
        d = np.linalg.norm(nodes - np.asarray(target), axis=1)
        i = int(np.argmin(d))
        assert d[i] < tol, f"no node at the corner {target}"
        return np.array([i])

    c0 = corner([lo[0], lo[1], lo[2]])
    c1 = corner([lo[0], hi[1], lo[2]])
    end_tris = triangles_on_plane(nodes, tris6, 0, hi[0], tol)
    load_ids, weights = tri6_weights(nodes, end_tris)
    boundary_nodes = np.unique(tris6)
    hole_nodes = boundary_nodes[distance_to_cylinder(nodes[boundary_nodes], hole) < 1e-3 * radius]
    if len(hole_nodes) == 0:
        raise ValueError(f"{vtu}: no node on a hole of radius {radius} at {center}")
    work, tmp = _workdir(keep)
    try:
        write_inp(os.path.join(work, "job.inp"), nodes, elements,
                  fixed=[(held, 1, 1), (c0, 2, 3), (c1, 3, 3)],
                  loads=[(load_ids, 1, stress * weights)],
                  print_sets={}, file_sets={"NHOLE": hole_nodes})
        seconds = run_ccx(work)
        s = parse_frd_block(os.path.join(work, "job.frd"), "STRESS")
    finally:
        if tmp:
            tmp.cleanup()
    sxx = np.array([s[i + 1][0] for i in hole_nodes])
    k = int(np.argmax(sxx))
    z = nodes[hole_nodes, 2]
    on_face = (np.abs(z - lo[2]) < tol) | (np.abs(z - hi[2]) < tol)
    thickness_mean = thickness_mean_at_peak(nodes[hole_nodes], sxx, center, lo[2], hi[2])
    return {"mesh": vtu, "tets": int(len(tets)), "nodes": int(len(nodes)),
            "radius": float(radius), "width": float(hi[1] - lo[1]),
            "thickness": float(hi[2] - lo[2]), "stress": stress,
            "load_area": float(weights.sum()), "hole_nodes": int(len(hole_nodes)),
            "peak_sxx": float(sxx[k]), "peak_at": nodes[hole_nodes[k]].tolist(),
            "peak_sxx_faces": float(sxx[on_face].max()) if np.any(on_face) else float("nan"),
            "thickness_mean_sxx": thickness_mean,
            "ccx_seconds": seconds}


# ----------------------------------------------------------------------------
# Cases for the Deform acceptance test
# ----------------------------------------------------------------------------

# case -> (analysis, reference part made by Data/generate_fea_parts.py,
#          nominal dimensions for the analytic value)
CASES = {
    "cantilever_width10": ("cantilever", "cantilever", {"length": 100.0, "width": 10.0, "height": 10.0}),
    "cantilever_width20": ("cantilever", "cantilever_width20", {"length": 100.0, "width": 20.0, "height": 10.0}),
    "plate_hole_r5": ("plate", "plate_hole", {"radius": 5.0, "width": 100.0}),
    "plate_hole_r10": ("plate", "plate_hole_r10", {"radius": 10.0, "width": 100.0}),
}
MAX_DIFFERENCE = 0.005   # deformed vs fresh
MAX_ANALYTIC_ERROR = 0.01


def analytic(case):
    kind, _, dims = CASES[case]
    if kind == "cantilever":
        eb = euler_bernoulli_deflection(CANTILEVER_FORCE, dims["length"], dims["width"], dims["height"])
        tim = timoshenko_deflection(CANTILEVER_FORCE, dims["length"], dims["width"], dims["height"])
        return {"value": eb, "name": "F L^3 / (3 E I)", "timoshenko": tim}
    peak, kt = heywood_peak(PLATE_STRESS, dims["radius"], dims["width"])
    howland, kt_h = howland_fit_peak(PLATE_STRESS, dims["radius"], dims["width"])
    return {"value": peak, "name": "Heywood Kt_net sigma W/(W-d)", "kt_net": kt,
            "howland_fit": howland, "kt_net_howland_fit": kt_h}


def run_case(case, vtu, keep=None):
    """The case's analysis on `vtu`: (figure, figure against the analytic
    value, full result dict). Cantilever: the tip deflection, both times.
    Plate: the peak nodal sigma_xx at the hole, and against Heywood's 2D
    (plane-stress) value its through-thickness mean where the hoop stress
    peaks (the peak itself is a 3D mid-plane value above it; README.md)."""
    kind, _, dims = CASES[case]
    if kind == "cantilever":
        r = cantilever(vtu, keep=keep)
        return r["tip_deflection"], r["tip_deflection"], r
    r = plate_tension(vtu, dims["radius"], keep=keep)
    return r["peak_sxx"], r["thickness_mean_sxx"], r


def fresh_mesh(case, out_dir):
    """Mesh the case's reference part with Gmsh into out_dir; returns its .vtu."""
    sys.path.insert(0, DATA)
    import generate_fea_parts  # needs gmsh
    part = CASES[case][1]
    generate_fea_parts.generate_fea(part, out_dir)
    return os.path.join(out_dir, part + ".vtu")


def compare(deformed_vtu, fresh_vtu, case, keep=None):
    """The case's analysis on both meshes. Returns a dict with both figures
    (`value`), their relative difference (deformed vs fresh), both errors of
    the analytic figure (`analytic_value`: the tip deflection, or the plate's
    through-thickness mean at the hole) against the analytic value and `ok`
    (difference <= 0.5 %, errors <= 1 %)."""
    ref = analytic(case)
    out = {"case": case, "analytic": ref}
    for label, vtu in (("deformed", deformed_vtu), ("fresh", fresh_vtu)):
        sub = os.path.join(keep, label) if keep else None
        value, analytic_value, detail = run_case(case, vtu, keep=sub)
        out[label] = {"value": value, "analytic_value": analytic_value,
                      "error": analytic_value / ref["value"] - 1.0,
                      "value_error": value / ref["value"] - 1.0, "detail": detail}
    out["difference"] = out["deformed"]["value"] / out["fresh"]["value"] - 1.0
    out["ok"] = bool(abs(out["difference"]) <= MAX_DIFFERENCE
                     and abs(out["deformed"]["error"]) <= MAX_ANALYTIC_ERROR
                     and abs(out["fresh"]["error"]) <= MAX_ANALYTIC_ERROR)
    return out


# ----------------------------------------------------------------------------
# Command line
# ----------------------------------------------------------------------------

def print_cantilever(r):
    eb = euler_bernoulli_deflection(r["force"], r["length"], r["width"], r["height"])
    tim = timoshenko_deflection(r["force"], r["length"], r["width"], r["height"])
    print(f"mesh {r['mesh']}: {r['tets']} tets -> {r['nodes']} C3D10 nodes, "
          f"beam {r['length']:g} x {r['width']:g} x {r['height']:g} mm, ccx {r['ccx_seconds']:.1f} s")
    print(f"tip deflection (mean over the end face) {r['tip_deflection']:.6f} mm "
          f"(end-face nodes {r['tip_deflection_min']:.6f} .. {r['tip_deflection_max']:.6f})")
    print(f"Euler-Bernoulli F L^3/(3 E I)           {eb:.6f} mm   error {100 * (r['tip_deflection'] / eb - 1):+.3f} %")
    print(f"Timoshenko (+ F L/(k G A), Cowper k)    {tim:.6f} mm   error {100 * (r['tip_deflection'] / tim - 1):+.3f} %")


def print_plate(r):
    peak, kt = heywood_peak(r["stress"], r["radius"], r["width"])
    howland, _ = howland_fit_peak(r["stress"], r["radius"], r["width"])
    print(f"mesh {r['mesh']}: {r['tets']} tets -> {r['nodes']} C3D10 nodes, "
          f"{r['hole_nodes']} nodes on the hole, ccx {r['ccx_seconds']:.1f} s")
    print(f"peak sigma_xx at the hole {r['peak_sxx']:.3f} MPa at "
          f"({', '.join(f'{v:.3f}' for v in r['peak_at'])}), on the plate faces "
          f"{r['peak_sxx_faces']:.3f} MPa (applied {r['stress']:g} MPa)")
    print(f"through-thickness mean of sigma_xx at the peak angle {r['thickness_mean_sxx']:.3f} MPa "
          f"(Heywood error {100 * (r['thickness_mean_sxx'] / peak - 1):+.3f} %)")
    print(f"Heywood Kt_net = 2 + (1 - d/W)^3 = {kt:.4f}: {peak:.3f} MPa   "
          f"error {100 * (r['peak_sxx'] / peak - 1):+.3f} %")
    print(f"Howland fit (Peterson):            {howland:.3f} MPa   "
          f"error {100 * (r['peak_sxx'] / howland - 1):+.3f} %")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("cantilever", help="tip deflection of a beam mesh")
    p.add_argument("mesh")
    p.add_argument("--keep", help="run ccx in this folder and keep its files")
    p.add_argument("--clamp", choices=["full", "free_y"], default="full",
                   help="full: all dofs of the x = 0 face (default); free_y: x and z only")
    p = sub.add_parser("plate", help="peak sigma_xx at the hole of a plate mesh")
    p.add_argument("mesh")
    p.add_argument("--radius", type=float, required=True)
    p.add_argument("--stress", type=float, default=PLATE_STRESS)
    p.add_argument("--straight", action="store_true",
                   help="leave the hole's mid-edge nodes on the straight edges (diagnostic)")
    p.add_argument("--keep", help="run ccx in this folder and keep its files")
    p = sub.add_parser("compare", help="a deformed mesh against a fresh mesh of the same part")
    p.add_argument("--case", choices=sorted(CASES), required=True)
    p.add_argument("--mesh", required=True, help="the deformed mesh (.vtu)")
    p.add_argument("--fresh", help="the fresh mesh (default: meshed now with Gmsh)")
    p.add_argument("--work-dir", help="keep the fresh mesh and the ccx files here")
    args = parser.parse_args(argv)
    for path in (args.mesh, getattr(args, "fresh", None)):
        if path and not os.path.isfile(path):
            parser.error(f"no file {path}")

    if not ccx_available():
        print("SKIP: ccx (CalculiX) not found", file=sys.stderr)
        return SKIP
    if args.command == "cantilever":
        print_cantilever(cantilever(args.mesh, keep=args.keep, clamp=args.clamp))
        return 0
    if args.command == "plate":
        print_plate(plate_tension(args.mesh, args.radius, args.stress, keep=args.keep,
                                  curved=not args.straight))
        return 0

    work, tmp = _workdir(args.work_dir)
    try:
        fresh = args.fresh
        if not fresh:
            try:
                import gmsh  # noqa: F401
            except ImportError:
                print("SKIP: gmsh (python3-gmsh) not found", file=sys.stderr)
                return SKIP
            fresh = fresh_mesh(args.case, work)
        r = compare(args.mesh, fresh, args.case, keep=args.work_dir)
    finally:
        if tmp:
            tmp.cleanup()
    a = r["analytic"]
    unit = "mm" if CASES[args.case][0] == "cantilever" else "MPa"
    print(f"case {args.case}: analytic {a['name']} = {a['value']:.6g} {unit}")
    plate = CASES[args.case][0] == "plate"
    for label in ("deformed", "fresh"):
        d = r[label]
        mesh = d["detail"]["mesh"] if label == "deformed" or args.fresh or args.work_dir else "Gmsh"
        if plate:
            print(f"  {label:<8} peak sigma_xx {d['value']:.6g} {unit} (error {100 * d['value_error']:+.3f} %), "
                  f"through-thickness mean {d['analytic_value']:.6g} {unit}  error {100 * d['error']:+.3f} %  "
                  f"({d['detail']['tets']} tets, ccx {d['detail']['ccx_seconds']:.1f} s, {mesh})")
        else:
            print(f"  {label:<8} {d['value']:.6g} {unit}  error {100 * d['error']:+.3f} %  "
                  f"({d['detail']['tets']} tets, ccx {d['detail']['ccx_seconds']:.1f} s, {mesh})")
    print(f"  difference deformed vs fresh{' (peak)' if plate else ''} {100 * r['difference']:+.3f} % "
          f"(limit {100 * MAX_DIFFERENCE:g} %; analytic error limit {100 * MAX_ANALYTIC_ERROR:g} %)")
    print("PASS" if r["ok"] else "FAIL")
    return 0 if r["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
