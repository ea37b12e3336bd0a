// Vertex repositioning (thesis 2.5.4.5): mapped vertices onto the updated
// surfaces of the control and following regions (Method 1), then curve,
// surface and inner vertices by their coordinates (Method 2, Eq. 2.10, one
// solve per kind with the factorisation of parameterize_vertices), curve and
// surface vertices finally onto their surfaces.
#include "deform/deform.h"

#include "mesh/tet_mesh.h"

#include <cmath>

namespace femorph {

namespace {

/// The point of the intersection of the fitted surfaces of `regions` near
/// p: Newton steps on their signed distances (the minimum-norm step of the
/// linearised system) while their normals are independent, alternating
/// projections where they are nearly tangent (G1 curves). One surface: its
/// closest point.
Vec3 project(const std::vector<SurfacePrimitive>& surfaces, const std::vector<index_t>& regions, Vec3 p, double tol) {
  std::vector<const SurfacePrimitive*> list;
  for (const index_t r : regions) {
    if (r >= 0 && r < static_cast<index_t>(surfaces.size()) && surfaces[r].type != SurfaceType::Unknown) {
      list.push_back(&surfaces[r]);
    }
  }
  if (list.empty()) return p;
  if (list.size() == 1) return closest_point(*list[0], p);
  const int m = static_cast<int>(std::min<std::size_t>(list.size(), 3));
  for (int it = 0; it < 200; ++it) {
    Eigen::Matrix<double, 3, Eigen::Dynamic> n(3, m);
    Eigen::VectorXd d(m);
    for (int k = 0; k < m; ++k) {
      d(k) = signed_distance(*list[k], p);
      n.col(k) = surface_normal(*list[k], p);
    }
    if (d.cwiseAbs().maxCoeff() <= tol) break;
    const Eigen::MatrixXd g = n.transpose() * n;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(g);
    const double conditioning = g.diagonal().minCoeff() > 0 ? std::abs(g.determinant()) : 0;
    if (conditioning > 1e-6 && ldlt.info() == Eigen::Success) {
      p -= n * ldlt.solve(d);
    } else {
      for (const SurfacePrimitive* s : list) p = closest_point(*s, p);
    }
  }
  return p;
}

/// The displacements of a system's unknowns from those of its knowns.
void solve(const VertexParameterization::System& system, std::vector<Vec3>& points, const std::vector<Vec3>& rest) {
  if (system.unknowns.empty()) return;
  Eigen::MatrixXd known(system.knowns.size(), 3);
  for (std::size_t k = 0; k < system.knowns.size(); ++k) {
    const index_t v = system.knowns[k];
    known.row(static_cast<Eigen::Index>(k)) = (points[v] - rest[v]).transpose();
  }
  const Eigen::MatrixXd rhs = system.rhs * known;
  Eigen::MatrixXd u;
  if (system.lu) {
    u = system.lu->solve(rhs);
  } else {
    u.resize(rhs.rows(), 3);
    for (int c = 0; c < 3; ++c) u.col(c) = system.iterative->solve(rhs.col(c));
  }
  for (std::size_t i = 0; i < system.unknowns.size(); ++i) {
    const index_t v = system.unknowns[i];
    points[v] = rest[v] + u.row(static_cast<Eigen::Index>(i)).transpose();
  }
}

/// Vertices of a region that does not move (a deformed plane) keep their
/// coordinate along its normal bit for bit when the normal is a coordinate
/// axis (a fitted normal a rounding error away from one): the projection
/// would leave ~1e-16 off the plane, and a solver's input deck selects
/// z = 0 by value.
void keep_axis_coordinates(const std::vector<SurfacePrimitive>& surfaces, const std::vector<index_t>& regions,
                           const Vec3& rest, Vec3& p) {
  for (const index_t r : regions) {
    if (r < 0 || r >= static_cast<index_t>(surfaces.size()) || surfaces[r].type != SurfaceType::Plane) continue;
    const Vec3& n = surfaces[r].axis;
    for (int k = 0; k < 3; ++k) {
      if (std::abs(std::abs(n[k]) - 1) < 1e-12 && std::abs(rest[k] - surfaces[r].point[k]) <= 1e-9 * (1 + std::abs(rest[k]))) {
        p[k] = rest[k];
      }
    }
  }
}

}  // namespace

void reposition_vertices(const TetMesh& mesh, const DeformRegions& /*regions*/, const VertexParameterization& param,
                         const SurfaceUpdate& update, std::vector<Vec3>& points) {
  using Param = VertexParameterization;
  const std::vector<Vec3>& rest = mesh.points();
  points = rest;
  double scale = 0;
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    if (mesh.vertex_alive(v)) scale = std::max(scale, rest[v].cwiseAbs().maxCoeff());
  }
  const double tol = 1e-15 * std::max(scale, 1.0);
  // Method 1: onto the updated surfaces, then onto the deformed neighbours'.
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    if (param.kind[v] != Param::Mapped) continue;
    points[v] = update.map(param.region[v], rest[v]);
    if (param.mapped_regions[v].size() > 1) {
      points[v] = project(update.surfaces, param.mapped_regions[v], points[v], tol);
      keep_axis_coordinates(update.surfaces, param.mapped_regions[v], rest[v], points[v]);
    }
  }
  // Method 2 by kind; curves and surfaces back onto their surfaces.
  solve(param.curves, points, rest);
  for (const index_t v : param.curves.unknowns) {
    const std::vector<index_t> two{param.curve_regions[v][0], param.curve_regions[v][1]};
    points[v] = project(update.surfaces, two, points[v], tol);
    keep_axis_coordinates(update.surfaces, two, rest[v], points[v]);
  }
  solve(param.surfaces, points, rest);
  for (const index_t v : param.surfaces.unknowns) {
    points[v] = project(update.surfaces, {param.region[v]}, points[v], tol);
    keep_axis_coordinates(update.surfaces, {param.region[v]}, rest[v], points[v]);
  }
  solve(param.inner, points, rest);
}

}  // namespace femorph
