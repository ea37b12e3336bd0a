// Surface edge flips of Phased ODT smoothing (thesis 2.6.5.3, Fig. 2.45):
// toward a Delaunay triangulation of each fitted region.
#include "improve/flip_surface_edges.h"

#include "improve/boundary_geometry.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace femorph {

namespace {

/// Angle at vertex p of triangle (p, q, r).
double angle_at(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 a = q - p, b = r - p;
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

double min_angle(const Vec3& p, const Vec3& q, const Vec3& r) {
  return std::min({angle_at(p, q, r), angle_at(q, r, p), angle_at(r, p, q)});
}

/// The vertex of the boundary face of tet t holding edge (a, b) other than a
/// and b, and the face's region; false when t has no such face.
bool boundary_apex(const TetMesh& mesh, index_t t, index_t a, index_t b, index_t* apex, index_t* region) {
  const Tet& T = mesh.tet(t);
  for (int f = 0; f < 4; ++f) {
    if (T[f] == a || T[f] == b || !mesh.is_boundary_face(t, f)) continue;
    for (int i = 0; i < 3; ++i) {
      const index_t u = T[kTetFace[f][i]];
      if (u != a && u != b) *apex = u;
    }
    *region = mesh.face_region(t, f);
    return true;
  }
  return false;
}

}  // namespace

SurfaceFlipStats flip_surface_edges(TetMesh& mesh, const BoundaryGeometry& geometry,
                                    const SurfaceFlipOptions& options) {
  SurfaceFlipStats stats;
  const auto& mask = options.vertex_mask;
  auto masked_in = [&mask](index_t v) {
    return mask.empty() || (static_cast<std::size_t>(v) < mask.size() && mask[v]);
  };
  std::vector<index_t> ring;
  // An edge's test reads only its ring (and the positions, which a flip
  // does not change), and a flip that changes a tet of that ring touches
  // tets holding both ends. So from the second pass on, an edge neither of
  // whose ends was touched since the previous pass began would be refused
  // again: it is skipped without walking its ring or retrying a flip that
  // failed (a failed flip restores the tets, in other slots).
  std::vector<std::uint32_t> touched_at(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  std::uint32_t clock = 1, previous_start = 0;
  const auto untouched_since = [&](index_t v, std::uint32_t since) {
    return static_cast<std::size_t>(v) < touched_at.size() && touched_at[static_cast<std::size_t>(v)] < since;
  };
  for (int pass = 0; pass < options.max_passes; ++pass) {
    std::size_t flips = 0;
    const std::uint32_t pass_start = clock;
    for (index_t t = 0; t < mesh.tet_slots(); ++t) {
      for (int f = 0; f < 4; ++f) {
        if (!mesh.tet_alive(t)) break;
        if (!mesh.is_boundary_face(t, f)) continue;
        const index_t region = mesh.face_region(t, f);
        const SurfacePrimitive* surface = geometry.region(region);
        // Unfitted regions only with kept triangles, and only nearly flat
        // pairs (below): a flip changes their shape.
        if (!surface && !geometry.discrete_region(region)) continue;
        const Tet& T = mesh.tet(t);
        const index_t u[3] = {T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]};
        for (int e = 0; e < 3; ++e) {
          // Face (a, b, c) outward; each edge once, from the face where a < b.
          const index_t a = u[e], b = u[(e + 1) % 3], c = u[(e + 2) % 3];
          if (a > b || !masked_in(a) || !masked_in(b) || !masked_in(c)) continue;
          if (pass > 0 && untouched_since(a, previous_start) && untouched_since(b, previous_start)) continue;
          bool on_boundary = false;
          if (!mesh.edge_ring(a, b, ring, &on_boundary, t) || !on_boundary || ring.size() < 2) continue;
          index_t c0 = kInvalidIndex, c1 = kInvalidIndex, r0 = kInvalidIndex, r1 = kInvalidIndex;
          if (!boundary_apex(mesh, ring.front(), a, b, &c0, &r0) || !boundary_apex(mesh, ring.back(), a, b, &c1, &r1))
            continue;
          if (r0 != region || r1 != region) continue;  // a curve edge
          const index_t d = c0 == c ? c1 : c0;
          if ((c0 != c && c1 != c) || d == c || !masked_in(d)) continue;
          const Vec3 &pa = mesh.point(a), &pb = mesh.point(b), &pc = mesh.point(c), &pd = mesh.point(d);
          // Not Delaunay: the opposite angles sum to more than pi.
          if (!(angle_at(pc, pa, pb) + angle_at(pd, pb, pa) > kPi + 1e-12)) continue;
          // The flip must raise the smaller minimum angle ...
          if (!(std::min(min_angle(pc, pd, pa), min_angle(pd, pc, pb)) >
                std::min(min_angle(pa, pb, pc), min_angle(pb, pa, pd)) + 1e-12))
            continue;
          // ... and keep the quad convex: new faces (a, d, c), (b, c, d)
          // oriented like the old (a, b, c), (b, a, d).
          const Vec3 n_abc = (pb - pa).cross(pc - pa), n_bad = (pa - pb).cross(pd - pb);
          const Vec3 n_adc = (pd - pa).cross(pc - pa), n_bcd = (pc - pb).cross(pd - pb);
          if (!(n_adc.dot(n_abc) > 0 && n_adc.dot(n_bad) > 0 && n_bcd.dot(n_abc) > 0 && n_bcd.dot(n_bad) > 0))
            continue;
          // An unfitted region keeps its shape within max_deviation: the
          // distance between the lines (a, b) and (c, d), how far the new
          // pair of triangles is from the old one.
          if (!surface) {
            const Vec3 n = (pb - pa).cross(pd - pc);
            const double length = std::max((pb - pa).norm(), (pd - pc).norm());
            if (!(std::abs((pc - pa).dot(n)) <= options.max_deviation * length * n.norm())) continue;
          }
          // Tets of the flip (split at the midpoint m, m collapsed onto c):
          // each ring tet without c becomes two, with b resp. a replaced by c.
          double before = std::numeric_limits<double>::infinity(), after = before;
          for (index_t r : ring) {
            const Tet& R = mesh.tet(r);
            Vec3 x[4];
            for (int i = 0; i < 4; ++i) x[i] = mesh.point(R[i]);
            before = std::min(before, tet_stretch(x[0], x[1], x[2], x[3]));
            if (mesh.local_index(r, c) >= 0) continue;
            for (const index_t replaced : {a, b}) {
              Vec3 y[4];
              for (int i = 0; i < 4; ++i) y[i] = R[i] == replaced ? pc : x[i];
              after = std::min(after, tet_stretch(y[0], y[1], y[2], y[3]));
            }
          }
          const bool ok = surface && surface->type == SurfaceType::Plane
                              ? after >= std::min(before, options.min_stretch)
                              : after >= options.min_stretch && after >= before;
          if (ok && mesh.flip_surface_edge(a, b, t) == OpStatus::Ok) {
            ++stats.flips;
            ++flips;
            ++clock;
            if (touched_at.size() < static_cast<std::size_t>(mesh.vertex_slots()))
              touched_at.resize(static_cast<std::size_t>(mesh.vertex_slots()), 0);
            for (const index_t n : mesh.touched_tets())
              for (const index_t w : mesh.tet(n)) touched_at[static_cast<std::size_t>(w)] = clock;
            break;  // tet t changed: go on with its next face
          }
          ++stats.refused;
        }
      }
    }
    if (flips == 0) break;
    previous_start = pass_start;
  }
  return stats;
}

}  // namespace femorph
