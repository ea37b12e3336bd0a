// Core/deform: mean value coordinates (Eqs. 2.11-2.20), classification and
// measurement (2.5.2), the valid range, parameterise once and reposition
// many (2.5.4), and deform_mesh on a cube.
#include "deform/deform.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace femorph {
namespace {

using testing::make_cube_mesh;

TEST(MeanValueCoordinates2d, RegularFanGivesEqualWeightsAndReproducesTheCentre) {
  std::vector<Vec3> ring;
  std::vector<std::array<int, 2>> fan;
  for (int k = 0; k < 6; ++k) {
    ring.emplace_back(std::cos(k * kPi / 3), std::sin(k * kPi / 3), 0);
    fan.push_back({k, (k + 1) % 6});
  }
  std::vector<double> w;
  mean_value_coordinates_2d(Vec3::Zero(), ring, fan, w);
  for (double x : w) EXPECT_NEAR(x, 1.0 / 6, 1e-14);
}

TEST(MeanValueCoordinates2d, LinearPrecisionOnAStarShapedPolygon) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> r(0.5, 2.0), t(-0.2, 0.2);
  std::vector<Vec3> ring;
  std::vector<std::array<int, 2>> fan;
  const int n = 9;
  for (int k = 0; k < n; ++k) {
    const double a = (k + t(rng)) * 2 * kPi / n, radius = r(rng);
    ring.emplace_back(radius * std::cos(a), radius * std::sin(a), 0);
    fan.push_back({k, (k + 1) % n});
  }
  const Vec3 x(0.1, -0.05, 0);
  std::vector<double> w;
  mean_value_coordinates_2d(x, ring, fan, w);
  Vec3 sum = Vec3::Zero();
  double total = 0;
  for (int k = 0; k < n; ++k) {
    EXPECT_GT(w[k], 0);
    sum += w[k] * ring[k];
    total += w[k];
  }
  EXPECT_NEAR(total, 1, 1e-14);
  EXPECT_LT((sum - x).norm(), 1e-13);
}

TEST(MeanValueCoordinates3d, LinearPrecisionInTheOneRingOfAnInnerVertex) {
  const auto m = make_cube_mesh(4, 0.1, 3);
  TetMesh mesh;
  BuildOptions o;
  o.face_regions = m.face_regions;
  ASSERT_TRUE(mesh.build(m.points, m.tets, o));
  int checked = 0;
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    if (mesh.on_boundary(v)) continue;
    std::vector<index_t> ball;
    mesh.vertex_ball(v, ball);
    std::vector<Vec3> ring;
    std::vector<index_t> ids;
    std::vector<Tri> link;
    const auto local = [&](index_t id) {
      for (std::size_t j = 0; j < ids.size(); ++j)
        if (ids[j] == id) return static_cast<index_t>(j);
      ids.push_back(id);
      ring.push_back(mesh.point(id));
      return static_cast<index_t>(ids.size() - 1);
    };
    for (const index_t t : ball) {
      const int i = mesh.local_index(t, v);
      const Tet& T = mesh.tet(t);
      link.push_back({local(T[kTetFace[i][0]]), local(T[kTetFace[i][1]]), local(T[kTetFace[i][2]])});
    }
    std::vector<double> w;
    ASSERT_TRUE(mean_value_coordinates_3d(mesh.point(v), ring, link, w));
    Vec3 sum = Vec3::Zero();
    double total = 0;
    for (std::size_t j = 0; j < ring.size(); ++j) {
      sum += w[j] * ring[j];
      total += w[j];
    }
    EXPECT_NEAR(total, 1, 1e-12);
    EXPECT_LT((sum - mesh.point(v)).norm(), 1e-12) << "vertex " << v;
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

struct Cube {
  TetMesh mesh;
  DeformRegions regions;
  Cube(int n = 6, double jitter = 0.1) {
    const auto m = make_cube_mesh(n, jitter, 11);
    BuildOptions o;
    o.face_regions = m.face_regions;
    EXPECT_TRUE(mesh.build(m.points, m.tets, o));
    mesh.classify_vertices();
    for (int r = 0; r < 6; ++r) {
      SurfacePrimitive s;
      s.type = SurfaceType::Plane;
      s.axis = Vec3::Zero();
      s.axis[r / 2] = r % 2 ? 1.0 : -1.0;
      s.point = Vec3::Zero();
      s.point[r / 2] = r % 2 ? 1.0 : 0.0;
      regions.surfaces.push_back(s);
      regions.convexity.push_back(Convexity::NotApplicable);
    }
  }
  double volume() const {
    double v = 0;
    for (index_t t = 0; t < mesh.tet_slots(); ++t) {
      if (!mesh.tet_alive(t)) continue;
      const Tet& T = mesh.tet(t);
      v += tet_signed_volume(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3]));
    }
    return v;
  }
};

TEST(DeformClassification, DistanceOnACubeFace) {
  Cube c;
  const RegionGraph graph = region_adjacency(c.mesh, 6);
  DeformOptions o;
  o.type = DeformationType::Distance;
  o.control_region = 1;  // x = 1
  DeformPlan plan;
  ASSERT_TRUE(classify_surface_regions(c.mesh, c.regions, graph, o, plan));
  EXPECT_EQ(plan.reference, std::vector<index_t>{0});
  EXPECT_NEAR(plan.current, 1.0, 1e-14);
  EXPECT_EQ(plan.roles[1], RegionRole::Control);
  EXPECT_EQ(plan.roles[0], RegionRole::Fixed);
  for (int r = 2; r < 6; ++r) EXPECT_EQ(plan.roles[r], RegionRole::Deformed) << r;  // perpendicular: no chamfer
  find_valid_range(c.mesh, c.regions, plan);
  EXPECT_GE(plan.valid_min, 0);
  EXPECT_LT(plan.valid_min, 0.2);
  EXPECT_GT(plan.valid_max, 5);
}

TEST(DeformClassification, WrongControlTypeNamesBoth) {
  Cube c;
  const RegionGraph graph = region_adjacency(c.mesh, 6);
  DeformOptions o;
  o.type = DeformationType::CylinderRadius;
  o.control_region = 1;
  DeformPlan plan;
  const Status s = classify_surface_regions(c.mesh, c.regions, graph, o, plan);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message.find("is a plane"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("CylinderRadius needs a cylinder"), std::string::npos) << s.message;
}

TEST(DeformReposition, ParameterizeOnceRepositionManyIsLinearInTheChange) {
  Cube c;
  const RegionGraph graph = region_adjacency(c.mesh, 6);
  DeformOptions o;
  o.control_region = 1;
  DeformPlan plan;
  ASSERT_TRUE(classify_surface_regions(c.mesh, c.regions, graph, o, plan));
  VertexParameterization param;
  ASSERT_TRUE(parameterize_vertices(c.mesh, plan, {}, param));
  std::vector<Vec3> a, b;
  reposition_vertices(c.mesh, c.regions, param, update_region_surfaces(plan, c.regions, 1.2), a);
  reposition_vertices(c.mesh, c.regions, param, update_region_surfaces(plan, c.regions, 1.4), b);
  double worst = 0;
  for (index_t v = 0; v < c.mesh.vertex_slots(); ++v) {
    const Vec3 da = a[v] - c.mesh.point(v), db = b[v] - c.mesh.point(v);
    worst = std::max(worst, (db - 2 * da).norm());
    if (c.mesh.point(v).x() == 0) {
      EXPECT_EQ(a[v], c.mesh.point(v));  // the fixed face, bit for bit
    }
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(DeformMesh, DistanceStretchesTheCubeExactly) {
  Cube c;
  DeformOptions o;
  o.control_region = 1;
  o.local_region = false;
  DeformMeshOptions mo;
  mo.target = 1.5;
  mo.improve = false;
  DeformPlan plan;
  DeformReport report;
  const std::vector<Vec3> before = c.mesh.points();
  ASSERT_TRUE(deform_mesh(c.mesh, c.regions, nullptr, o, mo, plan, report));
  EXPECT_NEAR(c.volume(), 1.5, 1e-12);
  EXPECT_NEAR(c.regions.surfaces[1].point.x(), 1.5, 1e-15);
  for (index_t v = 0; v < c.mesh.vertex_slots(); ++v) {
    if (before[v].x() == 1) {
      EXPECT_NEAR(c.mesh.point(v).x(), 1.5, 1e-14);
    }
    if (before[v].x() == 0) {
      EXPECT_EQ(c.mesh.point(v), before[v]);
    }
    for (int k = 1; k < 3; ++k) {
      if (before[v][k] == 0 || before[v][k] == 1) {
        EXPECT_NEAR(c.mesh.point(v)[k], before[v][k], 1e-14);
      }
    }
  }
  EXPECT_GT(report.min_stretch_after, 0);
}

TEST(DeformMesh, TargetOutsideTheValidRangeIsRefusedWithTheRange) {
  Cube c;
  DeformOptions o;
  o.control_region = 1;
  DeformMeshOptions mo;
  mo.target = -0.5;
  DeformPlan plan;
  DeformReport report;
  const std::vector<Vec3> before = c.mesh.points();
  const Status s = deform_mesh(c.mesh, c.regions, nullptr, o, mo, plan, report);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message.find("outside the valid range"), std::string::npos) << s.message;
  EXPECT_EQ(c.mesh.points(), before);
}

TEST(DeformMesh, ShrinkingWithImproveKeepsEveryTetPositive) {
  Cube c(6, 0.12);
  DeformOptions o;
  o.control_region = 1;
  DeformMeshOptions mo;
  mo.target = 0.3;
  DeformPlan plan;
  DeformReport report;
  ASSERT_TRUE(deform_mesh(c.mesh, c.regions, nullptr, o, mo, plan, report)) << "";
  EXPECT_NEAR(c.volume(), 0.3, 1e-12);
  EXPECT_GT(report.min_stretch_after, 0.2);
  EXPECT_TRUE(c.mesh.check_consistency());
}

}  // namespace
}  // namespace femorph

namespace femorph {
namespace {

TEST(DeformSession, RepositionsManyTargetsOnOneParameterisation) {
  Cube c;
  DeformOptions o;
  o.control_region = 1;
  DeformSession session;
  ASSERT_TRUE(session.prepare(c.mesh, c.regions, o));
  std::vector<Vec3> points;
  std::vector<SurfacePrimitive> surfaces;
  bool reused = true;
  ASSERT_TRUE(session.reposition(1.4, points, surfaces, &reused));
  EXPECT_FALSE(reused);  // the first target parameterises
  for (const double target : {1.3, 1.1, 1.2}) {
    ASSERT_TRUE(session.reposition(target, points, surfaces, &reused));
    EXPECT_TRUE(reused) << target;  // smaller changes keep it
    EXPECT_NEAR(surfaces[1].point.x(), target, 1e-14);
    for (index_t v = 0; v < c.mesh.vertex_slots(); ++v) {
      if (c.mesh.point(v).x() == 1) {
        EXPECT_NEAR(points[v].x(), target, 1e-14);
      }
    }
  }
  const Status out = session.reposition(-3, points, surfaces);
  ASSERT_FALSE(out);
  EXPECT_NE(out.message.find("valid range"), std::string::npos);
}

}  // namespace
}  // namespace femorph

namespace femorph {
namespace {

// Superposition answers exactly the right sides in the span of solved ones
// and refuses the others (which then need a solve).
TEST(SolveHistory, SuperposesOnlyInsideTheSpan) {
  const Eigen::MatrixXd map = Eigen::MatrixXd::Random(5, 7);  // a linear solution operator
  const Eigen::MatrixXd k1 = Eigen::MatrixXd::Random(7, 3), k2 = Eigen::MatrixXd::Random(7, 3);
  SolveHistory history;
  Eigen::MatrixXd u;
  EXPECT_FALSE(history.superpose(k1, 5, u));
  EXPECT_TRUE(history.superpose(Eigen::MatrixXd::Zero(7, 3), 5, u));  // no move: no solve
  EXPECT_EQ(u.norm(), 0.0);
  history.add(k1, map * k1);
  history.add(2.5 * k1, map * (2.5 * k1));  // no new direction
  EXPECT_EQ(history.size(), 1u);
  ASSERT_TRUE(history.superpose(-0.4 * k1, 5, u));
  EXPECT_LE((u - map * (-0.4 * k1)).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_FALSE(history.superpose(k1 + k2, 5, u));
  // The superposed part (a warm start): the solution of its projection on the span.
  const double c = (k1.array() * (k1 + k2).array()).sum() / k1.squaredNorm();
  EXPECT_LE((u - map * (c * k1)).cwiseAbs().maxCoeff(), 1e-12);
  history.add(k2, map * k2);
  ASSERT_TRUE(history.superpose(3 * k1 - 2 * k2, 5, u));
  EXPECT_LE((u - map * (3 * k1 - 2 * k2)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_FALSE(history.superpose(Eigen::MatrixXd::Random(6, 3), 5, u));  // another system's size
}

}  // namespace
}  // namespace femorph
