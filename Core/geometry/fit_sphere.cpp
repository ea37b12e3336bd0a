#include "geometry/fit_primitives.h"

#include <Eigen/QR>

#include <cmath>

namespace femorph {

FitResult fit_sphere(const std::vector<Vec3>& points) {
  FitResult result;
  const int n = static_cast<int>(points.size());
  if (n < 4) return result;
  // |x|^2 + D.x + F = 0 is linear in (D, F); centring and scaling keep it
  // well conditioned whatever the units.
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= n;
  double scale = 0;
  for (const Vec3& p : points) scale += (p - mean).squaredNorm();
  scale = std::sqrt(scale / n);
  if (!(scale > 0)) return result;
  Eigen::MatrixXd A(n, 4);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 z = (points[i] - mean) / scale;
    A.row(i) << z.x(), z.y(), z.z(), 1.0;
    b(i) = -z.squaredNorm();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 4) return result;  // coplanar points: no unique sphere
  const Eigen::Vector4d x = qr.solve(b);
  const Vec3 center = -0.5 * x.head<3>();
  const double r2 = center.squaredNorm() - x(3);
  if (!(r2 > 0)) return result;
  SurfacePrimitive sphere;
  sphere.type = SurfaceType::Sphere;
  sphere.point = mean + scale * center;
  sphere.radius = scale * std::sqrt(r2);
  return evaluate_fit(sphere, points);
}

}  // namespace femorph
