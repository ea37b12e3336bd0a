// Superposition of earlier solutions of one system of Eq. 2.10 (thesis
// 2.5.4.3-2.5.4.5): the unknowns' displacements are linear in the knowns'
// displacements, so when only the target value changes, a right side in the
// span of earlier ones needs no solve ("parameterise once, reposition
// many"). The stored right sides are kept orthonormal (Gram-Schmidt), each
// with the solution it maps to.
#include "deform/deform.h"

namespace femorph {

namespace {

double dot(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a.array() * b.array()).sum(); }

}  // namespace

bool SolveHistory::superpose(const Eigen::MatrixXd& known, Eigen::Index unknowns, Eigen::MatrixXd& solution,
                             double exact) const {
  solution = Eigen::MatrixXd::Zero(unknowns, known.cols());
  if (!basis_.empty() && (basis_[0].rows() != known.rows() || solutions_[0].rows() != unknowns)) return false;
  Eigen::MatrixXd rest = known;
  for (std::size_t i = 0; i < basis_.size(); ++i) {
    const double c = dot(basis_[i], rest);
    rest -= c * basis_[i];
    solution += c * solutions_[i];
  }
  // The solution is a weighted mean of the knowns (mean value coordinates),
  // so what is left of the right side bounds the error in the max norm.
  const double scale = known.size() ? known.cwiseAbs().maxCoeff() : 0.0;
  return rest.size() == 0 || rest.cwiseAbs().maxCoeff() <= exact * scale;
}

void SolveHistory::add(const Eigen::MatrixXd& known, const Eigen::MatrixXd& solution) {
  if (!basis_.empty() && (basis_[0].rows() != known.rows() || solutions_[0].rows() != solution.rows())) clear();
  Eigen::MatrixXd rest = known, mapped = solution;
  for (int pass = 0; pass < 2; ++pass) {  // twice: orthogonal to rounding
    for (std::size_t i = 0; i < basis_.size(); ++i) {
      const double c = dot(basis_[i], rest);
      rest -= c * basis_[i];
      mapped -= c * solutions_[i];
    }
  }
  // A right side almost in the span adds rounding, amplified, not a direction.
  const double norm = rest.norm();
  if (!(norm > kNewDirection * known.norm())) return;
  if (basis_.size() == kMaxSize) {
    basis_.erase(basis_.begin());
    solutions_.erase(solutions_.begin());
  }
  basis_.push_back(rest / norm);
  solutions_.push_back(mapped / norm);
}

void SolveHistory::clear() {
  basis_.clear();
  solutions_.clear();
}

}  // namespace femorph
