#include "improve/boundary_geometry.h"

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace femorph {

bool closest_point_on_curve(const CurvePrimitive& curve, const Vec3& p, Vec3* out) {
  switch (curve.type) {
    case CurveType::Line: {
      const Vec3& d = curve.direction;
      *out = curve.start + (p - curve.start).dot(d) * d;
      return true;
    }
    case CurveType::Circle:
    case CurveType::CircularArc: {
      const Vec3& n = curve.normal;
      Vec3 radial = (p - curve.center) - (p - curve.center).dot(n) * n;
      const double len = radial.norm();
      if (!(len > 1e-300)) return false;  // on the axis: no unique closest point
      *out = curve.center + curve.radius / len * radial;
      return true;
    }
    default:
      *out = p;
      return false;
  }
}

namespace {

/// Regions of the boundary faces of v's ball, ascending, without repeats.
void vertex_regions(const TetMesh& mesh, index_t v, const std::vector<index_t>& ball, std::vector<index_t>& regions) {
  regions.clear();
  for (index_t t : ball) {
    const Tet& T = mesh.tet(t);
    for (int f = 0; f < 4; ++f)
      if (T[f] != v && mesh.is_boundary_face(t, f)) regions.push_back(mesh.face_region(t, f));
  }
  std::sort(regions.begin(), regions.end());
  regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
}

bool is_line_or_circle(const CurvePrimitive& c) {
  return c.type == CurveType::Line || c.type == CurveType::Circle || c.type == CurveType::CircularArc;
}

}  // namespace

void add_discrete_regions(const TetMesh& mesh, BoundaryGeometry& geometry) {
  std::vector<std::vector<std::array<Vec3, 3>>> triangles;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const Tet& T = mesh.tet(t);
    for (int f = 0; f < 4; ++f) {
      if (!mesh.is_boundary_face(t, f)) continue;
      const index_t r = mesh.face_region(t, f);
      if (r < 0 || geometry.region(r)) continue;
      if (static_cast<std::size_t>(r) >= triangles.size()) triangles.resize(static_cast<std::size_t>(r) + 1);
      triangles[r].push_back(
          {mesh.point(T[kTetFace[f][0]]), mesh.point(T[kTetFace[f][1]]), mesh.point(T[kTetFace[f][2]])});
    }
  }
  geometry.discrete.assign(std::max(geometry.discrete.size(), triangles.size()), DiscreteSurface());
  for (std::size_t r = 0; r < triangles.size(); ++r)
    if (!triangles[r].empty()) geometry.discrete[r].build(std::move(triangles[r]));
}

VertexConstraint vertex_constraint(const TetMesh& mesh, const BoundaryGeometry& geometry, index_t v) {
  const VertexClass cls = mesh.vertex_class(v);
  // Per-thread walk marks, not the mesh's shared ones: callers may run in
  // parallel (the density control's collapse evaluation projects).
  thread_local std::vector<index_t> ball;
  thread_local TetMesh::WalkMarks marks;
  ball.clear();
  if (cls != VertexClass::Inner && cls != VertexClass::Corner) mesh.vertex_ball(v, ball, marks);
  return vertex_constraint(mesh, geometry, v, ball);
}

VertexConstraint vertex_constraint(const TetMesh& mesh, const BoundaryGeometry& geometry, index_t v,
                                   const std::vector<index_t>& ball) {
  VertexConstraint c;
  const VertexClass cls = mesh.vertex_class(v);
  if (cls == VertexClass::Inner) return c;
  c.kind = VertexConstraint::Fixed;
  if (cls == VertexClass::Corner) return c;
  thread_local std::vector<index_t> regions;
  vertex_regions(mesh, v, ball, regions);
  if (regions.size() == 1) {
    c.region_a = regions[0];
    c.surface = geometry.region(regions[0]);
    if (cls != VertexClass::Surface) return c;
    if (c.surface) {
      c.kind = VertexConstraint::Surface;
    } else if ((c.discrete = geometry.discrete_region(regions[0]))) {
      c.kind = VertexConstraint::Discrete;
    }
    return c;
  }
  if (regions.size() != 2 || cls != VertexClass::Curve) return c;
  c.region_a = regions[0];
  c.region_b = regions[1];
  c.surface = geometry.region(regions[0]);
  c.surface_b = geometry.region(regions[1]);
  // The closest known line or circle between the two regions.
  const Vec3& p = mesh.point(v);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < geometry.curves.size() && k < geometry.curve_regions.size(); ++k) {
    const auto& cr = geometry.curve_regions[k];
    if (!((cr[0] == c.region_a && cr[1] == c.region_b) || (cr[0] == c.region_b && cr[1] == c.region_a))) continue;
    if (!is_line_or_circle(geometry.curves[k])) continue;
    Vec3 q;
    if (!closest_point_on_curve(geometry.curves[k], p, &q)) continue;
    const double d = (q - p).norm();
    if (d < best) {
      best = d;
      c.curve = &geometry.curves[k];
    }
  }
  if (c.curve || (c.surface && c.surface_b)) c.kind = VertexConstraint::Curve;
  return c;
}

bool project_to_constraint(const VertexConstraint& c, const Vec3& p, Vec3* out) {
  switch (c.kind) {
    case VertexConstraint::Free:
      *out = p;
      return true;
    case VertexConstraint::Surface:
      *out = closest_point(*c.surface, p);
      return out->allFinite();
    case VertexConstraint::Curve: {
      if (c.curve) return closest_point_on_curve(*c.curve, p, out) && out->allFinite();
      // Alternating projections onto the two surfaces; converges to their
      // intersection near p when they cross at an angle.
      Vec3 q = p;
      for (int i = 0; i < 50; ++i) {
        const Vec3 prev = q;
        q = closest_point(*c.surface_b, closest_point(*c.surface, q));
        if ((q - prev).squaredNorm() <= 1e-30 * (1 + q.squaredNorm())) break;
      }
      *out = q;
      return q.allFinite();
    }
    case VertexConstraint::Discrete:
      *out = c.discrete->closest_point(p);
      return out->allFinite();
    case VertexConstraint::Fixed:
      break;
  }
  *out = p;
  return false;
}

double constraint_distance(const VertexConstraint& c, const Vec3& p) {
  if (c.kind == VertexConstraint::Fixed) return std::numeric_limits<double>::quiet_NaN();
  Vec3 q;
  if (!project_to_constraint(c, p, &q)) return std::numeric_limits<double>::quiet_NaN();
  return (q - p).norm();
}

}  // namespace femorph
