// Core/adapt (thesis chapter 3): the rigid motion model, the grids, the
// deformed region, and whole motions checked after every step by the
// independent validity checker: valid mesh, outer boundary unchanged, the
// object moved rigidly, quality and vertex count kept.
#include "adapt/adapt.h"
#include "io/read_medit_mesh.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"
#include "test_adapt_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

namespace femorph {
namespace {

using testing::CylinderHalfTube;
using testing::make_block_in_box;
using testing::make_cylinder_half_tube;
using testing::MaterialMesh;

double min_stretch(const std::vector<Vec3>& p, const std::vector<Tet>& tets) {
  double m = 1;
  for (const Tet& t : tets) m = std::min(m, tet_stretch(p[t[0]], p[t[1]], p[t[2]], p[t[3]]));
  return m;
}

/// Boundary faces (faces of one tet) as sorted coordinate triples.
std::vector<std::array<std::array<double, 3>, 3>> outer_faces(const std::vector<Vec3>& p, const std::vector<Tet>& tets) {
  static const int kF[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::map<std::array<index_t, 3>, int> count;
  for (const Tet& t : tets)
    for (const auto& f : kF) {
      std::array<index_t, 3> k{{t[f[0]], t[f[1]], t[f[2]]}};
      std::sort(k.begin(), k.end());
      ++count[k];
    }
  std::vector<std::array<std::array<double, 3>, 3>> out;
  for (const auto& [k, n] : count) {
    if (n != 1) continue;
    std::array<std::array<double, 3>, 3> f;
    for (int i = 0; i < 3; ++i) f[i] = {p[k[i]].x(), p[k[i]].y(), p[k[i]].z()};
    std::sort(f.begin(), f.end());
    out.push_back(f);
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The object's cells of the output, mapped back by the inverse pose, are
/// the input object's cells (each output tet against the input cell it
/// descends from, vertex by vertex): the largest distance, or 1e30 when the
/// object lost or gained a cell.
double object_rigid_error(const MaterialMesh& in, const AdaptOutput& out, const RigidPose& pose, int object) {
  const RigidPose back = pose.inverse();
  double worst = 0;
  std::size_t count_in = 0, count_out = 0;
  for (std::size_t t = 0; t < in.tets.size(); ++t) count_in += in.material[t] == object;
  for (std::size_t t = 0; t < out.tets.size(); ++t) {
    if (out.material[t] != object) continue;
    ++count_out;
    const Tet& T = out.tets[t];
    const Tet& I = in.tets[static_cast<std::size_t>(out.cell_origin[t])];
    if (in.material[static_cast<std::size_t>(out.cell_origin[t])] != object) return 1e30;
    for (int k = 0; k < 4; ++k) worst = std::max(worst, (back.apply(out.points[T[k]]) - in.points[I[k]]).norm());
  }
  return count_in == count_out ? worst : 1e30;
}

struct MotionCheck {
  double worst_min_stretch = 1;
  double worst_drift = 0;
  int steps = 0;
};

/// Runs `steps` steps and checks every one; returns the worst figures.
MotionCheck run_and_check(const MaterialMesh& in, const RigidMotion& motion, int steps, AdaptOptions options = {}) {
  MotionCheck c;
  AdaptSession session;
  const Status s = session.init(in.points, in.tets, in.material, motion, options);
  EXPECT_TRUE(s.ok) << s.message;
  if (!s) return c;
  const auto outer0 = outer_faces(in.points, in.tets);
  Vec3 lo = in.points[0], hi = lo;
  for (const Vec3& p : in.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double scale = (hi - lo).norm();
  for (int n = 1; n <= steps; ++n) {
    AdaptStepReport report;
    const Status st = session.advance(&report);
    EXPECT_TRUE(st.ok) << st.message;
    if (!st) return c;
    const AdaptOutput out = session.output();
    const ValidityReport v = check_validity(out.points, out.tets);
    EXPECT_TRUE(v.ok()) << "step " << n << ": " << v.summary();
    EXPECT_EQ(outer_faces(out.points, out.tets), outer0) << "step " << n << ": the outer boundary changed";
    EXPECT_LT(object_rigid_error(in, out, motion.pose(n), options.moving_object), 1e-9 * scale)
        << "step " << n << ": the object did not move rigidly";
    const double ms = min_stretch(out.points, out.tets);
    EXPECT_NEAR(ms, report.min_stretch, 1e-9);
    c.worst_min_stretch = std::min(c.worst_min_stretch, ms);
    c.worst_drift = std::max(c.worst_drift, std::abs(double(out.points.size()) / double(in.points.size()) - 1));
    c.steps = n;
    if (::testing::Test::HasFailure()) return c;
  }
  return c;
}

TEST(RigidPose, MotionModelComposesAndInverts) {
  RigidMotion m;
  m.translation_per_step = Vec3(0, 0, 0.1);
  m.rotation_axis = Vec3(2, 0, 0);
  m.rotation_center = Vec3(1, 2, 3);
  m.rotation_degrees_per_step = 1;
  const RigidPose p = m.pose(90);
  // The centre only translates; a point off it turns a quarter about x.
  EXPECT_LT((p.apply(m.rotation_center) - Vec3(1, 2, 12)).norm(), 1e-12);
  EXPECT_LT((p.apply(Vec3(1, 3, 3)) - Vec3(1, 2, 13)).norm(), 1e-12);
  EXPECT_LT((p.inverse().apply(p.apply(Vec3(4, 5, 6))) - Vec3(4, 5, 6)).norm(), 1e-12);
  // Sub-steps: two halves of a step make the step.
  const RigidPose step = m.pose(1);
  const RigidPose half = step.fraction(0.5);
  EXPECT_LT((half.after(half).apply(Vec3(3, -1, 2)) - step.apply(Vec3(3, -1, 2))).norm(), 1e-12);
}

TEST(RigidPose, MatrixRowsAreChecked) {
  RigidPose p;
  const double rigid[16] = {0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1};
  EXPECT_TRUE(rigid_pose_from_matrix(rigid, p).ok);
  EXPECT_LT((p.apply(Vec3(1, 0, 0)) - Vec3(1, 3, 3)).norm(), 1e-15);
  const double scaled[16] = {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const Status s = rigid_pose_from_matrix(scaled, p);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.message.find("not a rotation"), std::string::npos) << s.message;
  const double mirror[16] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_FALSE(rigid_pose_from_matrix(mirror, p).ok);
  const double projective[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0, 0, 1};
  EXPECT_FALSE(rigid_pose_from_matrix(projective, p).ok);
}

TEST(DistanceGrid, MarchesOutwardUpToTheThreshold) {
  const DistanceGrid g = build_distance_grid({Vec3(0.5, 0.5, 0.5)}, 1.0, 3);
  EXPECT_EQ(g.at(Vec3(0.5, 0.5, 0.5)), 0);
  EXPECT_EQ(g.at(Vec3(1.5, 1.5, 0.5)), 1);
  EXPECT_EQ(g.at(Vec3(3.5, 0.5, 0.5)), 3);
  EXPECT_TRUE(std::isinf(g.at(Vec3(10.5, 0.5, 0.5))));
}

TEST(AdaptSession, TranslationAndRotationKeepTheMeshValidEveryStep) {
  const MaterialMesh in = make_block_in_box({8, 8, 12}, {2, 3, 1}, 1.0, 0.15, 5);
  RigidMotion motion;
  motion.translation_per_step = Vec3(0, 0, 0.1);
  motion.rotation_center = 0.5 * (in.object_lo + in.object_hi);
  motion.rotation_axis = Vec3(1, 0, 0);
  motion.rotation_degrees_per_step = 4;
  const MotionCheck c = run_and_check(in, motion, 20);
  EXPECT_EQ(c.steps, 20);
  const double input_min = min_stretch(in.points, in.tets);
  EXPECT_GE(c.worst_min_stretch, std::min(0.2, input_min)) << "input " << input_min;
  EXPECT_LT(c.worst_drift, 0.05);
}

TEST(AdaptSession, AFullTurnInPlaceKeepsQualityAndVertexCount) {
  const MaterialMesh in = make_block_in_box({8, 8, 8}, {3, 2, 1}, 1.0, 0.15, 9);
  RigidMotion motion;
  motion.rotation_center = 0.5 * (in.object_lo + in.object_hi);
  motion.rotation_axis = Vec3(0, 0.3, 1);
  motion.rotation_degrees_per_step = 10;
  const MotionCheck c = run_and_check(in, motion, 36);
  EXPECT_EQ(c.steps, 36);
  EXPECT_GE(c.worst_min_stretch, std::min(0.2, min_stretch(in.points, in.tets)));
  EXPECT_LT(c.worst_drift, 0.05);
}

/// Other motions than the thesis': each checked every step, and no step's
/// minimum stretch below the input's (issue 27's goal).
struct OtherMotion {
  const char* name;
  Vec3 translation, axis, centre_offset;
  double degrees;
  int steps;
};

void PrintTo(const OtherMotion& m, std::ostream* os) { *os << m.name; }

class OtherMotions : public ::testing::TestWithParam<OtherMotion> {};

TEST_P(OtherMotions, StayValidAndAboveTheInputsMinimumStretch) {
  const OtherMotion& m = GetParam();
  const MaterialMesh in = make_block_in_box({10, 10, 10}, {3, 2, 1}, 1.0, 0.15, 3, {{-1, -1, -1}}, 1);
  RigidMotion motion;
  motion.translation_per_step = m.translation;
  motion.rotation_axis = m.axis;
  motion.rotation_center = 0.5 * (in.object_lo + in.object_hi) + m.centre_offset;
  motion.rotation_degrees_per_step = m.degrees;
  const MotionCheck c = run_and_check(in, motion, m.steps);
  EXPECT_EQ(c.steps, m.steps);
  EXPECT_GE(c.worst_min_stretch, min_stretch(in.points, in.tets));
  EXPECT_LT(c.worst_drift, 0.03);
}

INSTANTIATE_TEST_SUITE_P(
    Adapt, OtherMotions,
    ::testing::Values(OtherMotion{"rotation45", Vec3::Zero(), Vec3(0, 0, 1), Vec3::Zero(), 45, 4},
                      OtherMotion{"diagonal", Vec3(0.2, 0.2, 0.2), Vec3(1, 0, 0), Vec3::Zero(), 0, 6},
                      OtherMotion{"orbit", Vec3::Zero(), Vec3(0, 0, 1), Vec3(1.5, 0, 0), 5, 8},
                      OtherMotion{"unnormalised_negative", Vec3(0, 0, -0.05), Vec3(0, 3, 4), Vec3::Zero(), -7, 6},
                      OtherMotion{"one_cube_per_step", Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3::Zero(), 0, 2}),
    [](const ::testing::TestParamInfo<OtherMotion>& info) { return std::string(info.param.name); });

TEST(AdaptSession, SpaceDataIsInterpolatedInSpaceAndObjectDataMovesWithIt) {
  const MaterialMesh in = make_block_in_box({8, 8, 10}, {2, 2, 1}, 1.0, 0.1, 2);
  RigidMotion motion;
  motion.translation_per_step = Vec3(0, 0, 0.1);
  motion.rotation_center = 0.5 * (in.object_lo + in.object_hi);
  motion.rotation_degrees_per_step = 3;
  AdaptSession s;
  ASSERT_TRUE(s.init(in.points, in.tets, in.material, motion, {}).ok);
  // A linear field f(x) = a . x, carried step by step by point_previous: at
  // a space vertex it should stay f at the vertex's position (linear
  // interpolation is exact for it, up to the 4-term truncation), at an
  // object vertex f at its rest position (it moves with the object).
  const Vec3 a(1, 2, 3);
  std::vector<double> field;
  for (const Vec3& p : in.points) field.push_back(a.dot(p));
  double worst_space = 0, worst_object = 0, lagrangian = 0;  // space: sums, then means
  int moved = 0;
  for (int n = 1; n <= 10; ++n) {
    ASSERT_TRUE(s.advance().ok);
    const AdaptOutput out = s.output();
    ASSERT_EQ(out.point_previous.size(), out.points.size());
    std::vector<double> next(out.points.size(), 0.0);
    for (std::size_t v = 0; v < out.points.size(); ++v)
      for (int k = 0; k < 4; ++k)
        if (out.point_previous[v].ids[k] >= 0) next[v] += out.point_previous[v].weights[k] * field[out.point_previous[v].ids[k]];
    field = std::move(next);
    if (n < 10) continue;
    std::vector<char> on_object(out.points.size(), 0);
    for (std::size_t t = 0; t < out.tets.size(); ++t)
      if (out.material[t] == 1)
        for (const index_t v : out.tets[t]) on_object[v] = 1;
    const RigidPose back = motion.pose(n).inverse();
    std::vector<Vec3> object_points;
    for (std::size_t v = 0; v < out.points.size(); ++v)
      if (on_object[v]) object_points.push_back(out.points[v]);
    for (std::size_t v = 0; v < out.points.size(); ++v) {
      if (on_object[v]) {
        worst_object = std::max(worst_object, std::abs(field[v] - a.dot(back.apply(out.points[v]))));
        continue;
      }
      // Next to the object the field mixes with the object's, which moves
      // with it: no linear field there.
      double near = 1e30;
      for (const Vec3& q : object_points) near = std::min(near, (q - out.points[v]).norm());
      if (near < 1.5) continue;
      // What keeping the input's value (the material-following provenance) would give.
      const VertexStencil& o = out.point_origin[v];
      double carried = 0;
      for (int k = 0; k < 4; ++k)
        if (o.ids[k] >= 0) carried += o.weights[k] * a.dot(in.points[o.ids[k]]);
      if (std::abs(carried - a.dot(out.points[v])) < 1e-9) continue;  // did not move
      worst_space += std::abs(field[v] - a.dot(out.points[v]));
      lagrangian += std::abs(carried - a.dot(out.points[v]));
      ++moved;
    }
  }
  EXPECT_LT(worst_object, 1e-9);
  ASSERT_GT(moved, 50);
  worst_space /= moved;
  lagrangian /= moved;
  // Away from the object, the data follows space, not the moving vertices:
  // far below what keeping each vertex's value gives.
  EXPECT_LT(worst_space, 0.25 * lagrangian) << "space data not interpolated at the vertices' new positions";
  std::printf("linear field after 10 steps, %d moved space vertices: mean error %.3g (kept values: %.3g)\n", moved,
              worst_space, lagrangian);
}

TEST(AdaptSession, BadInputIsRefusedWithAMessage) {
  const MaterialMesh in = make_block_in_box({6, 6, 6}, {2, 2, 1}, 1.0, 0.1, 1);
  RigidMotion motion;
  motion.translation_per_step = Vec3(0.1, 0, 0);
  AdaptSession s;
  AdaptOptions o;
  o.moving_object = 7;
  Status st = s.init(in.points, in.tets, in.material, motion, o);
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("no cell has the moving object's material id 7"), std::string::npos) << st.message;
  std::vector<int> short_material(in.material.begin(), in.material.end() - 1);
  EXPECT_FALSE(s.init(in.points, in.tets, short_material, motion, {}).ok);
  std::vector<int> negative = in.material;
  negative[3] = -2;
  EXPECT_FALSE(s.init(in.points, in.tets, negative, motion, {}).ok);
  // An object touching the outer boundary cannot move without changing it.
  std::vector<int> touching = in.material;
  touching[0] = 1;
  st = s.init(in.points, in.tets, touching, motion, {});
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("outer boundary"), std::string::npos) << st.message;
  // An object whose points are duplicated (not merged with the space's):
  // a non-conformal interface.
  std::vector<Vec3> points = in.points;
  std::vector<Tet> tets = in.tets;
  std::vector<index_t> copy(points.size(), kInvalidIndex);
  for (std::size_t t = 0; t < tets.size(); ++t) {
    if (in.material[t] != 1) continue;
    for (index_t& v : tets[t]) {
      if (copy[v] < 0) {
        copy[v] = static_cast<index_t>(points.size());
        points.push_back(points[v]);
      }
      v = copy[v];
    }
  }
  st = s.init(points, tets, in.material, motion, {});
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("not conformal"), std::string::npos) << st.message;
}

TEST(AdaptSession, AStepIntoTheWallIsRefusedAndEarlierStepsKept) {
  const MaterialMesh in = make_block_in_box({6, 6, 6}, {2, 2, 1}, 1.0, 0.1, 3);
  RigidMotion motion;
  motion.translation_per_step = Vec3(0.6, 0, 0);  // the wall is 2 cubes away
  AdaptSession s;
  ASSERT_TRUE(s.init(in.points, in.tets, in.material, motion, {}).ok);
  int last_good = 0;
  Status st;
  for (int n = 1; n <= 6; ++n) {
    st = s.advance();
    if (!st) break;
    last_good = n;
  }
  ASSERT_FALSE(st.ok) << "the object went through the wall";
  EXPECT_NE(st.message.find("step " + std::to_string(last_good + 1) + " refused"), std::string::npos) << st.message;
  EXPECT_EQ(s.current_step(), last_good);
  // The object's right face is at x = 4 after 6 of 0.6, past the wall at
  // x = 6 after 4: refused by then, at the latest for crossing the boundary.
  EXPECT_LE(last_good, 3);
  const AdaptOutput out = s.output();
  EXPECT_TRUE(check_validity(out.points, out.tets).ok());
}

TEST(AdaptSession, AStepIntoAnotherObjectIsRefusedNamingIt) {
  // Object 1: cubes x 3..4, y 2..3, z 2; object 2: the cubes at x = 6 (a
  // gap of one cube). A step of 1.5 along x puts object 1 inside object 2.
  const std::array<int, 3> cells{{9, 6, 5}};
  MaterialMesh in = make_block_in_box(cells, {2, 2, 1}, 1.0, 0.1, 4, {{3, 2, 2}});
  for (int j = 2; j < 4; ++j) {
    const int cube = (2 * cells[1] + j) * cells[0] + 6;
    for (int k = 0; k < 12; ++k) in.material[static_cast<std::size_t>(12 * cube + k)] = 2;
  }
  RigidMotion motion;
  motion.translation_per_step = Vec3(1.5, 0, 0);
  AdaptSession s;
  ASSERT_TRUE(s.init(in.points, in.tets, in.material, motion, {}).ok);
  const Status st = s.advance();
  ASSERT_FALSE(st.ok);
  EXPECT_NE(st.message.find("step 1 refused"), std::string::npos) << st.message;
  EXPECT_NE(st.message.find("penetrate object 2"), std::string::npos) << st.message;
  EXPECT_EQ(s.current_step(), 0);
  // Half of it is no penetration: object 1 ends 0.25 from object 2.
  RigidMotion slow;
  slow.translation_per_step = Vec3(0.25, 0, 0);
  ASSERT_TRUE(s.init(in.points, in.tets, in.material, slow, {}).ok);
  for (int n = 1; n <= 3; ++n) EXPECT_TRUE(s.advance().ok) << "step " << n;
}

/// The boundary faces of the tets of one material (faces of exactly one of
/// them), as vertex triples.
std::vector<std::array<index_t, 3>> material_boundary(const MaterialMesh& m, int material) {
  std::map<std::array<index_t, 3>, int> count;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    if (m.material[t] != material) continue;
    for (const auto& f : kTetFace) {
      std::array<index_t, 3> k{{m.tets[t][f[0]], m.tets[t][f[1]], m.tets[t][f[2]]}};
      std::sort(k.begin(), k.end());
      ++count[k];
    }
  }
  std::vector<std::array<index_t, 3>> out;
  for (const auto& [k, n] : count)
    if (n == 1) out.push_back(k);
  return out;
}

double triangle_area(const std::vector<Vec3>& p, const std::array<index_t, 3>& f) {
  return 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).norm();
}

/// Thesis 3.7.3's input: the cylinder and the half tube meshed by TetGen
/// from exact surfaces, the space around them; checked as a whole.
TEST(CylinderHalfTube, IsValidWithExactPolygonVolumesAndSurfaces) {
  const CylinderHalfTube g;
  Status status;
  const MaterialMesh m = make_cylinder_half_tube(g, &status);
  ASSERT_TRUE(status.ok) << status.message;
  const ValidityReport v = check_validity(m.points, m.tets);
  ASSERT_TRUE(v.ok()) << v.summary();  // every tet positive, conformal, manifold
  // Volumes by material: the polygon prisms, and the box for all.
  double volume[3] = {0, 0, 0};
  std::size_t count[3] = {0, 0, 0};
  Vec3 lo = m.points[0], hi = lo;
  for (const Vec3& p : m.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    ASSERT_GE(m.material[t], 0);
    ASSERT_LE(m.material[t], 2);
    const Tet& T = m.tets[t];
    const Vec3 &a = m.points[T[0]], &b = m.points[T[1]], &c = m.points[T[2]], &d = m.points[T[3]];
    volume[m.material[t]] += (b - a).dot((c - a).cross(d - a)) / 6;
    ++count[m.material[t]];
  }
  EXPECT_NEAR(volume[1], g.cylinder_volume(), 1e-9 * g.cylinder_volume());
  EXPECT_NEAR(volume[2], g.half_tube_volume(), 1e-9 * g.half_tube_volume());
  const double box = (hi - lo).prod();
  EXPECT_NEAR(volume[0] + volume[1] + volume[2], box, 1e-9 * box);
  // The polygon volumes against the analytic ones (a coarse polygon).
  EXPECT_NEAR(g.cylinder_volume(), kPi * g.r * g.r * g.Lc, 0.05 * g.cylinder_volume());
  EXPECT_NEAR(g.half_tube_volume(), 0.5 * kPi * (g.R * g.R - g.r * g.r) * g.Lt, 0.05 * g.half_tube_volume());

  // The cylinder's surface: off its caps, every vertex at distance r from
  // the axis; among them the points at theta = 0 and pi (y = 0 exactly).
  const double z0 = -g.Lc - g.gap, z1 = -g.gap, tol = 1e-12;
  std::vector<char> on_cylinder(m.points.size(), 0), on_tube(m.points.size(), 0);
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (const index_t x : m.tets[t]) {
      if (m.material[t] == 1) on_cylinder[x] = 1;
      if (m.material[t] == 2) on_tube[x] = 1;
    }
  std::map<std::pair<double, double>, int> cylinder_xy;  // side vertices by (x, y)
  std::size_t side = 0, shared = 0;
  for (const auto& f : material_boundary(m, 1))
    for (const index_t x : f) {
      const Vec3& p = m.points[x];
      if (std::abs(p.z() - z0) < tol || std::abs(p.z() - z1) < tol) continue;
      ++side;
      EXPECT_NEAR(std::hypot(p.x(), p.y()), g.r, tol) << "cylinder side vertex " << x;
      cylinder_xy[{p.x(), p.y()}] = 1;
    }
  EXPECT_EQ(cylinder_xy.size(), static_cast<std::size_t>(g.n_theta)) << "the side is n_theta lines of points";
  EXPECT_TRUE(cylinder_xy.count({g.r, 0.0}) && cylinder_xy.count({-g.r, 0.0})) << "theta = 0, pi not on the polygon";
  // The half tube: every vertex off y = 0 and its ends on radius r or R; the
  // inner ones at the cylinder's lower polygon corners (bit for bit).
  double inner_area = 0;
  for (const auto& f : material_boundary(m, 2)) {
    bool inner = true;
    for (const index_t x : f) {
      const Vec3& p = m.points[x];
      const double rho = std::hypot(p.x(), p.y());
      inner = inner && std::abs(rho - g.r) < tol;
      if (p.y() == 0 || std::abs(p.z()) < tol || std::abs(p.z() - g.Lt) < tol) continue;
      EXPECT_TRUE(std::abs(rho - g.r) < tol || std::abs(rho - g.R) < tol) << "half tube vertex " << x << " at " << rho;
      EXPECT_LT(p.y(), 0);
      if (std::abs(rho - g.r) < tol) {
        EXPECT_TRUE(cylinder_xy.count({p.x(), p.y()})) << "inner tube vertex " << x << " off the cylinder's polygon";
      }
    }
    if (inner) inner_area += triangle_area(m.points, f);
  }
  // The tube's inner surface is the discrete contact surface: n_half chords
  // x Lt (what cylinder_half_tube_contact_area's `discrete` counts).
  const double chord = 2 * g.r * std::sin(kPi / (2 * g.n_half()));
  EXPECT_NEAR(inner_area, g.n_half() * chord * g.Lt, 1e-12 * inner_area);
  for (std::size_t x = 0; x < m.points.size(); ++x) shared += on_cylinder[x] && on_tube[x];
  EXPECT_EQ(shared, 0u) << "the cylinder and the half tube share vertices at step 0";
  // The objects inside the box, off its faces.
  for (std::size_t x = 0; x < m.points.size(); ++x)
    if (on_cylinder[x] || on_tube[x]) {
      EXPECT_TRUE((m.points[x].array() > lo.array()).all() && (m.points[x].array() < hi.array()).all());
    }
  EXPECT_GT(count[0], count[1] + count[2]);
  EXPECT_GT(side, 0u);
  std::printf("3.7.3 case (default size, n_theta %d): %zu tets (space %zu, cylinder %zu, half tube %zu), %zu points, "
              "min stretch %.3f\n",
              g.n_theta, m.tets.size(), count[0], count[1], count[2], m.points.size(), min_stretch(m.points, m.tets));
  // Deterministic: the same mesh again.
  const MaterialMesh again = make_cylinder_half_tube(g);
  EXPECT_TRUE(again.points == m.points && again.tets == m.tets && again.material == m.material);
}

TEST(CylinderHalfTube, BenchmarkSizeIsTheThesis) {
  // 3.7.3's input has 160,791 tets and 31,530 vertices.
  const CylinderHalfTube g = CylinderHalfTube::benchmark();
  Status status;
  const MaterialMesh m = make_cylinder_half_tube(g, &status);
  ASSERT_TRUE(status.ok) << status.message;
  EXPECT_GT(m.tets.size(), 120000u);
  EXPECT_LT(m.tets.size(), 200000u);
  double volume[3] = {0, 0, 0};
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const Tet& T = m.tets[t];
    const Vec3 &a = m.points[T[0]], &b = m.points[T[1]], &c = m.points[T[2]], &d = m.points[T[3]];
    volume[m.material[t]] += (b - a).dot((c - a).cross(d - a)) / 6;
  }
  EXPECT_NEAR(volume[1], g.cylinder_volume(), 1e-9 * g.cylinder_volume());
  EXPECT_NEAR(volume[2], g.half_tube_volume(), 1e-9 * g.half_tube_volume());
  std::printf("3.7.3 benchmark case (n_theta %d, edge %.3f): %zu tets, %zu points, min stretch %.3f\n", g.n_theta,
              g.edge(), m.tets.size(), m.points.size(), min_stretch(m.points, m.tets));
}

// improve_material_mesh (make_cylinder_half_tube's last step): each
// material improved with its boundary fixed keeps every boundary and
// interface triangle where it was, and raises each material's minimum
// stretch (TetGen's -q leaves slivers in all three).
TEST(CylinderHalfTube, ImprovedPerMaterialKeepsEverySurface) {
  CylinderHalfTube g;
  g.improve = false;
  const MaterialMesh raw = make_cylinder_half_tube(g);
  g.improve = true;
  const MaterialMesh m = make_cylinder_half_tube(g);
  ASSERT_FALSE(raw.tets.empty());
  ASSERT_FALSE(m.tets.empty());
  const ValidityReport v = check_validity(m.points, m.tets);
  ASSERT_TRUE(v.ok()) << v.summary();
  using Corners = std::array<std::array<double, 3>, 3>;
  const auto surface = [](const MaterialMesh& mesh, int material) {
    std::vector<Corners> out;
    for (const auto& f : material_boundary(mesh, material)) {
      Corners c;
      for (int k = 0; k < 3; ++k) c[k] = {{mesh.points[f[k]].x(), mesh.points[f[k]].y(), mesh.points[f[k]].z()}};
      std::sort(c.begin(), c.end());
      out.push_back(c);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  const auto worst = [](const MaterialMesh& mesh, int material) {
    double lo = 1;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
      if (mesh.material[t] == material) {
        const Tet& T = mesh.tets[t];
        lo = std::min(lo, tet_stretch(mesh.points[T[0]], mesh.points[T[1]], mesh.points[T[2]], mesh.points[T[3]]));
      }
    return lo;
  };
  for (int material = 0; material <= 2; ++material) {
    EXPECT_EQ(surface(m, material), surface(raw, material)) << "material " << material << "'s boundary changed";
    EXPECT_GE(worst(m, material), worst(raw, material)) << "material " << material;
  }
  EXPECT_GT(min_stretch(m.points, m.tets), min_stretch(raw.points, raw.tets));
  EXPECT_GE(min_stretch(m.points, m.tets), 0.15);
}

TEST(CylinderHalfTube, ContactAreaOfAStep) {
  CylinderHalfTube g;
  g.Lc = 3;
  g.Lt = 4;
  g.gap = 0.5;
  using testing::cylinder_half_tube_contact_area;
  EXPECT_EQ(cylinder_half_tube_contact_area(g, 0).overlap, 0);    // step 0: no contact
  EXPECT_EQ(cylinder_half_tube_contact_area(g, 0.5).overlap, 0);  // touching the tube's end
  EXPECT_DOUBLE_EQ(cylinder_half_tube_contact_area(g, 1).overlap, 0.5);
  EXPECT_DOUBLE_EQ(cylinder_half_tube_contact_area(g, 3).overlap, 2.5);
  EXPECT_DOUBLE_EQ(cylinder_half_tube_contact_area(g, 4).overlap, 3);    // all the cylinder inside
  EXPECT_DOUBLE_EQ(cylinder_half_tube_contact_area(g, 6.5).overlap, 1);  // coming out at z = Lt
  EXPECT_EQ(cylinder_half_tube_contact_area(g, 20).overlap, 0);
  const auto a = cylinder_half_tube_contact_area(g, 3);
  EXPECT_DOUBLE_EQ(a.exact, kPi * g.r * 2.5);
  // The polygon against the circle: n chords 2 r sin(pi / 2n) over pi r.
  const double x = kPi / (2 * g.n_half());
  EXPECT_NEAR(a.discrete / a.exact, std::sin(x) / x, 1e-14);
  EXPECT_LT(a.discrete, a.exact);
  std::printf("contact at s = 3 (overlap 2.5, n_theta %d): exact %.6f, discrete %.6f (%.2f%% below)\n", g.n_theta,
              a.exact, a.discrete, 100 * (1 - a.discrete / a.exact));
}

TEST(CylinderHalfTube, BadParametersAreRefused) {
  CylinderHalfTube g;
  g.n_theta = 13;  // theta = pi would not be a segment boundary
  Status status;
  EXPECT_TRUE(make_cylinder_half_tube(g, &status).tets.empty());
  EXPECT_FALSE(status.ok);
  g = CylinderHalfTube();
  g.R = g.r;  // no tube wall
  EXPECT_TRUE(make_cylinder_half_tube(g, &status).tets.empty());
  EXPECT_FALSE(status.ok);
  g = CylinderHalfTube();
  g.gap = 0;  // contact at step 0
  EXPECT_FALSE((make_cylinder_half_tube(g, &status), status.ok));
}

/// A real part made by someone else (../shared/realparts) as the moving
/// object, in a box meshed around it by mesh_space_around: 8 steps of a
/// translation and a rotation about a tilted axis, checked every step.
class RealPartInBox : public ::testing::TestWithParam<const char*> {};

TEST_P(RealPartInBox, MovesThroughTheBoxCheckedEveryStep) {
  const std::string path = std::string(FEMORPH_REALPARTS_DIR) + "/" + GetParam();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found";
  MeditMesh medit;
  ASSERT_TRUE(read_medit_mesh(path, medit).ok);
  std::vector<Vec3> points = medit.points;
  std::vector<Tet> tets = medit.tets;
  for (Tet& t : tets) {
    const Vec3 &a = points[t[0]], &b = points[t[1]], &c = points[t[2]], &d = points[t[3]];
    if ((b - a).dot((c - a).cross(d - a)) < 0) std::swap(t[0], t[1]);
  }
  Vec3 lo = points[0], hi = lo;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 size = hi - lo;
  const double diagonal = size.norm();
  MaterialMesh in;
  const Status s = mesh_space_around(points, tets, std::vector<int>(tets.size(), 1), lo - 0.5 * diagonal * Vec3::Ones(),
                                     hi + 0.5 * diagonal * Vec3::Ones(), 0, in.points, in.tets, in.material);
  ASSERT_TRUE(s.ok) << s.message;
  ASSERT_TRUE(check_validity(in.points, in.tets).ok()) << check_validity(in.points, in.tets).summary();
  RigidMotion motion;
  motion.translation_per_step = Vec3(0.005, 0.0025, -0.004) * diagonal;
  motion.rotation_center = 0.5 * (lo + hi);
  motion.rotation_axis = Vec3(0.2, 1, 0.4);
  motion.rotation_degrees_per_step = 1;
  const MotionCheck c = run_and_check(in, motion, 8);
  EXPECT_EQ(c.steps, 8);
  // The part's own slivers stay (it moves rigidly); the space may not fall
  // below them.
  EXPECT_GE(c.worst_min_stretch, 0.9 * min_stretch(in.points, in.tets));
  EXPECT_LT(c.worst_drift, 0.03);
  std::printf("%s in a box: %zu tets, %zu points; over 8 steps min stretch %.3f (input %.3f), drift %.2f%%\n",
              GetParam(), in.tets.size(), in.points.size(), c.worst_min_stretch, min_stretch(in.points, in.tets),
              100 * c.worst_drift);
}

INSTANTIATE_TEST_SUITE_P(SharedRealParts, RealPartInBox, ::testing::Values("chamfer_tet.mesh", "fandisk_tet.mesh"));

}  // namespace
}  // namespace femorph
