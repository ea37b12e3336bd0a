// Boundary curve classification (thesis 2.4.6) on exact plane sections in
// general position at sizes 0.01 to 1000: lines, circles, arcs, ellipses from
// oblique plane x cylinder and plane x cone sections, parabolas and
// hyperbolas from plane x cone sections, each with its parameters checked
// against the construction; non-planar and unexplained curves stay
// unclassified.
#include "geometry/curve_primitive.h"
#include "test_surfaces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace femorph {
namespace {

using namespace test_surfaces;

const double kScales[] = {0.01, 1.0, 1000.0};
constexpr double kDegree = kPi / 180;

const SurfacePrimitive kUnknown;

// A random orthonormal frame (e1, e2, e3) at a random origin.
struct Frame {
  Vec3 origin, e1, e2, e3;
};

Frame random_frame(Rng& rng, double scale) {
  Frame f;
  f.origin = random_point(rng, 5 * scale);
  f.e3 = random_unit(rng);
  frame_of(f.e3, f.e1, f.e2);
  return f;
}

// Points where the generatrices of a cone at angles [t0, t1] around its
// axis (measured from `e`) meet the plane N . (x - x0) = 0, on the nappe.
std::vector<Vec3> cone_section(const SurfacePrimitive& cone_surface, const Vec3& e, const Vec3& N, const Vec3& x0,
                               double t0, double t1, int n) {
  const Vec3 A = cone_surface.axis, w = A.cross(e);
  const double sa = std::sin(cone_surface.half_angle), ca = std::cos(cone_surface.half_angle);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) {
    const double t = t0 + (t1 - t0) * i / (n - 1);
    const Vec3 g = sa * (std::cos(t) * e + std::sin(t) * w) + ca * A;
    const double lambda = N.dot(x0 - cone_surface.point) / N.dot(g);
    EXPECT_GT(lambda, 0) << "not on the nappe";
    points.push_back(cone_surface.point + lambda * g);
  }
  return points;
}

TEST(CurvePrimitive, Names) {
  EXPECT_EQ(std::string(to_string(CurveType::Line)), "line");
  EXPECT_EQ(std::string(to_string(CurveType::Circle)), "circle");
  EXPECT_EQ(std::string(to_string(CurveType::CircularArc)), "circular arc");
  EXPECT_EQ(std::string(to_string(CurveType::Ellipse)), "ellipse");
  EXPECT_EQ(std::string(to_string(CurveType::EllipticArc)), "elliptic arc");
  EXPECT_EQ(std::string(to_string(CurveType::Parabola)), "parabola");
  EXPECT_EQ(std::string(to_string(CurveType::Hyperbola)), "hyperbola");
  EXPECT_EQ(std::string(to_string(CurveType::Unclassified)), "unclassified");
}

TEST(ClassifyBoundaryCurve, Line) {
  Rng rng(1);
  for (double scale : kScales) {
    const Frame f = random_frame(rng, scale);
    std::vector<Vec3> points;
    for (int i = 0; i <= 20; ++i) points.push_back(f.origin + (2 * scale * i / 20.0) * f.e1);
    const CurveFit fit = classify_boundary_curve(points, false, 1e-9 * scale, kUnknown, kUnknown);
    ASSERT_TRUE(fit.ok);
    EXPECT_EQ(fit.curve.type, CurveType::Line);
    EXPECT_LT((fit.curve.direction - f.e1).norm(), 1e-12) << "oriented from start to end";
    EXPECT_EQ(fit.curve.start, points.front());
    EXPECT_EQ(fit.curve.end, points.back());
    EXPECT_LT(fit.max_abs, 1e-12 * scale);
  }
}

TEST(ClassifyBoundaryCurve, CircleAndArc) {
  Rng rng(2);
  for (double scale : kScales) {
    const Frame f = random_frame(rng, scale);
    const double radius = scale * uniform(rng, 0.5, 2);
    const auto circle_points = [&](double t0, double t1, int n, bool closed) {
      std::vector<Vec3> points;
      for (int i = 0; i < n; ++i) {
        const double t = t0 + (t1 - t0) * i / (closed ? n : n - 1);
        points.push_back(f.origin + radius * (std::cos(t) * f.e1 + std::sin(t) * f.e2));
      }
      return points;
    };
    // A loop between a plane and a cylinder perpendicular to it.
    const SurfacePrimitive pl = plane(f.origin, f.e3);
    const SurfacePrimitive cyl = cylinder(f.origin, f.e3, radius);
    const CurveFit full = classify_boundary_curve(circle_points(0, 2 * kPi, 40, true), true, 1e-9 * scale, pl, cyl);
    ASSERT_TRUE(full.ok);
    EXPECT_EQ(full.curve.type, CurveType::Circle);
    EXPECT_LT((full.curve.center - f.origin).norm(), 1e-10 * scale);
    EXPECT_LT(line_angle(full.curve.normal, f.e3), 1e-10);
    EXPECT_NEAR(full.curve.radius, radius, 1e-10 * radius);
    EXPECT_LT(full.max_abs, 1e-11 * scale);

    // A 60 degree arc with unknown surfaces (e.g. a torus boundary).
    const std::vector<Vec3> arc_points = circle_points(0.5, 0.5 + kPi / 3, 15, false);
    const CurveFit arc = classify_boundary_curve(arc_points, false, 1e-9 * scale, kUnknown, kUnknown);
    ASSERT_TRUE(arc.ok);
    EXPECT_EQ(arc.curve.type, CurveType::CircularArc);
    EXPECT_LT((arc.curve.center - f.origin).norm(), 1e-9 * scale);
    EXPECT_NEAR(arc.curve.radius, radius, 1e-9 * radius);
    EXPECT_EQ(arc.curve.start, arc_points.front());
    EXPECT_EQ(arc.curve.end, arc_points.back());
    // The normal follows the right-hand rule along the points: e3 here,
    // -e3 for the arc run backwards.
    EXPECT_LT((arc.curve.normal - f.e3).norm(), 1e-9);
    const std::vector<Vec3> backwards(arc_points.rbegin(), arc_points.rend());
    EXPECT_LT((classify_boundary_curve(backwards, false, 1e-9 * scale, kUnknown, kUnknown).curve.normal + f.e3).norm(),
              1e-9);
  }
}

TEST(ClassifyBoundaryCurve, NoisyCircleWithinTolerance) {
  Rng rng(3);
  const Frame f = random_frame(rng, 10);
  std::vector<Vec3> points;
  for (int i = 0; i < 60; ++i) {
    const double t = 2 * kPi * i / 60;
    points.push_back(f.origin + 10 * (std::cos(t) * f.e1 + std::sin(t) * f.e2) + random_point(rng, 1e-4));
  }
  const CurveFit fit = classify_boundary_curve(points, true, 1e-3, kUnknown, kUnknown);
  ASSERT_TRUE(fit.ok);
  EXPECT_EQ(fit.curve.type, CurveType::Circle);
  EXPECT_NEAR(fit.curve.radius, 10, 1e-4);
  EXPECT_LT(fit.max_abs, 1e-3);
  // A tolerance below the noise: neither plane curve nor circle.
  EXPECT_EQ(classify_boundary_curve(points, true, 1e-6, kUnknown, kUnknown).curve.type, CurveType::Unclassified);
}

TEST(ClassifyBoundaryCurve, EllipseFromObliquePlaneAndCylinder) {
  Rng rng(4);
  for (double scale : kScales) {
    const Frame f = random_frame(rng, scale);
    const double radius = scale * uniform(rng, 0.5, 2);
    const double tilt = uniform(rng, 20, 60) * kDegree;  // plane normal vs axis
    const Vec3 axis = f.e3;
    const Vec3 N = std::cos(tilt) * f.e3 + std::sin(tilt) * f.e1;
    const SurfacePrimitive cyl = cylinder(f.origin, axis, radius);
    const SurfacePrimitive pl = plane(f.origin, N);
    std::vector<Vec3> points;
    const int n = 48;
    for (int i = 0; i < n; ++i) {
      const double t = 2 * kPi * i / n;
      const Vec3 radial = radius * (std::cos(t) * f.e1 + std::sin(t) * f.e2);
      points.push_back(f.origin + radial - (N.dot(radial) / N.dot(axis)) * axis);
    }
    for (bool swap : {false, true}) {
      const CurveFit fit = classify_boundary_curve(points, true, 1e-9 * scale, swap ? cyl : pl, swap ? pl : cyl);
      ASSERT_TRUE(fit.ok);
      EXPECT_EQ(fit.curve.type, CurveType::Ellipse) << to_string(fit.curve.type);
      EXPECT_LT((fit.curve.center - f.origin).norm(), 1e-9 * scale);
      EXPECT_LT(line_angle(fit.curve.normal, N), 1e-10);
      EXPECT_NEAR(fit.curve.radius, radius / std::cos(tilt), 1e-9 * radius);  // semi-major
      EXPECT_NEAR(fit.curve.minor_radius, radius, 1e-9 * radius);
      const Vec3 major = (axis - axis.dot(N) * N).normalized();
      EXPECT_LT(line_angle(fit.curve.direction, major), 1e-9);
      EXPECT_LT(fit.max_abs, 1e-10 * scale);
    }
    // Half of it, open: an elliptic arc.
    const std::vector<Vec3> half(points.begin(), points.begin() + n / 2);
    const CurveFit arc = classify_boundary_curve(half, false, 1e-9 * scale, pl, cyl);
    EXPECT_EQ(arc.curve.type, CurveType::EllipticArc);
    EXPECT_NEAR(arc.curve.radius, radius / std::cos(tilt), 1e-9 * radius);
    EXPECT_EQ(arc.curve.start, half.front());
    // The same points between two cylinders are not explained: unclassified.
    const CurveFit other = classify_boundary_curve(points, true, 1e-9 * scale, cyl, cylinder(f.origin, f.e1, radius));
    EXPECT_TRUE(other.ok);
    EXPECT_EQ(other.curve.type, CurveType::Unclassified);
  }
}

TEST(ClassifyBoundaryCurve, ConeSections) {
  Rng rng(5);
  for (double scale : kScales) {
    const Frame f = random_frame(rng, scale);
    const double alpha = uniform(rng, 20, 40) * kDegree;
    const SurfacePrimitive k = cone(f.origin, f.e3, alpha);
    const Vec3 A = f.e3, e = f.e1;
    const double tol = 1e-9 * scale;

    // Parabola: the plane makes the half angle with the axis (contains a
    // generatrix direction), at distance D along the axis from the apex.
    {
      const Vec3 N = (std::sin(alpha) * A - std::cos(alpha) * e).normalized();
      const Vec3 x0 = f.origin + scale * A;
      const std::vector<Vec3> points = cone_section(k, e, N, x0, 0.6 * kPi, 1.4 * kPi, 41);
      const CurveFit fit = classify_boundary_curve(points, false, tol, plane(x0, N), k);
      ASSERT_TRUE(fit.ok);
      ASSERT_EQ(fit.curve.type, CurveType::Parabola) << to_string(fit.curve.type) << " scale " << scale;
      EXPECT_LT(line_angle(fit.curve.normal, N), 1e-10);
      // Axis along the cone's axis projected on the plane, opening away from
      // the apex; vertex on the cone; every point on x = y^2 / (4 f).
      const Vec3 projected = (A - A.dot(N) * N).normalized();
      EXPECT_LT((fit.curve.direction - projected).norm(), 1e-9);
      EXPECT_LT(distance(k, fit.curve.center), 1e-9 * scale);
      EXPECT_LT(std::abs((fit.curve.center - x0).dot(N)), 1e-9 * scale);
      const Vec3 across = N.cross(fit.curve.direction);
      for (const Vec3& p : points) {
        const double x = (p - fit.curve.center).dot(fit.curve.direction);
        const double y = (p - fit.curve.center).dot(across);
        EXPECT_NEAR(x, y * y / (4 * fit.curve.radius), 1e-8 * scale);
      }
      EXPECT_EQ(fit.curve.start, points.front());
      EXPECT_EQ(fit.curve.end, points.back());
    }

    // Hyperbola: a plane parallel to the axis at distance d from it:
    // z^2 / (d / tan a)^2 - y^2 / d^2 = 1, centred at the apex's projection.
    {
      const double d = 0.3 * scale;
      const Vec3 N = e;
      const Vec3 x0 = f.origin + d * e;
      const std::vector<Vec3> points = cone_section(k, f.e2, N, x0, 1.15 * kPi, 1.85 * kPi, 41);
      const CurveFit fit = classify_boundary_curve(points, false, tol, k, plane(x0, N));
      ASSERT_TRUE(fit.ok);
      ASSERT_EQ(fit.curve.type, CurveType::Hyperbola) << to_string(fit.curve.type) << " scale " << scale;
      const double a = d / std::tan(alpha);
      EXPECT_NEAR(fit.curve.radius, a, 1e-9 * scale);
      EXPECT_NEAR(fit.curve.minor_radius, d, 1e-9 * scale);
      EXPECT_LT((fit.curve.direction - A).norm(), 1e-9);
      EXPECT_LT((fit.curve.center - (f.origin + d * e + a * A)).norm(), 1e-9 * scale);  // the vertex
    }

    // Ellipse: a plane steeper than the cone's generatrices, closed and open.
    {
      const double tilt = alpha / 2;  // normal vs axis, so the plane-axis angle is 90 - tilt > alpha
      const Vec3 N = std::cos(tilt) * A + std::sin(tilt) * e;
      const Vec3 x0 = f.origin + scale * A;
      std::vector<Vec3> loop = cone_section(k, e, N, x0, 0, 2 * kPi, 61);
      loop.pop_back();  // a loop does not repeat its first point
      const CurveFit fit = classify_boundary_curve(loop, true, tol, plane(x0, N), k);
      ASSERT_TRUE(fit.ok);
      ASSERT_EQ(fit.curve.type, CurveType::Ellipse) << to_string(fit.curve.type) << " scale " << scale;
      // Every point satisfies the fitted ellipse's equation.
      const Vec3 minor_dir = N.cross(fit.curve.direction);
      for (const Vec3& p : loop) {
        const double x = (p - fit.curve.center).dot(fit.curve.direction) / fit.curve.radius;
        const double y = (p - fit.curve.center).dot(minor_dir) / fit.curve.minor_radius;
        EXPECT_NEAR(x * x + y * y, 1.0, 1e-8);
      }
      EXPECT_GT(fit.curve.radius, fit.curve.minor_radius);
      const Vec3 projected = (A - A.dot(N) * N).normalized();
      EXPECT_LT(line_angle(fit.curve.direction, projected), 1e-8);
      const std::vector<Vec3> open(loop.begin(), loop.begin() + 20);
      EXPECT_EQ(classify_boundary_curve(open, false, tol, k, plane(x0, N)).curve.type, CurveType::EllipticArc);
    }
  }
}

TEST(ClassifyBoundaryCurve, NonPlanarAndUnexplained) {
  Rng rng(6);
  const Frame f = random_frame(rng, 1);
  // A helix: not planar.
  std::vector<Vec3> helix;
  for (int i = 0; i < 50; ++i) {
    const double t = 0.1 * i;
    helix.push_back(f.origin + std::cos(t) * f.e1 + std::sin(t) * f.e2 + 0.05 * t * f.e3);
  }
  const SurfacePrimitive cyl = cylinder(f.origin, f.e3, 1);
  const CurveFit fit = classify_boundary_curve(helix, false, 1e-6, cyl, plane(f.origin, f.e3));
  EXPECT_TRUE(fit.ok);
  EXPECT_EQ(fit.curve.type, CurveType::Unclassified);
  EXPECT_EQ(fit.curve.start, helix.front());
  EXPECT_EQ(fit.curve.end, helix.back());
  // A planar curve at a torus that is no circle (a planar ellipse): unclassified.
  std::vector<Vec3> ellipse;
  for (int i = 0; i < 40; ++i) {
    const double t = 2 * kPi * i / 40;
    ellipse.push_back(f.origin + 2 * std::cos(t) * f.e1 + std::sin(t) * f.e2);
  }
  const SurfacePrimitive tor = torus(f.origin, f.e3, 3, 1);
  EXPECT_EQ(classify_boundary_curve(ellipse, true, 1e-6, tor, plane(f.origin, f.e3)).curve.type,
            CurveType::Unclassified);
  // ... but a circle at a torus is a circle.
  std::vector<Vec3> circle;
  for (int i = 0; i < 40; ++i) {
    const double t = 2 * kPi * i / 40;
    circle.push_back(f.origin + 2 * std::cos(t) * f.e1 + 2 * std::sin(t) * f.e2);
  }
  EXPECT_EQ(classify_boundary_curve(circle, true, 1e-6, tor, plane(f.origin, f.e3)).curve.type, CurveType::Circle);
  // A plane parallel to a cylinder's axis cuts no ellipse.
  EXPECT_EQ(classify_boundary_curve(ellipse, true, 1e-6, plane(f.origin, f.e3), cylinder(f.origin, f.e1, 1))
                .curve.type,
            CurveType::Unclassified);
}

TEST(ClassifyBoundaryCurve, Refusals) {
  const CurveFit one = classify_boundary_curve({Vec3(1, 2, 3)}, false, 1e-6, kUnknown, kUnknown);
  EXPECT_FALSE(one.ok);
  EXPECT_EQ(one.curve.type, CurveType::Unclassified);
  EXPECT_FALSE(classify_boundary_curve({Vec3(0, 0, 0), Vec3(1, 0, 0)}, true, 1e-6, kUnknown, kUnknown).ok);
  EXPECT_FALSE(classify_boundary_curve({}, false, 1e-6, kUnknown, kUnknown).ok);
  // Two points, open: a line.
  const CurveFit two = classify_boundary_curve({Vec3(0, 0, 0), Vec3(0, 2, 0)}, false, 1e-6, kUnknown, kUnknown);
  EXPECT_TRUE(two.ok);
  EXPECT_EQ(two.curve.type, CurveType::Line);
  EXPECT_LT((two.curve.direction - Vec3(0, 1, 0)).norm(), 1e-15);
}

}  // namespace
}  // namespace femorph
