// SurfaceChart: lift and map invert each other on every surface type, the
// developable surfaces' charts keep lengths (development planes, thesis
// 3.4.2), the centre maps to the origin's line and unwrap() brings points
// across the seam.
#include "geometry/surface_chart.h"

#include <gtest/gtest.h>

#include <random>

namespace femorph {
namespace {

std::vector<SurfacePrimitive> surfaces() {
  std::vector<SurfacePrimitive> s(5);
  s[0].type = SurfaceType::Plane;
  s[0].point = Vec3(1, 2, 3);
  s[0].axis = Vec3(1, 1, 0.5).normalized();
  s[1].type = SurfaceType::Cylinder;
  s[1].point = Vec3(0.5, -1, 0);
  s[1].axis = Vec3(0, 0.3, 1).normalized();
  s[1].radius = 2.5;
  s[2].type = SurfaceType::Cone;
  s[2].point = Vec3(0, 0, -4);
  s[2].axis = Vec3(0.2, 0, 1).normalized();
  s[2].half_angle = 0.6;
  s[3].type = SurfaceType::Sphere;
  s[3].point = Vec3(1, 1, 1);
  s[3].radius = 3;
  s[4].type = SurfaceType::Torus;
  s[4].point = Vec3(0, 0, 1);
  s[4].axis = Vec3(0, 1, 0);
  s[4].radius = 4;
  s[4].minor_radius = 1.5;
  return s;
}

TEST(SurfaceChart, LiftAndMapInvertEachOther) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (const SurfacePrimitive& s : surfaces()) {
    // A centre on the surface, away from a cone's apex.
    const SurfaceChart probe = make_surface_chart(s, s.point + 7 * s.axis.unitOrthogonal() + 3 * s.axis);
    const Vec3 centre = probe.lift(Vec2(0.3, s.type == SurfaceType::Cone ? 5.0 : 0.2));
    const SurfaceChart c = make_surface_chart(s, centre);
    for (int i = 0; i < 200; ++i) {
      Vec2 q(u(rng), u(rng));
      if (s.type == SurfaceType::Cone) q += c.map(centre);
      const Vec3 p = c.lift(q);
      EXPECT_NEAR(distance(s, p), 0, 1e-12) << to_string(s.type) << ": the lift is not on the surface";
      EXPECT_NEAR((c.map(p) - q).norm(), 0, 1e-12) << to_string(s.type);
      // A point off the surface maps like its closest point.
      const Vec3 off = p + 0.01 * surface_normal(s, p);
      EXPECT_NEAR((c.map(off) - q).norm(), 0, 1e-9) << to_string(s.type);
    }
  }
}

TEST(SurfaceChart, DevelopableChartsKeepLengths) {
  for (const SurfacePrimitive& s : surfaces()) {
    if (s.type == SurfaceType::Sphere || s.type == SurfaceType::Torus) continue;
    const SurfaceChart probe = make_surface_chart(s, s.point + 5 * s.axis.unitOrthogonal() + 6 * s.axis);
    const Vec2 base = probe.map(probe.lift(Vec2(0.1, s.type == SurfaceType::Cone ? 6.0 : 0.1)));
    // A short chart segment has the length of its lifted curve.
    for (int k = 0; k < 8; ++k) {
      const Vec2 d = 1e-3 * Vec2(std::cos(k), std::sin(k));
      EXPECT_NEAR((probe.lift(base + d) - probe.lift(base)).norm(), d.norm(), 1e-8) << to_string(s.type);
    }
  }
}

TEST(SurfaceChart, UnwrapAcrossTheSeam) {
  const SurfacePrimitive cyl = surfaces()[1];
  const SurfaceChart c = make_surface_chart(cyl, cyl.point + 2.5 * cyl.axis.unitOrthogonal());
  const double r = cyl.radius;
  // Two points just either side of the seam (opposite the centre).
  const Vec2 a = c.map(c.lift(Vec2(r * (kPi - 0.01), 1)));
  const Vec2 b = c.map(c.lift(Vec2(r * (-kPi + 0.01), 1)));
  EXPECT_GT((a - b).norm(), r);
  EXPECT_NEAR((c.unwrap(b, a) - a).norm(), 0.02 * r, 1e-12);
}

}  // namespace
}  // namespace femorph
