#include "geometry/fit_primitives.h"

#include <Eigen/Eigenvalues>

namespace femorph {

FitResult fit_plane(const std::vector<Vec3>& points, const std::vector<Vec3>* normals) {
  FitResult result;
  if (points.size() < 3) return result;
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) scatter += (p - centroid) * (p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  // Collinear (or coincident) points span no plane.
  if (!(eigen.eigenvalues()(1) > 1e-14 * eigen.eigenvalues()(2))) return result;
  Vec3 normal = eigen.eigenvectors().col(0);
  if (normals != nullptr && !normals->empty()) {
    Vec3 mean = Vec3::Zero();
    for (const Vec3& n : *normals) mean += n;
    if (normal.dot(mean) < 0) normal = -normal;
  } else {
    // No reference: make the sign reproducible (largest component positive).
    Eigen::Index k;
    normal.cwiseAbs().maxCoeff(&k);
    if (normal(k) < 0) normal = -normal;
  }
  SurfacePrimitive plane;
  plane.type = SurfaceType::Plane;
  plane.point = centroid;
  plane.axis = normal;
  result = evaluate_fit(plane, points);
  return result;
}

}  // namespace femorph
