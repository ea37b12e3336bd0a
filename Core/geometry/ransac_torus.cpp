#include "geometry/fit_internal.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace femorph {

namespace {

// Beyond the thesis: the axis from normals alone. Every normal line
// x_i + t n_i of a surface of revolution meets its axis; in Plücker
// coordinates a line (c, cbar) (direction, moment) meets the normal line
// (n_i, x_i x n_i) iff c . (x_i x n_i) + cbar . n_i = 0, linear in (c, cbar).
// Least squares with |c| = 1: cbar = -C^-1 B^T c eliminates the moment and c
// is the smallest eigenvector of the 3x3 Schur complement.
bool normal_lines_axis(const std::vector<Vec3>& y, const std::vector<Vec3>& n, const int* idx, int count, Vec3& point,
                       Vec3& axis) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), B = Eigen::Matrix3d::Zero(), C = Eigen::Matrix3d::Zero();
  for (int k = 0; k < count; ++k) {
    const int i = idx ? idx[k] : k;
    const Vec3 m = y[i].cross(n[i]);
    A += m * m.transpose();
    B += m * n[i].transpose();
    C += n[i] * n[i].transpose();
  }
  // Normals in one plane (a cylinder-like patch) leave C singular: a tiny
  // ridge keeps the moment bounded.
  C.diagonal().array() += 1e-12 * C.trace();
  const Eigen::Matrix3d Cinv_Bt = C.ldlt().solve(B.transpose());
  const Eigen::Matrix3d S = A - B * Cinv_Bt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(0.5 * (S + S.transpose()));
  const Vec3 c = eigen.eigenvectors().col(0);
  const Vec3 cbar = -Cinv_Bt * c;
  axis = c;
  point = c.cross(cbar);  // the axis point closest to the origin
  return axis.allFinite() && point.allFinite();
}

// Fig. 2.14 step 2: the axis lies in the planes spanned by the normal and the
// principal direction of maximum curvature (the meridian planes).
bool meridian_planes_axis(const std::vector<Vec3>& y, const std::vector<Vec3>& n, const std::vector<Vec3>& dirs,
                          const int* idx, int count, Vec3& point, Vec3& axis) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  Vec3 rhs = Vec3::Zero(), mean = Vec3::Zero();
  std::vector<Vec3> planes(count);
  for (int k = 0; k < count; ++k) {
    const Vec3 m = n[idx[k]].cross(dirs[idx[k]]);
    const double l = m.norm();
    if (!(l > 1e-6)) return false;
    planes[k] = m / l;
    M += planes[k] * planes[k].transpose();
    mean += y[idx[k]] / count;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(M);
  // Points in one meridian plane do not fix the axis.
  if (!(eigen.eigenvalues()(1) > 1e-6 * eigen.eigenvalues()(2))) return false;
  axis = eigen.eigenvectors().col(0);
  // The axis point nearest the planes, pinned along the axis at the sample's mean.
  Eigen::Matrix3d A = axis * axis.transpose();
  rhs = axis * axis.dot(mean);
  for (int k = 0; k < count; ++k) {
    A += planes[k] * planes[k].transpose();
    rhs += planes[k] * planes[k].dot(y[idx[k]]);
  }
  point = A.lu().solve(rhs);
  return point.allFinite();
}

// Fig. 2.14 steps 3-4: the points rotated into one meridian half-plane
// (distance from the axis, height along it); the circle through them gives
// the minor radius (its radius), the major radius (its distance from the
// axis) and the centre (the axis point at its height).
bool meridian_circle(const std::vector<Vec3>& y, const int* idx, int count, const Vec3& point, const Vec3& axis,
                     SurfacePrimitive& torus) {
  std::vector<Eigen::Vector2d> meridian(count);
  for (int k = 0; k < count; ++k) {
    const Vec3 v = y[idx ? idx[k] : k] - point;
    const double h = v.dot(axis);
    meridian[k] = Eigen::Vector2d((v - h * axis).norm(), h);
  }
  const Circle2dFit circle = fit_circle_2d(meridian);
  if (!circle.ok || !(circle.center.x() >= 0)) return false;
  torus.type = SurfaceType::Torus;
  torus.axis = axis;
  torus.point = point + circle.center.y() * axis;
  torus.radius = circle.center.x();
  torus.minor_radius = circle.radius;
  torus.half_angle = 0;
  return true;
}

bool torus_from_normal_lines(const std::vector<Vec3>& y, const std::vector<Vec3>& n, const int* idx, int count,
                             SurfacePrimitive& torus) {
  Vec3 point, axis;
  return normal_lines_axis(y, n, idx, count, point, axis) && meridian_circle(y, idx, count, point, axis, torus);
}

}  // namespace

FitResult ransac_torus(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                       const std::vector<Vec3>* max_dirs, const RansacParams& params) {
  FitResult result;
  const std::size_t count = points.size();
  if (count < 7 || normals.size() != count || (max_dirs != nullptr && max_dirs->size() != count)) return result;
  const detail::Normalisation frame(points);
  if (!frame.valid()) return result;
  const std::vector<Vec3> y = frame.apply(points);
  const std::vector<Vec3> n = detail::unit_normals(normals);
  // Thesis samples: 3 points with principal directions. Normals only: the
  // line meeting the normal lines needs 5 of them (6 Plücker unknowns up to
  // scale).
  const int sample_size = max_dirs != nullptr ? 3 : 5;
  // Local optimisation: axis and meridian circle of a consensus set.
  const auto refit = [&](const SurfacePrimitive& model, const std::vector<int>& inliers, SurfacePrimitive& torus) {
    const std::vector<int> used = detail::normal_consistent(model, y, n, inliers);
    return torus_from_normal_lines(y, n, used.data(), static_cast<int>(used.size()), torus);
  };
  detail::Ransac ransac(y, params.inlier_tolerance / frame.scale, params, sample_size, refit);

  // The axis meeting all normal lines, and the meridian circle of all points:
  // on a clean region (a fillet over a small part of its tube included) this
  // alone is close enough for refine_fit_lm.
  SurfacePrimitive torus;
  if (torus_from_normal_lines(y, n, nullptr, static_cast<int>(count), torus)) ransac.offer(torus);

  while (ransac.next()) {
    int idx[5];
    ransac.sample(idx);
    if (max_dirs != nullptr) {
      Vec3 point, axis;
      if (meridian_planes_axis(y, n, *max_dirs, idx, 3, point, axis) && meridian_circle(y, idx, 3, point, axis, torus))
        ransac.offer(torus);
    } else if (torus_from_normal_lines(y, n, idx, 5, torus)) {
      ransac.offer(torus);
    }
  }
  if (!ransac.has_best()) return result;

  result = evaluate_fit(frame.to_world(ransac.best()), points);
  result.iterations = ransac.iterations();
  result.inlier_count = ransac.best_consensus().inliers;
  return result;
}

}  // namespace femorph
