#include "geometry/surface_chart.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace femorph {

namespace {

// Unit direction of p's offset from the axis through o along a (any normal of
// a on the axis).
Vec3 radial(const Vec3& o, const Vec3& a, const Vec3& p) {
  const Vec3 v = p - o;
  const Vec3 r = v - v.dot(a) * a;
  const double n = r.norm();
  return n > 0 ? Vec3(r / n) : Vec3(a.unitOrthogonal());
}

}  // namespace

SurfaceChart make_surface_chart(const SurfacePrimitive& s, const Vec3& centre) {
  SurfaceChart c;
  c.surface = s;
  const Vec3 a = s.axis.norm() > 0 ? Vec3(s.axis.normalized()) : Vec3::UnitZ();
  switch (s.type) {
    case SurfaceType::Plane:
      c.origin = centre - (centre - s.point).dot(a) * a;
      c.e3 = a;
      c.e1 = a.unitOrthogonal();
      c.e2 = a.cross(c.e1);
      break;
    case SurfaceType::Cylinder:
    case SurfaceType::Cone:
    case SurfaceType::Torus:
      c.origin = s.point;
      c.e3 = a;
      c.e1 = radial(s.point, a, centre);
      c.e2 = a.cross(c.e1);
      if (s.type == SurfaceType::Cylinder) c.period = Vec2(2 * kPi * s.radius, 0);
      if (s.type == SurfaceType::Torus) {
        c.period = Vec2(2 * kPi * s.radius, 2 * kPi * s.minor_radius);
        const Vec3 d = centre - (s.point + s.radius * c.e1);
        c.poloidal0 = std::atan2(d.dot(a), d.dot(c.e1));
      }
      break;
    case SurfaceType::Sphere: {
      c.origin = s.point;
      c.e1 = (centre - s.point).norm() > 0 ? Vec3((centre - s.point).normalized()) : Vec3::UnitX();
      c.e3 = c.e1.unitOrthogonal();  // the pole
      c.e2 = c.e3.cross(c.e1);
      c.period = Vec2(2 * kPi * s.radius, 0);
      break;
    }
    case SurfaceType::Unknown:
      break;
  }
  return c;
}

Vec2 SurfaceChart::map(const Vec3& p) const {
  const Vec3 v = p - origin;
  switch (surface.type) {
    case SurfaceType::Plane:
      return Vec2(v.dot(e1), v.dot(e2));
    case SurfaceType::Cylinder:
      return Vec2(surface.radius * std::atan2(v.dot(e2), v.dot(e1)), v.dot(e3));
    case SurfaceType::Cone: {
      // Slant distance along the generator through p's meridian, and the
      // development angle: the cone's angle times sin(half angle).
      const double h = v.dot(e3);
      const double rho = (v - h * e3).norm();
      const double sn = std::sin(surface.half_angle);
      const double slant = h * std::cos(surface.half_angle) + rho * sn;
      const double psi = std::atan2(v.dot(e2), v.dot(e1)) * sn;
      return Vec2(slant * std::cos(psi), slant * std::sin(psi));
    }
    case SurfaceType::Sphere: {
      const double n = v.norm();
      if (n == 0) return Vec2::Zero();
      const Vec3 d = v / n;
      return surface.radius * Vec2(std::atan2(d.dot(e2), d.dot(e1)), std::asin(std::max(-1.0, std::min(1.0, d.dot(e3)))));
    }
    case SurfaceType::Torus: {
      const double phi = std::atan2(v.dot(e2), v.dot(e1));
      const Vec3 rdir = std::cos(phi) * e1 + std::sin(phi) * e2;
      const Vec3 d = v - surface.radius * rdir;
      double psi = std::atan2(d.dot(e3), d.dot(rdir)) - poloidal0;
      if (psi > kPi) psi -= 2 * kPi;
      if (psi <= -kPi) psi += 2 * kPi;
      return Vec2(surface.radius * phi, surface.minor_radius * psi);
    }
    case SurfaceType::Unknown:
      break;
  }
  return Vec2::Zero();
}

Vec3 SurfaceChart::lift(const Vec2& q) const {
  switch (surface.type) {
    case SurfaceType::Plane:
      return origin + q.x() * e1 + q.y() * e2;
    case SurfaceType::Cylinder: {
      const double t = q.x() / surface.radius;
      return origin + q.y() * e3 + surface.radius * (std::cos(t) * e1 + std::sin(t) * e2);
    }
    case SurfaceType::Cone: {
      const double slant = q.norm();
      const double sn = std::sin(surface.half_angle);
      const double phi = std::atan2(q.y(), q.x()) / sn;
      return origin + slant * (std::cos(surface.half_angle) * e3 + sn * (std::cos(phi) * e1 + std::sin(phi) * e2));
    }
    case SurfaceType::Sphere: {
      const double lon = q.x() / surface.radius, lat = q.y() / surface.radius;
      return origin + surface.radius * (std::cos(lat) * (std::cos(lon) * e1 + std::sin(lon) * e2) + std::sin(lat) * e3);
    }
    case SurfaceType::Torus: {
      const double phi = q.x() / surface.radius, psi = q.y() / surface.minor_radius + poloidal0;
      const Vec3 rdir = std::cos(phi) * e1 + std::sin(phi) * e2;
      return origin + surface.radius * rdir + surface.minor_radius * (std::cos(psi) * rdir + std::sin(psi) * e3);
    }
    case SurfaceType::Unknown:
      break;
  }
  return origin;
}

Vec2 SurfaceChart::unwrap(const Vec2& q, const Vec2& near) const {
  Vec2 r = q;
  for (int i = 0; i < 2; ++i)
    if (period[i] > 0) r[i] -= period[i] * std::round((r[i] - near[i]) / period[i]);
  return r;
}

double distance_to_triangle_2d(const Vec2& q, const Vec2& a, const Vec2& b, const Vec2& c) {
  const auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
  const double area = cross(b - a, c - a);
  const double s0 = cross(b - q, c - q), s1 = cross(c - q, a - q), s2 = cross(a - q, b - q);
  if (area != 0 && ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0))) return 0;
  const auto seg = [&](const Vec2& u, const Vec2& v) {
    const Vec2 d = v - u;
    const double l2 = d.squaredNorm();
    const double t = l2 > 0 ? std::clamp((q - u).dot(d) / l2, 0.0, 1.0) : 0.0;
    return (u + t * d - q).norm();
  };
  return std::min({seg(a, b), seg(b, c), seg(c, a)});
}

namespace {

std::uint64_t bin_key(long i, long j) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
}

}  // namespace

long ChartTriangles::cell_of(double x) const { return static_cast<long>(std::floor(x / cell_)); }

index_t ChartTriangles::add(const Vec3& a, const Vec3& b, const Vec3& c) {
  std::array<Vec2, 3> t;
  t[0] = chart_.map(a);
  t[1] = chart_.unwrap(chart_.map(b), t[0]);
  t[2] = chart_.unwrap(chart_.map(c), t[0]);
  return add(t);
}

index_t ChartTriangles::add(const std::array<Vec2, 3>& t) {
  const index_t id = static_cast<index_t>(tris_.size());
  tris_.push_back(t);
  const Vec2 lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]), hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
  for (long i = cell_of(lo.x()); i <= cell_of(hi.x()); ++i)
    for (long j = cell_of(lo.y()); j <= cell_of(hi.y()); ++j) bins_[bin_key(i, j)].push_back(id);
  return id;
}

bool ChartTriangles::contains(const Vec2& q0, double tol) const {
  for (int k = -1; k <= 1; ++k) {
    if (k != 0 && chart_.period.x() == 0) continue;
    const Vec2 q = q0 + Vec2(k * chart_.period.x(), 0);
    std::unordered_set<index_t> seen;
    for (long i = cell_of(q.x() - tol); i <= cell_of(q.x() + tol); ++i)
      for (long j = cell_of(q.y() - tol); j <= cell_of(q.y() + tol); ++j) {
        const auto it = bins_.find(bin_key(i, j));
        if (it == bins_.end()) continue;
        for (const index_t t : it->second)
          if (seen.insert(t).second && distance_to_triangle_2d(q, tris_[t][0], tris_[t][1], tris_[t][2]) <= tol)
            return true;
      }
  }
  return false;
}

}  // namespace femorph
