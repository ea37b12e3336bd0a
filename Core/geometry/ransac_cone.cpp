#include "geometry/fit_internal.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace femorph {

namespace {

// The cone with apex `apex` whose axis runs into the nappe holding the points:
// orientation by the mean direction apex -> points, opening angle Eq. 2.7
// (mean angle between the axis and the unit vectors apex -> points).
bool finish_cone(const Vec3& apex, Vec3 axis, const std::vector<Vec3>& y, const int* idx, int count,
                 double max_half_angle, SurfacePrimitive& cone) {
  const double length = axis.norm();
  if (!(length > 0)) return false;
  axis /= length;
  Vec3 mean = Vec3::Zero();
  for (int k = 0; k < count; ++k) {
    const Vec3 d = y[idx ? idx[k] : k] - apex;
    const double l = d.norm();
    if (!(l > 0)) return false;
    mean += d / l;
  }
  if (axis.dot(mean) < 0) axis = -axis;
  double angle = 0;
  for (int k = 0; k < count; ++k) {
    const Vec3 e = (y[idx ? idx[k] : k] - apex).normalized();
    angle += std::acos(std::clamp(e.dot(axis), -1.0, 1.0));
  }
  angle /= count;
  // Step 6: too wide cones are rejected; a vanishing angle is a cylinder.
  if (!(angle > 1e-6 && angle <= max_half_angle)) return false;
  cone.type = SurfaceType::Cone;
  cone.point = apex;
  cone.axis = axis;
  cone.half_angle = angle;
  cone.radius = cone.minor_radius = 0;
  return true;
}

// Beyond the thesis, the cone of a whole point set from its normals: the
// normals make a constant angle with the axis, so the plane fitted to them on
// the Gaussian sphere has the axis as normal (the cylinder test of 2.4.3.3);
// the apex is the least-squares point of all tangent planes.
bool cone_from_normals(const std::vector<Vec3>& y, const std::vector<Vec3>& n, double max_half_angle,
                       SurfacePrimitive& cone) {
  const int count = static_cast<int>(y.size());
  if (count < 6) return false;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& v : n) mean += v;
  mean /= count;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero(), tangent = Eigen::Matrix3d::Zero();
  Vec3 rhs = Vec3::Zero();
  for (int i = 0; i < count; ++i) {
    scatter += (n[i] - mean) * (n[i] - mean).transpose();
    const Eigen::Matrix3d nn = n[i] * n[i].transpose();
    tangent += nn;
    rhs += nn * y[i];
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> planes(tangent);
  if (!(planes.eigenvalues()(0) > 1e-9 * planes.eigenvalues()(2))) return false;
  const Vec3 apex = planes.eigenvectors() * (planes.eigenvalues().cwiseInverse().asDiagonal() *
                                             (planes.eigenvectors().transpose() * rhs));
  return finish_cone(apex, eigen.eigenvectors().col(0), y, nullptr, count, max_half_angle, cone);
}

}  // namespace

FitResult ransac_cone(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, const RansacParams& params) {
  FitResult result;
  if (points.size() < 6 || normals.size() != points.size()) return result;
  const detail::Normalisation frame(points);
  if (!frame.valid()) return result;
  const std::vector<Vec3> y = frame.apply(points);
  const std::vector<Vec3> n = detail::unit_normals(normals);
  // Local optimisation: the cone of a consensus set from its normals.
  const auto refit = [&](const SurfacePrimitive& model, const std::vector<int>& inliers, SurfacePrimitive& cone) {
    const std::vector<int> used = detail::normal_consistent(model, y, n, inliers);
    return cone_from_normals(detail::gather(y, used), detail::gather(n, used), params.max_cone_half_angle, cone);
  };
  detail::Ransac ransac(y, params.inlier_tolerance / frame.scale, params, 3, refit);

  SurfacePrimitive cone;
  if (cone_from_normals(y, n, params.max_cone_half_angle, cone)) ransac.offer(cone);

  while (ransac.next()) {
    int idx[3];
    ransac.sample(idx);
    // Step 2: the apex where the three tangent planes n_i . (p - x_i) = 0 meet.
    Eigen::Matrix3d N;
    Vec3 b;
    for (int k = 0; k < 3; ++k) {
      N.row(k) = n[idx[k]].transpose();
      b(k) = n[idx[k]].dot(y[idx[k]]);
    }
    if (!(std::abs(N.determinant()) > 1e-9)) continue;
    const Vec3 apex = N.lu().solve(b);
    if (!apex.allFinite()) continue;
    // Step 3: the axis is normal to the plane through apex + unit(x_i - apex).
    Vec3 e[3];
    bool degenerate = false;
    for (int k = 0; k < 3; ++k) {
      const Vec3 d = y[idx[k]] - apex;
      const double l = d.norm();
      degenerate = degenerate || !(l > 0);
      e[k] = d / l;
    }
    if (degenerate) continue;
    // Step 4 (Eq. 2.7) and step 6 (angle limit) in finish_cone.
    if (finish_cone(apex, (e[1] - e[0]).cross(e[2] - e[0]), y, idx, 3, params.max_cone_half_angle, cone))
      ransac.offer(cone);
  }
  if (!ransac.has_best()) return result;

  result = evaluate_fit(frame.to_world(ransac.best()), points);
  result.iterations = ransac.iterations();
  result.inlier_count = ransac.best_consensus().inliers;
  return result;
}

}  // namespace femorph
