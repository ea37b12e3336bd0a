#include "geometry/fit_internal.h"

#include <Eigen/LU>

namespace femorph {

namespace {

// Fig. 2.11 step 2: the point nearest (least squares) to the normal lines
// x_i + t n_i, i.e. sum (I - n n^T) c = sum (I - n n^T) x.
bool normal_lines_meet(const Vec3* x, const Vec3* n, int count, Vec3& center) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Vec3 b = Vec3::Zero();
  for (int k = 0; k < count; ++k) {
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n[k] * n[k].transpose();
    A += P;
    b += P * x[k];
  }
  // Parallel normals (a plane) meet nowhere.
  if (!(std::abs(A.determinant()) > 1e-9)) return false;
  center = A.lu().solve(b);
  return center.allFinite();
}

}  // namespace

FitResult ransac_sphere(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, const RansacParams& params) {
  FitResult result;
  if (points.size() < 4 || normals.size() != points.size()) return result;
  const detail::Normalisation frame(points);
  if (!frame.valid()) return result;
  const std::vector<Vec3> y = frame.apply(points);
  const std::vector<Vec3> n = detail::unit_normals(normals);
  // Local optimisation: the linear least-squares sphere of a consensus set.
  const auto refit = [&y](const SurfacePrimitive&, const std::vector<int>& inliers, SurfacePrimitive& sphere) {
    const FitResult fit = fit_sphere(detail::gather(y, inliers));
    sphere = fit.surface;
    return fit.ok;
  };
  detail::Ransac ransac(y, params.inlier_tolerance / frame.scale, params, 3, refit);

  // Beyond the thesis: the algebraic sphere of all points competes too, so a
  // clean region needs no lucky sample.
  const FitResult all = fit_sphere(y);
  if (all.ok) ransac.offer(all.surface);

  while (ransac.next()) {
    int idx[3];
    ransac.sample(idx);
    const Vec3 x[3] = {y[idx[0]], y[idx[1]], y[idx[2]]};
    const Vec3 nn[3] = {n[idx[0]], n[idx[1]], n[idx[2]]};
    SurfacePrimitive sphere;
    sphere.type = SurfaceType::Sphere;
    if (!normal_lines_meet(x, nn, 3, sphere.point)) continue;
    // Step 3: the mean distance to the three points.
    sphere.radius = ((x[0] - sphere.point).norm() + (x[1] - sphere.point).norm() + (x[2] - sphere.point).norm()) / 3.0;
    ransac.offer(sphere);
  }
  if (!ransac.has_best()) return result;

  result = evaluate_fit(frame.to_world(ransac.best()), points);
  result.iterations = ransac.iterations();
  result.inlier_count = ransac.best_consensus().inliers;
  return result;
}

}  // namespace femorph
