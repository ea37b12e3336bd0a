#include "geometry/curve_primitive.h"
#include "geometry/fit_primitives.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

namespace femorph {

namespace {

using Eigen::Vector2d;

// A plane section of a cone is a parabola when the plane makes the cone's half
// angle with the axis; CAD builds it exactly, fitted surfaces carry small
// angle errors (radians). Near it the parabola is tried first.
constexpr double kParabolaAngle = 1e-2;
// A plane parallel to a cylinder's axis cuts it in lines, not an ellipse.
constexpr double kParallelCosine = 1e-6;

// Which conic the plane of the curve (unit normal N) cuts from the surfaces
// (thesis 2.4.6 step 3 (b)): Ellipse, Parabola or Hyperbola when one surface
// is a plane and the other a cylinder or a cone, else Unclassified (only
// circles and lines are recognised there).
CurveType expected_section(const SurfacePrimitive& a, const SurfacePrimitive& b, const Vec3& N, bool closed) {
  const SurfacePrimitive* other = nullptr;
  if (a.type == SurfaceType::Plane) other = &b;
  if (b.type == SurfaceType::Plane) other = &a;
  if (other == nullptr) return CurveType::Unclassified;
  const double sine = std::min(1.0, std::abs(N.dot(other->axis.normalized())));  // sin of the plane-axis angle
  if (other->type == SurfaceType::Cylinder) return sine > kParallelCosine ? CurveType::Ellipse : CurveType::Unclassified;
  if (other->type != SurfaceType::Cone) return CurveType::Unclassified;
  if (closed) return CurveType::Ellipse;  // the only closed section but the circle
  const double beta = std::asin(sine);
  if (std::abs(beta - other->half_angle) <= kParabolaAngle) return CurveType::Parabola;
  return beta > other->half_angle ? CurveType::Ellipse : CurveType::Hyperbola;
}

// General conic z^T M z + l . z + f = 0 fitted to centred, scaled plane points
// by least squares with unit coefficient vector (smallest singular vector of
// the design matrix, through its R factor).
struct Conic {
  Eigen::Matrix2d M;
  Vector2d l;
  double f;
  double value(const Vector2d& z) const { return z.dot(M * z) + l.dot(z) + f; }
  // Sampson's first-order distance |Q| / |grad Q|.
  double distance(const Vector2d& z) const {
    const double gradient = (2 * M * z + l).norm();
    return gradient > 0 ? std::abs(value(z)) / gradient : std::abs(value(z));
  }
};

bool fit_conic(const std::vector<Vector2d>& z, Conic& conic) {
  const int n = static_cast<int>(z.size());
  if (n < 5) return false;
  // Five points fix a conic; a zero row pads the design matrix to 6 rows.
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(std::max(n, 6), 6);
  for (int i = 0; i < n; ++i) {
    const double x = z[i].x(), y = z[i].y();
    D.row(i) << x * x, x * y, y * y, x, y, 1.0;
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(D);
  const Eigen::Matrix<double, 6, 6> R = qr.matrixQR().topRows<6>().triangularView<Eigen::Upper>();
  const Eigen::JacobiSVD<Eigen::Matrix<double, 6, 6>> svd(R, Eigen::ComputeFullV);
  const Eigen::Matrix<double, 6, 1> c = svd.matrixV().col(5);
  conic.M << c(0), 0.5 * c(1), 0.5 * c(1), c(2);
  conic.l << c(3), c(4);
  conic.f = c(5);
  return c.allFinite();
}

// The plane of the curve and 2D coordinates in it (centred, scaled).
struct PlaneFrame {
  Vec3 origin, normal, u, v;
  double scale = 1;
  Vector2d to_plane(const Vec3& p) const { return Vector2d((p - origin).dot(u), (p - origin).dot(v)) / scale; }
  Vec3 to_space(const Vector2d& z) const { return origin + scale * (z.x() * u + z.y() * v); }
  Vec3 direction(const Vector2d& d) const { return (d.x() * u + d.y() * v).normalized(); }
};

// Largest distance of the points to the curve: out of the plane and, in it,
// `in_plane(z)` (in plane units).
template <class InPlane>
double largest_distance(const std::vector<Vec3>& points, const PlaneFrame& frame, InPlane in_plane) {
  double largest = 0;
  for (const Vec3& p : points) {
    const double off = (p - frame.origin).dot(frame.normal);
    const double in = frame.scale * in_plane(frame.to_plane(p));
    largest = std::max(largest, std::hypot(off, in));
  }
  return largest;
}

// Ellipse or hyperbola parameters from the conic: centre c and
// (z - c)^T M (z - c) = k.
bool central_conic(const Conic& conic, const std::vector<Vector2d>& z, CurveType type, const PlaneFrame& frame,
                   CurvePrimitive& curve) {
  const double det = conic.M.determinant();
  if (!(std::abs(det) > 0)) return false;
  const Vector2d center = -0.5 * conic.M.inverse() * conic.l;
  const double k = -0.5 * conic.l.dot(center) - conic.f;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(conic.M);
  const Vector2d lambda = eigen.eigenvalues() / k;  // (z - c)^T (M / k) (z - c) = 1
  if (!lambda.allFinite()) return false;
  // Dividing by k may reverse the eigenvalues' order.
  const int small = lambda(0) < lambda(1) ? 0 : 1, large = 1 - small;
  if (type == CurveType::Ellipse) {
    if (!(lambda(small) > 0)) return false;
    // The smaller eigenvalue belongs to the major axis.
    curve.center = frame.to_space(center);
    curve.direction = frame.direction(eigen.eigenvectors().col(small));
    curve.radius = frame.scale / std::sqrt(lambda(small));
    curve.minor_radius = frame.scale / std::sqrt(lambda(large));
    return true;
  }
  // Hyperbola: the transverse axis has the positive eigenvalue.
  if (!(lambda(small) < 0 && lambda(large) > 0)) return false;
  Vector2d transverse = eigen.eigenvectors().col(large);
  const double a = 1 / std::sqrt(lambda(large));
  Vector2d mean = Vector2d::Zero();
  for (const Vector2d& p : z) mean += p;
  if ((mean / static_cast<double>(z.size()) - center).dot(transverse) < 0) transverse = -transverse;  // the branch
  curve.center = frame.to_space(center + a * transverse);  // vertex of the branch
  curve.direction = frame.direction(transverse);
  curve.radius = frame.scale * a;
  curve.minor_radius = frame.scale / std::sqrt(-lambda(small));
  return true;
}

// Parabola x' = k2 y'^2 + k1 y' + k0 in the frame of its axis (the conic's
// direction of vanishing curvature), by linear least squares.
bool fit_parabola(const Conic& conic, const std::vector<Vector2d>& z, const std::vector<Vec3>& points,
                  const PlaneFrame& frame, CurvePrimitive& curve, double& max_abs) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(conic.M);
  const int small = std::abs(eigen.eigenvalues()(0)) < std::abs(eigen.eigenvalues()(1)) ? 0 : 1;
  const Vector2d axis = eigen.eigenvectors().col(small);
  const Vector2d across(-axis.y(), axis.x());
  const int n = static_cast<int>(z.size());
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    const double t = z[i].dot(across);
    A.row(i) << t * t, t, 1.0;
    b(i) = z[i].dot(axis);
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 3) return false;
  const Eigen::Vector3d k = qr.solve(b);
  if (!(std::abs(k(0)) > 0)) return false;
  const double t_vertex = -k(1) / (2 * k(0));
  const double s_vertex = k(2) - k(1) * k(1) / (4 * k(0));
  curve.center = frame.to_space(s_vertex * axis + t_vertex * across);
  curve.direction = frame.direction(k(0) > 0 ? axis : Vector2d(-axis));
  curve.radius = frame.scale / (4 * std::abs(k(0)));  // focal length
  curve.minor_radius = 0;
  max_abs = largest_distance(points, frame, [&](const Vector2d& p) {
    const double t = p.dot(across);
    const double residual = p.dot(axis) - (k(0) * t * t + k(1) * t + k(2));
    return std::abs(residual) / std::hypot(1.0, 2 * k(0) * t + k(1));
  });
  return std::isfinite(max_abs);
}

}  // namespace

CurveFit classify_boundary_curve(const std::vector<Vec3>& points, bool closed, double tolerance,
                                 const SurfacePrimitive& a, const SurfacePrimitive& b) {
  CurveFit fit;
  const int n = static_cast<int>(points.size());
  if (n == 0) return fit;
  if (!closed) {
    fit.curve.start = points.front();
    fit.curve.end = points.back();
  } else {
    fit.curve.start = fit.curve.end = points.front();
  }
  if (n < 2 || (closed && n < 3)) return fit;

  // Step 1 (open segments): the total least squares line.
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : points) centroid += p;
  centroid /= n;
  if (!closed) {
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const Vec3& p : points) scatter += (p - centroid) * (p - centroid).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
    Vec3 direction = eigen.eigenvectors().col(2);
    if (direction.dot(points.back() - points.front()) < 0) direction = -direction;
    double largest = 0;
    for (const Vec3& p : points) largest = std::max(largest, (p - centroid).cross(direction).norm());
    if (largest <= tolerance) {
      fit.curve.type = CurveType::Line;
      fit.curve.direction = direction;
      fit.max_abs = largest;
      fit.ok = true;
      return fit;
    }
  }

  // Step 2: a plane curve?
  const FitResult plane = fit_plane(points);
  if (!plane.ok) return fit;  // a closed loop on a line: degenerate
  fit.ok = true;
  if (plane.max_abs > tolerance) return fit;  // non-planar: unclassified
  PlaneFrame frame;
  frame.origin = plane.surface.point;
  // Orient the normal by the right-hand rule along the chain, so that an arc
  // runs counter-clockwise about it from start to end.
  Vec3 swept = Vec3::Zero();
  for (int i = 0; i + 1 < n; ++i) swept += (points[i] - centroid).cross(points[i + 1] - centroid);
  if (closed) swept += (points[n - 1] - centroid).cross(points[0] - centroid);
  frame.normal = swept.dot(plane.surface.axis) < 0 ? Vec3(-plane.surface.axis) : plane.surface.axis;
  frame.u = frame.normal.unitOrthogonal();
  frame.v = frame.normal.cross(frame.u);
  double scale = 0;
  for (const Vec3& p : points) scale += (p - centroid).squaredNorm();
  frame.scale = std::sqrt(scale / n);
  std::vector<Vector2d> z(n);
  for (int i = 0; i < n; ++i) z[i] = frame.to_plane(points[i]);
  fit.curve.normal = frame.normal;

  // Step 3 (a) and the circles of (b): a least-squares circle in the plane
  // (thesis: RANSAC; the chain has no outliers, so all points are used).
  const Circle2dFit circle = fit_circle_2d(z);
  if (circle.ok) {
    const double largest = largest_distance(
        points, frame, [&](const Vector2d& p) { return std::abs((p - circle.center).norm() - circle.radius); });
    if (largest <= tolerance) {
      fit.curve.type = closed ? CurveType::Circle : CurveType::CircularArc;
      fit.curve.center = frame.to_space(circle.center);
      fit.curve.radius = frame.scale * circle.radius;
      fit.max_abs = largest;
      return fit;
    }
  }

  // Step 3 (b): other conics by the type of the surfaces' intersection, then
  // fitted; the conic's own discriminant is the fallback when the expected
  // type does not fit (angles of fitted surfaces near the parabola limit).
  const CurveType expected = expected_section(a, b, frame.normal, closed);
  if (expected == CurveType::Unclassified) return fit;
  const bool cone_section = a.type == SurfaceType::Cone || b.type == SurfaceType::Cone;
  Conic conic;
  if (!fit_conic(z, conic)) return fit;
  const CurveType discriminant = conic.M.determinant() > 0 ? CurveType::Ellipse : CurveType::Hyperbola;
  std::vector<CurveType> order = {expected};
  if (cone_section && !closed && expected != CurveType::Parabola) order.push_back(CurveType::Parabola);
  if (cone_section && !(closed && discriminant == CurveType::Hyperbola)) order.push_back(discriminant);
  for (const CurveType type : order) {
    CurvePrimitive curve = fit.curve;
    double largest = 0;
    if (type == CurveType::Parabola) {
      if (!fit_parabola(conic, z, points, frame, curve, largest)) continue;
    } else {
      if (!central_conic(conic, z, type, frame, curve)) continue;
      largest = largest_distance(points, frame, [&](const Vector2d& p) { return conic.distance(p); });
    }
    if (!(largest <= tolerance)) continue;
    curve.type = type == CurveType::Ellipse && !closed ? CurveType::EllipticArc : type;
    fit.curve = curve;
    fit.max_abs = largest;
    return fit;
  }
  return fit;
}

}  // namespace femorph
