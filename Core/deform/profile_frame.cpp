// The 2D profile of an axisymmetric or prismatic feature (deform_internal.h).
#include "deform/deform_internal.h"

#include <cmath>

namespace femorph {

namespace {
Vec3 any_perpendicular(const Vec3& a) {
  const Vec3 t = std::abs(a.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return a.cross(t).normalized();
}
}  // namespace

ProfileFrame ProfileFrame::prismatic(const Vec3& origin, const Vec3& direction) {
  ProfileFrame f;
  f.axisymmetric = false;
  f.origin = origin;
  f.axis = direction.normalized();
  f.e1 = any_perpendicular(f.axis);
  f.e2 = f.axis.cross(f.e1);
  return f;
}

Vec2 ProfileFrame::to2d(const Vec3& p) const {
  const Vec3 r = p - origin;
  if (axisymmetric) {
    const double z = r.dot(axis);
    return Vec2((r - z * axis).norm(), z);
  }
  return Vec2(r.dot(e1), r.dot(e2));
}

Vec3 ProfileFrame::from2d(const Vec2& q, const Vec3& like) const {
  const Vec3 r = like - origin;
  const double s = r.dot(axis);
  if (axisymmetric) {
    Vec3 radial = r - s * axis;
    const double n = radial.norm();
    radial = n > 1e-300 ? Vec3(radial / n) : any_perpendicular(axis);
    return origin + q.y() * axis + q.x() * radial;
  }
  return origin + s * axis + q.x() * e1 + q.y() * e2;
}

bool profile_line(const ProfileFrame& frame, const SurfacePrimitive& s, ProfileLine& line, double angle_tol,
                  double position_tol) {
  const Vec3& a = frame.axis;
  if (!frame.axisymmetric) {
    if (s.type != SurfaceType::Plane || std::abs(s.axis.dot(a)) > angle_tol) return false;
    line.n = Vec2(s.axis.dot(frame.e1), s.axis.dot(frame.e2));
    const double norm = line.n.norm();
    line.n /= norm;
    line.c = (frame.origin - s.point).dot(s.axis) / norm;
    return true;
  }
  // Distance of a point from the frame's axis line.
  const auto off_axis = [&](const Vec3& p) {
    const Vec3 r = p - frame.origin;
    return (r - r.dot(a) * a).norm();
  };
  switch (s.type) {
    case SurfaceType::Plane: {
      if (s.axis.cross(a).norm() > angle_tol) return false;
      const double na = s.axis.dot(a) > 0 ? 1.0 : -1.0;
      line.n = Vec2(0, na);
      line.c = (frame.origin - s.point).dot(s.axis);
      return true;
    }
    case SurfaceType::Cylinder:
      if (s.axis.cross(a).norm() > angle_tol || off_axis(s.point) > position_tol) return false;
      line.n = Vec2(1, 0);
      line.c = -s.radius;
      return true;
    case SurfaceType::Cone: {
      if (s.axis.cross(a).norm() > angle_tol || off_axis(s.point) > position_tol) return false;
      const double sigma = s.axis.dot(a) > 0 ? 1.0 : -1.0;
      const double z_apex = (s.point - frame.origin).dot(a);
      const double ca = std::cos(s.half_angle), sa = std::sin(s.half_angle);
      line.n = Vec2(ca, -sigma * sa);
      line.c = sigma * sa * z_apex;
      return true;
    }
    default:
      return false;
  }
}

bool offset_intersection(const ProfileLine& a, double da, const ProfileLine& b, double db, Vec2& q) {
  Eigen::Matrix2d m;
  m << a.n.x(), a.n.y(), b.n.x(), b.n.y();
  const double det = m.determinant();
  if (std::abs(det) < 1e-9) return false;
  q = m.inverse() * Vec2(da - a.c, db - b.c);
  return true;
}

}  // namespace femorph
