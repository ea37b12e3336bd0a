#include "geometry/surface_primitive.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace femorph {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// p in the frame of an axis through `origin` along unit `axis`: height h
// along the axis, distance rho from it and the unit radial direction e (any
// perpendicular unit vector when p is on the axis, where it is not unique).
struct AxisFrame {
  double h = 0;
  double rho = 0;
  Vec3 e = Vec3::Zero();
};

AxisFrame axis_frame(const Vec3& origin, const Vec3& axis, const Vec3& p) {
  AxisFrame f;
  const Vec3 v = p - origin;
  f.h = v.dot(axis);
  const Vec3 radial = v - f.h * axis;
  f.rho = radial.norm();
  f.e = f.rho > 0 ? Vec3(radial / f.rho) : Vec3(axis.unitOrthogonal());
  return f;
}


// Torus: the point of the core circle nearest to p and the unit direction from
// it to p (outward in the meridian plane when p is on the core circle).
void torus_core(const SurfacePrimitive& s, const Vec3& p, Vec3& core, Vec3& dir) {
  const AxisFrame f = axis_frame(s.point, s.axis, p);
  core = s.point + s.radius * f.e;
  const Vec3 d = p - core;
  const double n = d.norm();
  dir = n > 0 ? Vec3(d / n) : f.e;
}

}  // namespace

const char* to_string(SurfaceType type) {
  switch (type) {
    case SurfaceType::Plane: return "plane";
    case SurfaceType::Cylinder: return "cylinder";
    case SurfaceType::Cone: return "cone";
    case SurfaceType::Sphere: return "sphere";
    case SurfaceType::Torus: return "torus";
    case SurfaceType::Unknown: break;
  }
  return "unknown";
}

double signed_distance(const SurfacePrimitive& s, const Vec3& p) {
  switch (s.type) {
    case SurfaceType::Plane:
      return (p - s.point).dot(s.axis);
    case SurfaceType::Cylinder:
      return axis_frame(s.point, s.axis, p).rho - s.radius;
    case SurfaceType::Cone: {
      // In the meridian half-plane (rho, h) the nappe is the ray from the apex
      // along (sin a, cos a); its outward normal is (cos a, -sin a). A point
      // whose projection on the ray falls behind the apex is closest to it.
      const AxisFrame f = axis_frame(s.point, s.axis, p);
      const double sn = std::sin(s.half_angle), c = std::cos(s.half_angle);
      if (f.rho * sn + f.h * c < 0) return (p - s.point).norm();  // behind the apex: outside
      return f.rho * c - f.h * sn;
    }
    case SurfaceType::Sphere:
      return (p - s.point).norm() - s.radius;
    case SurfaceType::Torus: {
      // Distance to the core circle minus r. Exact for a ring torus (R > r);
      // for R <= r it stays finite and continuous (a distance bound).
      const AxisFrame f = axis_frame(s.point, s.axis, p);
      const double dr = f.rho - s.radius;
      return std::sqrt(dr * dr + f.h * f.h) - s.minor_radius;
    }
    case SurfaceType::Unknown: break;
  }
  return kNaN;
}

Vec3 closest_point(const SurfacePrimitive& s, const Vec3& p) {
  switch (s.type) {
    case SurfaceType::Plane:
      return p - signed_distance(s, p) * s.axis;
    case SurfaceType::Cylinder: {
      const AxisFrame f = axis_frame(s.point, s.axis, p);
      return s.point + f.h * s.axis + s.radius * f.e;
    }
    case SurfaceType::Cone: {
      const AxisFrame f = axis_frame(s.point, s.axis, p);
      const double sn = std::sin(s.half_angle), c = std::cos(s.half_angle);
      const double t = f.rho * sn + f.h * c;  // along the ray from the apex
      if (t < 0) return s.point;
      return s.point + t * (sn * f.e + c * s.axis);
    }
    case SurfaceType::Sphere: {
      const Vec3 d = p - s.point;
      const double n = d.norm();
      return s.point + s.radius * (n > 0 ? Vec3(d / n) : Vec3::UnitX());
    }
    case SurfaceType::Torus: {
      Vec3 core, dir;
      torus_core(s, p, core, dir);
      return core + s.minor_radius * dir;
    }
    case SurfaceType::Unknown: break;
  }
  return p;
}

Vec3 surface_normal(const SurfacePrimitive& s, const Vec3& p) {
  switch (s.type) {
    case SurfaceType::Plane:
      return s.axis;
    case SurfaceType::Cylinder:
      return axis_frame(s.point, s.axis, p).e;
    case SurfaceType::Cone: {
      const AxisFrame f = axis_frame(s.point, s.axis, p);
      const double sn = std::sin(s.half_angle), c = std::cos(s.half_angle);
      const Vec3 side = c * f.e - sn * s.axis;
      if (f.rho * sn + f.h * c >= 0) return side;
      // Behind the apex the closest point is the apex itself: the direction
      // to p keeps p = closest + d * normal.
      const Vec3 d = p - s.point;
      const double n = d.norm();
      return n > 0 ? Vec3(d / n) : side;
    }
    case SurfaceType::Sphere: {
      const Vec3 d = p - s.point;
      const double n = d.norm();
      return n > 0 ? Vec3(d / n) : Vec3::UnitX();
    }
    case SurfaceType::Torus: {
      Vec3 core, dir;
      torus_core(s, p, core, dir);
      return dir;
    }
    case SurfaceType::Unknown: break;
  }
  return Vec3::Zero();
}

bool same_surface(const SurfacePrimitive& a, const SurfacePrimitive& b, double rel, double scale, double angle) {
  if (a.type != b.type || a.type == SurfaceType::Unknown) return false;
  const double position_tolerance = rel * scale;
  const auto same_length = [rel](double x, double y) {
    return std::abs(x - y) <= rel * std::max(std::abs(x), std::abs(y));
  };
  // Angle between lines (sign ignored), by the sine so that tiny angles keep
  // their precision.
  const double axis_angle = std::atan2(a.axis.cross(b.axis).norm(), std::abs(a.axis.dot(b.axis)));
  const auto distance_to_line = [](const Vec3& p, const Vec3& origin, const Vec3& dir) {
    return (p - origin).cross(dir).norm();
  };
  switch (a.type) {
    case SurfaceType::Plane:
      return axis_angle <= angle && std::abs((b.point - a.point).dot(a.axis)) <= position_tolerance &&
             std::abs((a.point - b.point).dot(b.axis)) <= position_tolerance;
    case SurfaceType::Cylinder:
      return axis_angle <= angle && same_length(a.radius, b.radius) &&
             distance_to_line(b.point, a.point, a.axis) <= position_tolerance &&
             distance_to_line(a.point, b.point, b.axis) <= position_tolerance;
    case SurfaceType::Cone:
      // The axis sign picks the nappe, so here it is not ignored.
      return a.axis.dot(b.axis) > 0 && axis_angle <= angle && std::abs(a.half_angle - b.half_angle) <= angle &&
             (a.point - b.point).norm() <= position_tolerance;
    case SurfaceType::Sphere:
      return same_length(a.radius, b.radius) && (a.point - b.point).norm() <= position_tolerance;
    case SurfaceType::Torus:
      return axis_angle <= angle && same_length(a.radius, b.radius) && same_length(a.minor_radius, b.minor_radius) &&
             (a.point - b.point).norm() <= position_tolerance;
    case SurfaceType::Unknown: break;
  }
  return false;
}

}  // namespace femorph
