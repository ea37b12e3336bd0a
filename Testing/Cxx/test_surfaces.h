// Points and normals sampled exactly (to rounding) from analytic surfaces in
// general position, for the geometry tests: random frames, any scale, parts
// of surfaces (strips, sectors, fillets), noise and mesh-like normal errors.
#pragma once

#include "geometry/surface_primitive.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

namespace femorph {
namespace test_surfaces {


using Rng = std::mt19937_64;

struct Sample {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;   // unit, outward (signed_distance > 0 side)
  std::vector<Vec3> max_dirs;  // unit principal direction of the largest |curvature| (tori)
};

inline double uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline Vec3 random_unit(Rng& rng) {
  std::normal_distribution<double> g(0, 1);
  for (;;) {
    const Vec3 v(g(rng), g(rng), g(rng));
    if (v.norm() > 1e-3) return v.normalized();
  }
}

inline Vec3 random_point(Rng& rng, double half_size) {
  return Vec3(uniform(rng, -half_size, half_size), uniform(rng, -half_size, half_size),
              uniform(rng, -half_size, half_size));
}

/// Unit u, v perpendicular to unit a, right-handed.
inline void frame_of(const Vec3& a, Vec3& u, Vec3& v) {
  u = a.unitOrthogonal();
  v = a.cross(u);
}

/// Angle between two lines (sign of the directions ignored).
inline double line_angle(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), std::abs(a.dot(b)));
}

/// Distance of p from the line through o along unit d.
inline double line_distance(const Vec3& p, const Vec3& o, const Vec3& d) { return (p - o).cross(d).norm(); }

inline double relative_error(double value, double truth) { return std::abs(value - truth) / std::abs(truth); }

inline SurfacePrimitive plane(const Vec3& point, const Vec3& normal) {
  SurfacePrimitive s;
  s.type = SurfaceType::Plane;
  s.point = point;
  s.axis = normal.normalized();
  return s;
}

inline SurfacePrimitive cylinder(const Vec3& on_axis, const Vec3& axis, double radius) {
  SurfacePrimitive s;
  s.type = SurfaceType::Cylinder;
  s.axis = axis.normalized();
  s.point = on_axis - on_axis.dot(s.axis) * s.axis;
  s.radius = radius;
  return s;
}

inline SurfacePrimitive cone(const Vec3& apex, const Vec3& axis, double half_angle) {
  SurfacePrimitive s;
  s.type = SurfaceType::Cone;
  s.point = apex;
  s.axis = axis.normalized();
  s.half_angle = half_angle;
  return s;
}

inline SurfacePrimitive sphere(const Vec3& center, double radius) {
  SurfacePrimitive s;
  s.type = SurfaceType::Sphere;
  s.point = center;
  s.radius = radius;
  return s;
}

inline SurfacePrimitive torus(const Vec3& center, const Vec3& axis, double major, double minor) {
  SurfacePrimitive s;
  s.type = SurfaceType::Torus;
  s.point = center;
  s.axis = axis.normalized();
  s.radius = major;
  s.minor_radius = minor;
  return s;
}

/// Plane: a square of half side `half` around s.point.
inline Sample sample_plane(const SurfacePrimitive& s, double half, int n, Rng& rng) {
  Sample out;
  Vec3 u, v;
  frame_of(s.axis, u, v);
  for (int i = 0; i < n; ++i) {
    out.points.push_back(s.point + uniform(rng, -half, half) * u + uniform(rng, -half, half) * v);
    out.normals.push_back(s.axis);
    out.max_dirs.push_back(u);
  }
  return out;
}

/// Cylinder: angles [t0, t1] around the axis, heights [h0, h1] from s.point.
inline Sample sample_cylinder(const SurfacePrimitive& s, double t0, double t1, double h0, double h1, int n, Rng& rng) {
  Sample out;
  Vec3 u, v;
  frame_of(s.axis, u, v);
  for (int i = 0; i < n; ++i) {
    const double t = uniform(rng, t0, t1), h = uniform(rng, h0, h1);
    const Vec3 e = std::cos(t) * u + std::sin(t) * v;
    out.points.push_back(s.point + h * s.axis + s.radius * e);
    out.normals.push_back(e);
    out.max_dirs.push_back(s.axis.cross(e));
  }
  return out;
}

/// Cone: angles [t0, t1] around the axis, distances [l0, l1] from the apex
/// along the generatrix.
inline Sample sample_cone(const SurfacePrimitive& s, double t0, double t1, double l0, double l1, int n, Rng& rng) {
  Sample out;
  Vec3 u, v;
  frame_of(s.axis, u, v);
  const double sa = std::sin(s.half_angle), ca = std::cos(s.half_angle);
  for (int i = 0; i < n; ++i) {
    const double t = uniform(rng, t0, t1), l = uniform(rng, l0, l1);
    const Vec3 e = std::cos(t) * u + std::sin(t) * v;
    out.points.push_back(s.point + l * (sa * e + ca * s.axis));
    out.normals.push_back(ca * e - sa * s.axis);
    out.max_dirs.push_back(s.axis.cross(e));
  }
  return out;
}

/// Sphere: polar angles [p0, p1] from the axis `pole`, all around it.
inline Sample sample_sphere(const SurfacePrimitive& s, const Vec3& pole, double p0, double p1, int n, Rng& rng) {
  Sample out;
  Vec3 u, v;
  frame_of(pole, u, v);
  for (int i = 0; i < n; ++i) {
    const double t = uniform(rng, 0, 2 * kPi);
    const double c = uniform(rng, std::cos(p1), std::cos(p0));  // uniform on the zone
    const double sn = std::sqrt(std::max(0.0, 1 - c * c));
    const Vec3 e = c * pole + sn * (std::cos(t) * u + std::sin(t) * v);
    out.points.push_back(s.point + s.radius * e);
    out.normals.push_back(e);
    out.max_dirs.push_back(e.unitOrthogonal());
  }
  return out;
}

/// Torus: angles [t0, t1] around the axis, [p0, p1] around the tube (0: the
/// outer equator, pi/2: the top).
inline Sample sample_torus(const SurfacePrimitive& s, double t0, double t1, double p0, double p1, int n, Rng& rng) {
  Sample out;
  Vec3 u, v;
  frame_of(s.axis, u, v);
  for (int i = 0; i < n; ++i) {
    const double t = uniform(rng, t0, t1), p = uniform(rng, p0, p1);
    const Vec3 e = std::cos(t) * u + std::sin(t) * v;
    const Vec3 normal = std::cos(p) * e + std::sin(p) * s.axis;
    out.points.push_back(s.point + s.radius * e + s.minor_radius * normal);
    out.normals.push_back(normal);
    // Meridian direction: curvature 1/r, the largest on a ring torus.
    out.max_dirs.push_back(-std::sin(p) * e + std::cos(p) * s.axis);
  }
  return out;
}

/// Gaussian noise of deviation sigma on every coordinate.
inline void add_noise(Sample& sample, double sigma, Rng& rng) {
  std::normal_distribution<double> g(0, sigma);
  for (Vec3& p : sample.points) p += Vec3(g(rng), g(rng), g(rng));
}

/// Turns every normal (and principal direction) by a random angle up to
/// `angle`, as a mesh's vertex normals err from the surface's.
inline void perturb_normals(Sample& sample, double angle, Rng& rng) {
  const auto turn = [&](Vec3& n) {
    const Vec3 k = n.cross(random_unit(rng)).normalized();
    n = Eigen::AngleAxisd(uniform(rng, 0, angle), k) * n;
  };
  for (Vec3& n : sample.normals) turn(n);
  for (Vec3& d : sample.max_dirs) turn(d);
}

/// Flips the sign of every other normal (normals of a mesh may point either way).
inline void flip_some_normals(Sample& sample) {
  for (std::size_t i = 0; i < sample.normals.size(); i += 2) sample.normals[i] = -sample.normals[i];
}

inline void append(Sample& to, const Sample& from) {
  to.points.insert(to.points.end(), from.points.begin(), from.points.end());
  to.normals.insert(to.normals.end(), from.normals.begin(), from.normals.end());
  to.max_dirs.insert(to.max_dirs.end(), from.max_dirs.begin(), from.max_dirs.end());
}

}  // namespace test_surfaces
}  // namespace femorph
