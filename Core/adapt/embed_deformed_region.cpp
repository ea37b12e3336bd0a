// Rigid transformation and deformed region adaptation, thesis 3.5.3
// (Fig. 3.8): each inner vertex of K_Df is written as the mean value
// coordinates of its 1-ring polyhedron (Eq. 3.1, Ju et al. 2005, shared with
// Deform), the moving object's vertices take their new positions, and the
// inner vertices follow as the solution of the sparse system of Eq. 3.2.
#include "adapt/adapt.h"

#include "deform/deform.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>

#include <algorithm>

namespace femorph {

Status embed_deformed_region(RegionMesh& region, const std::vector<std::uint8_t>& moved,
                             const std::vector<Vec3>& moved_position, std::size_t* inner_vertices) {
  TetMesh& mesh = region.mesh;
  const index_t nv = mesh.vertex_slots();
  std::vector<index_t> row_of(static_cast<std::size_t>(nv), kInvalidIndex);
  std::vector<index_t> unknowns;
  for (index_t v = 0; v < nv; ++v)
    if (mesh.vertex_alive(v) && !mesh.on_boundary(v) && !(v < static_cast<index_t>(moved.size()) && moved[v])) {
      row_of[v] = static_cast<index_t>(unknowns.size());
      unknowns.push_back(v);
    }
  if (inner_vertices) *inner_vertices = unknowns.size();

  // Eq. 3.1 before the motion.
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> a;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(unknowns.size()), 3);
  std::vector<index_t> ring_ids;
  std::vector<double> weights;
  const auto known_position = [&](index_t w) -> Vec3 {
    return w < static_cast<index_t>(moved.size()) && moved[w] ? moved_position[w] : mesh.point(w);
  };
  for (std::size_t i = 0; i < unknowns.size(); ++i) {
    const index_t v = unknowns[i];
    vertex_ring_mvc(mesh, v, ring_ids, weights);
    a.emplace_back(static_cast<int>(i), static_cast<int>(i), 1.0);
    for (std::size_t j = 0; j < ring_ids.size(); ++j) {
      const index_t w = ring_ids[j];
      if (row_of[w] >= 0) a.emplace_back(static_cast<int>(i), static_cast<int>(row_of[w]), -weights[j]);
      else b.row(static_cast<Eigen::Index>(i)) += weights[j] * known_position(w).transpose();
    }
  }
  // Step 2: the object's vertices move.
  for (index_t v = 0; v < nv && v < static_cast<index_t>(moved.size()); ++v)
    if (moved[v]) mesh.set_point(v, moved_position[v]);
  if (unknowns.empty()) return Status::success();
  // Step 3: Eq. 3.2.
  Eigen::SparseMatrix<double> matrix(static_cast<Eigen::Index>(unknowns.size()),
                                     static_cast<Eigen::Index>(unknowns.size()));
  matrix.setFromTriplets(a.begin(), a.end());
  // The positions before the motion solve the system for the old boundary
  // (MVC reproduce linear functions), so they start an iterative solve that
  // needs few iterations for a small step; a direct solve is the fallback.
  // The matrix is I - W with W's rows summing to at most 1: BiCGSTAB needs
  // no preconditioner (an incomplete LU cost more than it saved).
  Eigen::MatrixXd x(static_cast<Eigen::Index>(unknowns.size()), 3);
  for (std::size_t i = 0; i < unknowns.size(); ++i) x.row(static_cast<Eigen::Index>(i)) = mesh.point(unknowns[i]).transpose();
  bool solved = false;
  {
    Eigen::BiCGSTAB<Eigen::SparseMatrix<double>> solver;
    solver.setTolerance(1e-12);
    solver.setMaxIterations(500);
    solver.compute(matrix);
    if (solver.info() == Eigen::Success) {
      solved = true;
      for (int c = 0; c < 3 && solved; ++c) {
        const Eigen::VectorXd xc = solver.solveWithGuess(b.col(c), x.col(c));
        solved = solver.info() == Eigen::Success && xc.allFinite();
        if (solved) x.col(c) = xc;
      }
    }
  }
  if (!solved) {
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.compute(matrix);
    if (lu.info() != Eigen::Success)
      return Status::failure("the embedding system of the deformed region (Eq. 3.2) is singular");
    x = lu.solve(b);
    if (lu.info() != Eigen::Success || !x.allFinite())
      return Status::failure("the embedding system of the deformed region (Eq. 3.2) could not be solved");
  }
  for (std::size_t i = 0; i < unknowns.size(); ++i)
    mesh.set_point(unknowns[i], x.row(static_cast<Eigen::Index>(i)).transpose());
  return Status::success();
}

}  // namespace femorph
