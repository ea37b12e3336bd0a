// Vertex repositioning (thesis 2.5.4.5): mapped vertices onto the updated
// surfaces of the control and following regions (Method 1), then curve,
// surface and inner vertices by their coordinates (Method 2, Eq. 2.10, one
// solve per kind with the factorisation of parameterize_vertices, or a
// superposition of earlier solutions), curve and
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

/// The displacements of a system's unknowns from those of its knowns: by
/// superposition of earlier solutions where they span the knowns' moves,
/// else by a solve (warm-started from the superposed part when iterative).
void solve(const VertexParameterization::System& system, SolveHistory* history, std::vector<Vec3>& points,
           const std::vector<Vec3>& rest, double exact = SolveHistory::kExact) {
  if (system.unknowns.empty()) return;
  const auto n = static_cast<Eigen::Index>(system.unknowns.size());
  Eigen::MatrixXd known(system.knowns.size(), 3);
  for (std::size_t k = 0; k < system.knowns.size(); ++k) {
    const index_t v = system.knowns[k];
    known.row(static_cast<Eigen::Index>(k)) = (points[v] - rest[v]).transpose();
  }
  Eigen::MatrixXd u;
  bool superposed = false;
  if (history) {
    superposed = history->superpose(known, n, u, exact);
  } else {
    u = Eigen::MatrixXd::Zero(n, 3);
  }
  if (!superposed) {
    const Eigen::MatrixXd rhs = system.rhs * known;
    bool solved = false;
    if (system.lu) {
      u = system.lu->solve(rhs);
      solved = true;
    } else if (system.iterative) {
      solved = true;
      for (int c = 0; c < 3 && solved; ++c) {
        const Eigen::VectorXd guess = u.col(c);
        u.col(c) = system.iterative->solveWithGuess(rhs.col(c), guess);
        solved = system.iterative->info() == Eigen::Success;
      }
    }
    if (!solved) {  // BiCGSTAB stalled: factorise this once
      Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(system.matrix);
      solved = lu.info() == Eigen::Success;
      if (solved) u = lu.solve(rhs);
      solved = solved && lu.info() == Eigen::Success && u.allFinite();
      // Singular (vertices outside their 1-ring): the unknowns stay, and the
      // caller's inversion check sees the tets this folds.
      if (!solved) u.setZero(n, 3);
    }
    if (history && solved) history->add(known, u);
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
                         const SurfaceUpdate& update, std::vector<Vec3>& points, RepositionHistory* history) {
  const std::vector<Vec3>& rest = mesh.points();
  points = rest;
  const double tol = 1e-15 * std::max(param.scale, 1.0);
  // Method 1: onto the updated surfaces, then onto the deformed neighbours'.
  for (const index_t v : param.mapped) {
    points[v] = update.map(param.region[v], rest[v]);
    if (param.mapped_regions[v].size() > 1) {
      points[v] = project(update.surfaces, param.mapped_regions[v], points[v], tol);
      keep_axis_coordinates(update.surfaces, param.mapped_regions[v], rest[v], points[v]);
    }
  }
  // Method 2 by kind; curves and surfaces back onto their surfaces.
  solve(param.curves, history ? &history->curves : nullptr, points, rest);
  for (const index_t v : param.curves.unknowns) {
    const std::vector<index_t> two{param.curve_regions[v][0], param.curve_regions[v][1]};
    points[v] = project(update.surfaces, two, points[v], tol);
    keep_axis_coordinates(update.surfaces, two, rest[v], points[v]);
  }
  solve(param.surfaces, history ? &history->surfaces : nullptr, points, rest);
  for (const index_t v : param.surfaces.unknowns) {
    points[v] = project(update.surfaces, {param.region[v]}, points[v], tol);
    keep_axis_coordinates(update.surfaces, {param.region[v]}, rest[v], points[v]);
  }
  solve(param.inner, history ? &history->inner : nullptr, points, rest, SolveHistory::kInnerExact);
}

}  // namespace femorph
