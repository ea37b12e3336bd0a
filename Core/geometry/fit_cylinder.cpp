#include "geometry/fit_primitives.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>

namespace femorph {

FitResult fit_cylinder(const std::vector<Vec3>& points, const std::vector<Vec3>& normals) {
  FitResult result;
  const std::size_t n = points.size();
  if (n < 5 || normals.size() != n) return result;

  // Fig. 2.9(a): the unit normals on the Gaussian sphere lie on a great
  // circle, whose plane has the axis as normal. A cylinder's plane passes the
  // sphere's centre (2.4.3.3), so it is fitted through the centre: this keeps
  // the axis well determined on narrow strips, where the normals' own spread
  // is small.
  Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
  for (const Vec3& normal : normals) {
    const double length = normal.norm();
    if (length > 0) tensor += (normal / length) * (normal / length).transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(tensor);
  // All normals parallel: a plane, no axis.
  if (!(eigen.eigenvalues()(1) > 1e-12 * eigen.eigenvalues()(2))) return result;
  Vec3 axis = eigen.eigenvectors().col(0);
  Eigen::Index k;
  axis.cwiseAbs().maxCoeff(&k);
  if (axis(k) < 0) axis = -axis;  // reproducible sign
  const Vec3 u = axis.unitOrthogonal();
  const Vec3 v = axis.cross(u);

  // Fig. 2.9(b, c): project onto the plane normal to the axis, fit a circle.
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : points) centroid += p;
  centroid /= static_cast<double>(n);
  std::vector<Eigen::Vector2d> projected(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = points[i] - centroid;
    projected[i] = Eigen::Vector2d(d.dot(u), d.dot(v));
  }
  const Circle2dFit circle = fit_circle_2d(projected);
  if (!circle.ok) return result;

  SurfacePrimitive cylinder;
  cylinder.type = SurfaceType::Cylinder;
  cylinder.axis = axis;
  const Vec3 on_axis = centroid + circle.center.x() * u + circle.center.y() * v;
  cylinder.point = on_axis - on_axis.dot(axis) * axis;  // closest to the origin
  cylinder.radius = circle.radius;
  return evaluate_fit(cylinder, points);
}

double gaussian_sphere_plane_offset(const std::vector<Vec3>& normals) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<Vec3> unit;
  unit.reserve(normals.size());
  for (const Vec3& normal : normals) {
    const double length = normal.norm();
    if (length > 0) unit.push_back(normal / length);
  }
  if (unit.size() < 3) return kNaN;
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : unit) centroid += p;
  centroid /= static_cast<double>(unit.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Vec3& p : unit) scatter += (p - centroid) * (p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  // All normals (nearly) equal: no plane through them.
  if (!(eigen.eigenvalues()(2) > 1e-24)) return kNaN;
  return std::abs(centroid.dot(eigen.eigenvectors().col(0)));
}

}  // namespace femorph
