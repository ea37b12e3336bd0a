// Signed distance, closest point and normal of the five analytic surfaces in
// general position at scales 0.01 to 1000: the closest point lies on the
// surface, p = closest + d * normal, no sampled surface point is closer, and
// points offset along the true normal measure the offset. Cone apex, spindle
// torus and same_surface conventions.
#include "geometry/surface_primitive.h"
#include "test_surfaces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace femorph {
namespace {

using namespace test_surfaces;

const double kScales[] = {0.01, 1.0, 1000.0};

// A random surface of the given type and size in general position, with a
// sample of it (points, outward normals) dense enough to compare distances.
Sample random_surface(SurfaceType type, double scale, Rng& rng, SurfacePrimitive& s, int n) {
  const Vec3 center = random_point(rng, 2 * scale);
  const Vec3 axis = random_unit(rng);
  switch (type) {
    case SurfaceType::Plane:
      s = plane(center, axis);
      return sample_plane(s, 4 * scale, n, rng);
    case SurfaceType::Cylinder:
      s = cylinder(center, axis, scale * uniform(rng, 0.5, 1.5));
      return sample_cylinder(s, 0, 2 * kPi, -4 * scale, 4 * scale, n, rng);
    case SurfaceType::Cone:
      s = cone(center, axis, uniform(rng, 0.2, 1.2));
      return sample_cone(s, 0, 2 * kPi, 0, 6 * scale, n, rng);
    case SurfaceType::Sphere:
      s = sphere(center, scale * uniform(rng, 0.5, 1.5));
      return sample_sphere(s, axis, 0, kPi, n, rng);
    case SurfaceType::Torus:
      s = torus(center, axis, scale * uniform(rng, 1.0, 1.5), scale * uniform(rng, 0.2, 0.6));
      return sample_torus(s, 0, 2 * kPi, 0, 2 * kPi, n, rng);
    case SurfaceType::Unknown: break;
  }
  return {};
}

TEST(SurfacePrimitive, Names) {
  EXPECT_EQ(std::string(to_string(SurfaceType::Plane)), "plane");
  EXPECT_EQ(std::string(to_string(SurfaceType::Cylinder)), "cylinder");
  EXPECT_EQ(std::string(to_string(SurfaceType::Cone)), "cone");
  EXPECT_EQ(std::string(to_string(SurfaceType::Sphere)), "sphere");
  EXPECT_EQ(std::string(to_string(SurfaceType::Torus)), "torus");
  EXPECT_EQ(std::string(to_string(SurfaceType::Unknown)), "unknown");
}

TEST(SurfacePrimitive, ClosestPointLiesOnSurfaceAndIsClosest) {
  Rng rng(7);
  for (SurfaceType type : {SurfaceType::Plane, SurfaceType::Cylinder, SurfaceType::Cone, SurfaceType::Sphere,
                           SurfaceType::Torus}) {
    for (double scale : kScales) {
      for (int trial = 0; trial < 3; ++trial) {
        SurfacePrimitive s;
        const Sample sample = random_surface(type, scale, rng, s, 20000);
        const double eps = 1e-12 * scale;
        for (int q = 0; q < 100; ++q) {
          // Query points near the sampled part (so the sample can compete).
          const Vec3 p = sample.points[q * 97] + random_point(rng, 0.8 * scale);
          const double d = signed_distance(s, p);
          const Vec3 c = closest_point(s, p);
          const Vec3 n = surface_normal(s, p);
          SCOPED_TRACE(std::string(to_string(type)) + " scale " + std::to_string(scale));
          EXPECT_NEAR(std::abs(d), distance(s, p), 0);
          EXPECT_NEAR(signed_distance(s, c), 0.0, eps);
          EXPECT_NEAR(n.norm(), 1.0, 1e-14);
          EXPECT_LE((c + d * n - p).norm(), eps);
          EXPECT_NEAR(std::abs(d), (p - c).norm(), eps);
          // The normal at the closest point is the same normal.
          if (!(type == SurfaceType::Cone && (p - s.point).dot(s.axis) < 0)) {
            EXPECT_LE((surface_normal(s, c) - n).norm(), 1e-9);
          }
          // No sampled point of the surface is closer.
          double nearest = INFINITY;
          for (const Vec3& x : sample.points) nearest = std::min(nearest, (x - p).norm());
          EXPECT_LE(std::abs(d), nearest + eps);
        }
      }
    }
  }
}

TEST(SurfacePrimitive, OffsetAlongNormalIsSignedDistance) {
  Rng rng(11);
  for (SurfaceType type : {SurfaceType::Plane, SurfaceType::Cylinder, SurfaceType::Cone, SurfaceType::Sphere,
                           SurfaceType::Torus}) {
    for (double scale : kScales) {
      SurfacePrimitive s;
      const Sample sample = random_surface(type, scale, rng, s, 500);
      for (std::size_t i = 0; i < sample.points.size(); ++i) {
        // Offsets below the smallest radius of curvature (cone: keep in front
        // of the apex, where the offset line still meets the nappe first).
        const double offset = scale * uniform(rng, -0.1, 0.1);
        if (type == SurfaceType::Cone && (sample.points[i] - s.point).norm() < 0.5 * scale) continue;
        const Vec3 p = sample.points[i] + offset * sample.normals[i];
        SCOPED_TRACE(std::string(to_string(type)) + " scale " + std::to_string(scale));
        EXPECT_NEAR(signed_distance(s, sample.points[i]), 0.0, 1e-12 * scale);
        EXPECT_NEAR(signed_distance(s, p), offset, 1e-12 * scale);
        EXPECT_LE((surface_normal(s, p) - sample.normals[i]).norm(), 1e-10);
        EXPECT_LE((closest_point(s, p) - sample.points[i]).norm(), 1e-12 * scale);
      }
    }
  }
}

TEST(SurfacePrimitive, ConeBehindApexMeasuresToApex) {
  const SurfacePrimitive s = cone(Vec3(1, 2, 3), Vec3(0, 0, 1), 0.5);
  // Straight behind the apex, and off to the side but still behind the
  // nappe's normal line through the apex.
  for (const Vec3& p : {Vec3(1, 2, 1), Vec3(1.5, 2, 2), Vec3(1, 2.1, 2.9)}) {
    EXPECT_NEAR(signed_distance(s, p), (p - s.point).norm(), 1e-15);
    EXPECT_EQ(closest_point(s, p), s.point);
    EXPECT_LE((s.point + signed_distance(s, p) * surface_normal(s, p) - p).norm(), 1e-15);
  }
  // In front: inside the cone is negative, on the axis the distance is
  // h sin(a) to any generatrix.
  EXPECT_NEAR(signed_distance(s, Vec3(1, 2, 5)), -2 * std::sin(0.5), 1e-15);
  // The apex itself is on the surface.
  EXPECT_EQ(signed_distance(s, s.point), 0.0);
  // Continuity across the apex's normal cone: just in front and just behind.
  const Vec3 n = std::cos(0.5) * Vec3(1, 0, 0) - std::sin(0.5) * Vec3(0, 0, 1);
  EXPECT_NEAR(signed_distance(s, s.point + 2 * n + Vec3(0, 0, 1e-9)), 2.0, 1e-8);
  EXPECT_NEAR(signed_distance(s, s.point + 2 * n - Vec3(0, 0, 1e-9)), 2.0, 1e-8);
}

TEST(SurfacePrimitive, PointsOnAxesAreHandled) {
  const SurfacePrimitive cyl = cylinder(Vec3::Zero(), Vec3(0, 0, 1), 2);
  EXPECT_EQ(signed_distance(cyl, Vec3(0, 0, 5)), -2.0);
  EXPECT_NEAR(signed_distance(cyl, closest_point(cyl, Vec3(0, 0, 5))), 0.0, 1e-15);
  const SurfacePrimitive tor = torus(Vec3::Zero(), Vec3(0, 0, 1), 3, 1);
  EXPECT_NEAR(signed_distance(tor, Vec3(0, 0, 0)), 2.0, 1e-15);
  EXPECT_NEAR(signed_distance(tor, Vec3(3, 0, 0)), -1.0, 1e-15);  // on the core circle
  EXPECT_NEAR(signed_distance(tor, closest_point(tor, Vec3(3, 0, 0))), 0.0, 1e-15);
  const SurfacePrimitive sph = sphere(Vec3(1, 1, 1), 2);
  EXPECT_NEAR(signed_distance(sph, closest_point(sph, Vec3(1, 1, 1))), 0.0, 1e-15);
}

TEST(SurfacePrimitive, SpindleTorusStaysFinite) {
  // R <= r: distance to the core circle minus r, finite and consistent.
  Rng rng(3);
  for (double major : {0.0, 0.5, 1.0}) {
    const SurfacePrimitive s = torus(Vec3(1, -2, 0.5), random_unit(rng), major, 1.0);
    for (int i = 0; i < 200; ++i) {
      const Vec3 p = s.point + random_point(rng, 3);
      const double d = signed_distance(s, p);
      ASSERT_TRUE(std::isfinite(d));
      const Vec3 c = closest_point(s, p), n = surface_normal(s, p);
      ASSERT_TRUE(c.allFinite() && n.allFinite());
      EXPECT_LE((c + d * n - p).norm(), 1e-12);
    }
    // The outer equator is on the surface.
    Vec3 u, v;
    frame_of(s.axis, u, v);
    EXPECT_NEAR(signed_distance(s, s.point + (major + 1.0) * u), 0.0, 1e-14);
  }
}

TEST(SurfacePrimitive, UnknownSurface) {
  const SurfacePrimitive s;
  EXPECT_TRUE(std::isnan(signed_distance(s, Vec3(1, 2, 3))));
  EXPECT_EQ(closest_point(s, Vec3(1, 2, 3)), Vec3(1, 2, 3));
  EXPECT_EQ(surface_normal(s, Vec3(1, 2, 3)), Vec3::Zero());
  EXPECT_FALSE(same_surface(s, s, 1e-6, 1, 1e-3));
}

TEST(SurfacePrimitive, SameSurface) {
  const double rel = 1e-6, scale = 100, angle = 1e-4;
  const Vec3 axis = Vec3(1, 2, 2).normalized();
  Vec3 u, v;
  frame_of(axis, u, v);

  // Cylinder: another point of the axis and the reversed axis are the same.
  const SurfacePrimitive c1 = cylinder(Vec3(3, 4, 5), axis, 10);
  SurfacePrimitive c2 = c1;
  c2.point = c1.point + 7 * axis;
  c2.axis = -axis;
  EXPECT_TRUE(same_surface(c1, c2, rel, scale, angle));
  c2.radius = 10 * (1 + 3 * rel);
  EXPECT_FALSE(same_surface(c1, c2, rel, scale, angle));
  c2.radius = 10;
  c2.point += 2 * rel * scale * u;  // axes apart
  EXPECT_FALSE(same_surface(c1, c2, rel, scale, angle));
  c2.point = c1.point;
  c2.axis = (axis + 2 * angle * u).normalized();
  EXPECT_FALSE(same_surface(c1, c2, rel, scale, angle));

  // Plane: the reversed normal and another point of it are the same.
  const SurfacePrimitive p1 = plane(Vec3(1, 1, 1), axis);
  SurfacePrimitive p2 = plane(Vec3(1, 1, 1) + 50 * u - 20 * v, -axis);
  EXPECT_TRUE(same_surface(p1, p2, rel, scale, angle));
  p2.point += 2 * rel * scale * axis;
  EXPECT_FALSE(same_surface(p1, p2, rel, scale, angle));

  // Cone: the reversed axis is the other nappe.
  const SurfacePrimitive k1 = cone(Vec3(0, 0, 1), axis, 0.3);
  SurfacePrimitive k2 = k1;
  EXPECT_TRUE(same_surface(k1, k2, rel, scale, angle));
  k2.axis = -axis;
  EXPECT_FALSE(same_surface(k1, k2, rel, scale, angle));
  k2 = k1;
  k2.half_angle += 2 * angle;
  EXPECT_FALSE(same_surface(k1, k2, rel, scale, angle));

  // Sphere and torus.
  const SurfacePrimitive s1 = sphere(Vec3(1, 2, 3), 5);
  SurfacePrimitive s2 = s1;
  s2.radius *= 1 + 0.5 * rel;
  EXPECT_TRUE(same_surface(s1, s2, rel, scale, angle));
  s2.point.x() += 2 * rel * scale;
  EXPECT_FALSE(same_surface(s1, s2, rel, scale, angle));
  const SurfacePrimitive t1 = torus(Vec3(1, 2, 3), axis, 15, 3);
  SurfacePrimitive t2 = t1;
  t2.axis = -axis;
  EXPECT_TRUE(same_surface(t1, t2, rel, scale, angle));
  t2.minor_radius = 3 * (1 + 3 * rel);
  EXPECT_FALSE(same_surface(t1, t2, rel, scale, angle));
  EXPECT_FALSE(same_surface(t1, s1, rel, scale, angle));
}

}  // namespace
}  // namespace femorph
