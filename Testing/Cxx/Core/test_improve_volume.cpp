// Phase (3) of Phased ODT smoothing (thesis 2.6.5.4): ODT smoothing of the
// inner vertices and quality-raising flips repair randomly displaced inner
// vertices without touching the boundary.
#include "improve/ball_quality.h"
#include "improve/improve_tets_by_flips.h"
#include "improve/improve_volume.h"
#include "improve/odt_smooth_volume.h"
#include "improve/optimize_worst_vertices.h"
#include "improve/scan_live_tets.h"
#include "improve/split_locked_tets.h"
#include "io/read_medit_mesh.h"
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "test_meshes.h"
#include "test_threads.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>

namespace femorph {
namespace {

/// Moves every inner vertex (id order) by a random vector of length up to
/// `fraction` of its mean edge length; moves that would invert are refused
/// by TetMesh, so the mesh stays valid. Returns the number of moves made.
int perturb_inner_vertices(TetMesh& m, double fraction, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<index_t> nb;
  int moved = 0;
  for (index_t v = 0; v < m.vertex_slots(); ++v) {
    if (!m.vertex_alive(v) || m.vertex_class(v) != VertexClass::Inner) continue;
    m.vertex_neighbors(v, nb);
    double len = 0;
    for (index_t w : nb) len += (m.point(w) - m.point(v)).norm();
    len /= static_cast<double>(nb.size());
    Vec3 d;
    do d = Vec3(u(rng), u(rng), u(rng));
    while (d.squaredNorm() > 1);
    moved += m.move_vertex(v, m.point(v) + fraction * len * d) == OpStatus::Ok;
  }
  return moved;
}

/// What every run must satisfy: valid, same volume, boundary in place.
void expect_valid_and_boundary_fixed(const TetMesh& before, const TetMesh& after, double volume) {
  ASSERT_TRUE(after.check_consistency().ok) << after.check_consistency().message;
  const CompactMesh out = after.compact();
  const ValidityReport report = check_validity(out.points, out.tets);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_NEAR(testing::total_volume(out.points, out.tets), volume, 1e-12 * volume);
  ASSERT_EQ(before.vertex_slots(), after.vertex_slots());
  std::size_t moved_boundary = 0;
  for (index_t v = 0; v < before.vertex_slots(); ++v)
    if (before.vertex_alive(v) && before.on_boundary(v))
      moved_boundary += std::memcmp(before.point(v).data(), after.point(v).data(), 3 * sizeof(double)) != 0;
  EXPECT_EQ(moved_boundary, 0u);
}

TetMesh perturbed_cube(double* volume, double* undeformed_mean) {
  const testing::TestMesh cube = testing::make_cube_mesh(8, 0.1, 3);
  BuildOptions options;
  options.face_regions = cube.face_regions;
  TetMesh m;
  EXPECT_TRUE(m.build(cube.points, cube.tets, options).ok);
  *volume = testing::total_volume(cube.points, cube.tets);
  live_stretch_range(m, nullptr, undeformed_mean);
  EXPECT_GT(perturb_inner_vertices(m, 0.4, 11), 200);
  return m;
}

// The shared scan of Improve's full-mesh passes: every live tet once, none
// of the dead slots collapses leave, each chunk's slots in order, the same
// for 1 and 2 threads.
TEST(ScanLiveTets, VisitsLiveTetsInSlotOrderPerChunk) {
  TetMesh m;
  const auto cube = testing::make_cube_mesh(14, 0.1, 3);
  ASSERT_TRUE(m.build(cube.points, cube.tets).ok);
  std::vector<index_t> nb;
  int collapsed = 0;
  for (index_t v = 0; v < m.vertex_slots() && collapsed < 40; v += 97) {
    if (!m.vertex_alive(v) || m.vertex_class(v) != VertexClass::Inner) continue;
    m.vertex_neighbors(v, nb);
    for (const index_t w : nb)
      if (m.vertex_class(w) == VertexClass::Inner && m.collapse_edge(Keep{w}, Remove{v}, nullptr) == OpStatus::Ok) {
        ++collapsed;
        break;
      }
  }
  ASSERT_GT(collapsed, 10);
  std::vector<index_t> live;
  for (index_t t = 0; t < m.tet_slots(); ++t)
    if (m.tet_alive(t)) live.push_back(t);
  ASSERT_LT(live.size(), static_cast<std::size_t>(m.tet_slots()));
  ASSERT_GT(m.tet_slots(), 2 * kTetScanChunk);  // several chunks, run in parallel
  for (const int threads : {1, 2}) {
    const auto chunks = testing::with_threads(threads, [&] {
      return scan_live_tets(m, std::vector<index_t>{}, [](index_t t, std::vector<index_t>& out) { out.push_back(t); });
    });
    ASSERT_EQ(static_cast<long>(chunks.size()), (m.tet_slots() + kTetScanChunk - 1) / kTetScanChunk);
    for (std::size_t c = 0; c < chunks.size(); ++c)
      for (const index_t t : chunks[c]) {
        EXPECT_GE(t, static_cast<index_t>(c * kTetScanChunk));
        EXPECT_LT(t, static_cast<index_t>((c + 1) * kTetScanChunk));
      }
    std::vector<index_t> joined{42};  // replaced, not appended to
    join_chunks(chunks, [](const std::vector<index_t>& f) -> const std::vector<index_t>& { return f; }, &joined);
    EXPECT_EQ(joined, live) << threads << " thread(s)";
  }
}

TEST(ImproveVolume, JitteredCubeReachesGoal) {
  double volume = 0, undeformed_mean = 0;
  TetMesh m = perturbed_cube(&volume, &undeformed_mean);
  const TetMesh before = m;
  const ImproveVolumeStats s = improve_volume(m);
  std::printf("cube 8^3: stretch min %.4f -> %.4f, mean %.4f -> %.4f (undeformed mean %.4f); moved %zu refused %zu; "
              "flips 2-3 %zu 3-2 %zu 4-4 %zu; %d rounds, %.3f s\n",
              s.min_stretch_before, s.min_stretch_after, s.mean_stretch_before, s.mean_stretch_after, undeformed_mean,
              s.moved, s.refused, s.flips_23, s.flips_32, s.flips_44, s.rounds, s.seconds);
  expect_valid_and_boundary_fixed(before, m, volume);
  EXPECT_GE(s.min_stretch_after, s.min_stretch_before);
  EXPECT_GE(s.min_stretch_after, 0.3);
  EXPECT_GT(s.mean_stretch_after, s.mean_stretch_before);
  EXPECT_GE(s.mean_stretch_after, undeformed_mean);
  EXPECT_GT(s.moved, 0u);
}

TEST(ImproveVolume, SmoothingAloneIsMonotoneAndKeepsBoundary) {
  double volume = 0, undeformed_mean = 0;
  TetMesh m = perturbed_cube(&volume, &undeformed_mean);
  const TetMesh before = m;
  double min0 = 0, mean0 = 0, min1 = 0, mean1 = 0;
  live_stretch_range(m, &min0, &mean0);
  const OdtSmoothReport r = odt_smooth_volume(m);
  live_stretch_range(m, &min1, &mean1);
  std::printf("smoothing only: min %.4f -> %.4f, mean %.4f -> %.4f, moved %zu refused %zu halvings %zu\n", min0, min1,
              mean0, mean1, r.moved, r.refused, r.halvings);
  expect_valid_and_boundary_fixed(before, m, volume);
  EXPECT_GE(min1, min0);
  EXPECT_GT(mean1, mean0);
  EXPECT_EQ(r.sweeps, 3);
}

/// The input of the thread-count tests: a jittered 14^3 cube with its inner
/// vertices moved by up to 40% of the local edge length.
TetMesh perturbed_cube() {
  const testing::TestMesh cube = testing::make_cube_mesh(14, 0.1, 5);
  TetMesh m;
  EXPECT_TRUE(m.build(cube.points, cube.tets).ok);
  EXPECT_GT(perturb_inner_vertices(m, 0.4, 7), 1000);
  return m;
}

/// Vertex slots whose points differ in any bit between two runs on copies
/// of one mesh.
std::size_t points_differing(const TetMesh& one, const TetMesh& two) {
  std::size_t differ = 0;
  for (index_t v = 0; v < one.vertex_slots(); ++v)
    differ += std::memcmp(one.point(v).data(), two.point(v).data(), 3 * sizeof(double)) != 0;
  return differ;
}

// The coloured, parallel sweeps (odt_smooth_volume.h) must give the same
// points whatever the number of threads: reproducible outputs.
TEST(ImproveVolume, SmoothingDoesNotDependOnThreadCount) {
  const TetMesh m = perturbed_cube();
  TetMesh one = m, two = m;
  const OdtSmoothReport r1 = testing::with_threads(1, [&] { return odt_smooth_volume(one); });
  const OdtSmoothReport r2 = testing::with_threads(2, [&] { return odt_smooth_volume(two); });
  EXPECT_GT(r1.moved, 1000u);
  EXPECT_EQ(r1.moved, r2.moved);
  EXPECT_EQ(r1.halvings, r2.halvings);
  EXPECT_EQ(points_differing(one, two), 0u);
}

// The worst-vertex search runs colour by colour in parallel: the same
// points for any number of threads, and the minimum never drops.
TEST(ImproveVolume, WorstVertexSearchDoesNotDependOnThreadCount) {
  const TetMesh m = perturbed_cube();
  TetMesh one = m, two = m;
  WorstVertexOptions options;
  options.threshold = 0.5;  // enough candidates for colours of 64 and more
  const WorstVertexStats r1 = testing::with_threads(1, [&] { return optimize_worst_vertices(one, options); });
  const WorstVertexStats r2 = testing::with_threads(2, [&] { return optimize_worst_vertices(two, options); });
  std::printf("candidates %zu, improved %zu\n", r1.candidates, r1.improved);
  EXPECT_GT(r1.improved, 500u);
  EXPECT_EQ(r1.candidates, r2.candidates);
  EXPECT_EQ(r1.improved, r2.improved);
  EXPECT_EQ(points_differing(one, two), 0u);
  double min0 = 0, min1 = 0;
  live_stretch_range(m, &min0, nullptr);
  live_stretch_range(one, &min1, nullptr);
  EXPECT_GT(min1, min0);
  const CompactMesh out = one.compact();
  EXPECT_TRUE(check_validity(out.points, out.tets).ok());
}

// Flips are evaluated in parallel batches (improve_tets_by_flips.h): the
// tets must not depend on the number of threads.
TEST(ImproveVolume, FlipsDoNotDependOnThreadCount) {
  const TetMesh m = perturbed_cube();
  TetMesh one = m, two = m;
  const FlipImproveReport r1 = testing::with_threads(1, [&] { return improve_tets_by_flips(one, FlipImproveOptions()); });
  const FlipImproveReport r2 = testing::with_threads(2, [&] { return improve_tets_by_flips(two, FlipImproveOptions()); });
  std::printf("flips %zu / %zu, visits %zu / %zu\n", r1.total(), r2.total(), r1.visits, r2.visits);
  EXPECT_GT(r1.total(), 500u);
  EXPECT_EQ(r1.total(), r2.total());
  EXPECT_EQ(r1.visits, r2.visits);
  ASSERT_EQ(one.tet_slots(), two.tet_slots());
  for (index_t t = 0; t < one.tet_slots(); ++t) {
    ASSERT_EQ(one.tet_alive(t), two.tet_alive(t));
    if (one.tet_alive(t)) {
      EXPECT_EQ(one.tet(t), two.tet(t));
    }
  }
}

TEST(ImproveVolume, FlipsRaiseMinimumOfQueue) {
  double volume = 0, undeformed_mean = 0;
  TetMesh m = perturbed_cube(&volume, &undeformed_mean);
  const TetMesh before = m;
  double min0 = 0, min1 = 0;
  live_stretch_range(m, &min0, nullptr);
  for (bool delaunay : {true, false}) {
    FlipImproveOptions options;
    options.delaunay_conditions = delaunay;
    const FlipImproveReport r = improve_tets_by_flips(m, options);
    live_stretch_range(m, &min1, nullptr);
    std::printf("flips (delaunay conditions %d): 2-3 %zu 3-2 %zu 4-4 %zu, visits %zu, min %.4f -> %.4f\n", delaunay,
                r.flips_23, r.flips_32, r.flips_44, r.visits, min0, min1);
    EXPECT_FALSE(r.exhausted);
    EXPECT_GE(min1, min0);
    if (!delaunay) {
      EXPECT_GT(r.total(), 0u);
    }
    min0 = min1;
  }
  expect_valid_and_boundary_fixed(before, m, volume);
}

// The last resort of the finishing step: interior edges of tets below the
// threshold split, also when the tet has an inner vertex (only_locked off).
TEST(ImproveVolume, SplittingTetsBelowThresholdNeverLowersTheMinimum) {
  double volume = 0, undeformed_mean = 0;
  TetMesh m = perturbed_cube(&volume, &undeformed_mean);
  double min0 = 0, min1 = 0;
  live_stretch_range(m, &min0, nullptr);
  LockedTetOptions options;
  options.threshold = 0.3;
  const LockedTetStats locked_only = split_locked_tets(m, options);
  options.only_locked = false;
  const LockedTetStats all = split_locked_tets(m, options);
  live_stretch_range(m, &min1, nullptr);
  std::printf("locked %zu (splits %zu), all below 0.3: %zu (splits %zu), min %.4f -> %.4f\n", locked_only.locked,
              locked_only.splits, all.locked, all.splits, min0, min1);
  EXPECT_GT(all.locked, locked_only.locked);
  EXPECT_GT(all.splits, 0u);
  EXPECT_GE(min1, min0);
  ASSERT_TRUE(m.check_consistency().ok) << m.check_consistency().message;
  const CompactMesh out = m.compact();
  EXPECT_TRUE(check_validity(out.points, out.tets).ok());
  EXPECT_NEAR(testing::total_volume(out.points, out.tets), volume, 1e-12 * volume);
}

// The last resort is evaluated in parallel batches: the same splits, at
// the same positions, for 1 and 2 threads; and more than a batch's worth of
// tets below the threshold, so that batches defer stale evaluations.
TEST(ImproveVolume, SplittingTetsBelowThresholdDoesNotDependOnThreadCount) {
  double volume = 0, undeformed_mean = 0;
  const TetMesh m = perturbed_cube(&volume, &undeformed_mean);
  TetMesh one = m, two = m;
  LockedTetOptions options;
  options.threshold = 0.45;
  options.only_locked = false;
  const LockedTetStats r1 = testing::with_threads(1, [&] { return split_locked_tets(one, options); });
  const LockedTetStats r2 = testing::with_threads(2, [&] { return split_locked_tets(two, options); });
  std::printf("below 0.45: %zu, splits %zu / %zu\n", r1.locked, r1.splits, r2.splits);
  EXPECT_GT(r1.locked, 600u);
  EXPECT_GT(r1.splits, 100u);
  EXPECT_EQ(r1.splits, r2.splits);
  ASSERT_EQ(one.vertex_slots(), two.vertex_slots());
  EXPECT_EQ(points_differing(one, two), 0u);
  ASSERT_EQ(one.tet_slots(), two.tet_slots());
  for (index_t t = 0; t < one.tet_slots(); ++t) {
    ASSERT_EQ(one.tet_alive(t), two.tet_alive(t));
    if (one.tet_alive(t)) {
      EXPECT_EQ(one.tet(t), two.tet(t));
    }
  }
  const CompactMesh out = one.compact();
  EXPECT_TRUE(check_validity(out.points, out.tets).ok());
}

// The ball of a vertex that would split an inner edge, built before the
// split (MovingBall's split constructor, what split_locked_tets evaluates):
// the same minimum stretch as the ball after a real split, for positions
// around the midpoint.
TEST(ImproveVolume, SplitBallAgreesWithRealSplit) {
  double volume = 0, undeformed_mean = 0;
  const TetMesh m = perturbed_cube(&volume, &undeformed_mean);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<index_t> ring, opposite, ball;
  int checked = 0, negative = 0;
  for (index_t t = 0; t < m.tet_slots() && checked < 600; t += 13) {
    if (!m.tet_alive(t)) continue;
    const index_t a = m.tet(t)[0], b = m.tet(t)[1];
    bool boundary = true;
    if (!m.edge_ring_with_vertices(a, b, ring, opposite, &boundary, t) || boundary) continue;
    const Vec3 mid = 0.5 * (m.point(a) + m.point(b));
    MovingBall virtual_ball(m, ring, a, b, mid);
    TetMesh split = m;
    index_t v = kInvalidIndex;
    ASSERT_EQ(split.split_edge(a, b, nullptr, &v, t), OpStatus::Ok);
    split.vertex_ball(v, ball);
    ASSERT_EQ(ball.size(), 2 * ring.size());
    for (int k = 0; k < 20; ++k) {
      const Vec3 p = mid + 0.05 * Vec3(u(rng), u(rng), u(rng));
      const double expected = ball_min_stretch(split, ball, v, p);
      EXPECT_NEAR(virtual_ball.min_stretch(p), expected, 1e-12);
      negative += expected < 0;
      ++checked;
    }
  }
  EXPECT_GE(checked, 600);
  EXPECT_GT(negative, 10);  // positions that invert a tet were tried
}

// The compass search's ball: the same stretches as tet_stretch for every
// local position of the moving vertex (orientation kept: inverted positions
// score negative), and exceeds() the same verdict as the full minimum.
TEST(ImproveVolume, MovingBallAgreesWithTetStretch) {
  double volume = 0, undeformed_mean = 0;
  TetMesh m = perturbed_cube(&volume, &undeformed_mean);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<index_t> ball;
  int checked = 0, negative = 0, agreed = 0;
  for (index_t v = 0; v < m.vertex_slots(); v += 7) {
    if (!m.vertex_alive(v) || m.vertex_class(v) != VertexClass::Inner) continue;
    m.vertex_ball(v, ball);
    MovingBall moving(m, ball, v);
    for (int k = 0; k < 20; ++k) {
      const Vec3 p = m.point(v) + 0.06 * Vec3(u(rng), u(rng), u(rng));
      const double expected = ball_min_stretch(m, ball, v, p);
      EXPECT_NEAR(moving.min_stretch(p), expected, 1e-12);
      negative += expected < 0;
      const double bound = expected + 0.02 * u(rng);
      if (std::abs(bound - expected) < 1e-12) continue;  // a tie is decided by rounding
      double q = -1;
      const bool exceeds = moving.exceeds(p, bound, &q);
      EXPECT_EQ(exceeds, expected > bound);
      if (exceeds) {
        EXPECT_NEAR(q, expected, 1e-12);
      }
      agreed += exceeds;
      ++checked;
    }
  }
  EXPECT_GT(checked, 500);
  EXPECT_GT(negative, 10);  // positions that invert a tet were tried
  EXPECT_GT(agreed, 10);
  EXPECT_LT(agreed, checked);
}

TEST(ImproveVolume, RestrictionMaskRespected) {
  double volume = 0, undeformed_mean = 0;
  TetMesh m = perturbed_cube(&volume, &undeformed_mean);
  const TetMesh before = m;
  ImproveVolumeOptions options;
  options.smooth.vertex_mask.assign(m.vertex_slots(), 0);
  std::size_t masked = 0;
  for (index_t v = 0; v < m.vertex_slots(); ++v)
    if (m.point(v).x() < 0.5) options.smooth.vertex_mask[v] = 1, ++masked;
  ASSERT_GT(masked, 0u);
  const ImproveVolumeStats s = improve_volume(m, options);
  expect_valid_and_boundary_fixed(before, m, volume);
  EXPECT_GT(s.moved, 0u);
  std::size_t moved_outside = 0;
  for (index_t v = 0; v < m.vertex_slots(); ++v)
    if (!options.smooth.vertex_mask[v])
      moved_outside += std::memcmp(before.point(v).data(), m.point(v).data(), 3 * sizeof(double)) != 0;
  EXPECT_EQ(moved_outside, 0u);
  // Tets without a masked vertex are unchanged (flips keep off them).
  auto unmasked_tets = [&](const TetMesh& mesh) {
    std::vector<Tet> tets;
    for (index_t t = 0; t < mesh.tet_slots(); ++t) {
      if (!mesh.tet_alive(t)) continue;
      Tet T = mesh.tet(t);
      bool any = false;
      for (index_t v : T) any = any || options.smooth.vertex_mask[v];
      if (any) continue;
      std::sort(T.begin(), T.end());
      tets.push_back(T);
    }
    std::sort(tets.begin(), tets.end());
    return tets;
  };
  EXPECT_EQ(unmasked_tets(before), unmasked_tets(m));
}

TEST(ImproveVolume, Deterministic) {
  double volume = 0, undeformed_mean = 0;
  TetMesh a = perturbed_cube(&volume, &undeformed_mean);
  TetMesh b = a;
  improve_volume(a);
  improve_volume(b);
  const CompactMesh ca = a.compact(), cb = b.compact();
  ASSERT_EQ(ca.points.size(), cb.points.size());
  EXPECT_EQ(0, std::memcmp(ca.points.data(), cb.points.data(), ca.points.size() * sizeof(Vec3)));
  EXPECT_EQ(ca.tets, cb.tets);
}

// Thesis case (a): inner vertices of a real part displaced at random.
TEST(ImproveVolume, RealPartRandomInnerDisplacement) {
  const std::string path = std::string(FEMORPH_REALPARTS_DIR) + "/fandisk_tet.mesh";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found";
  MeditMesh medit;
  ASSERT_TRUE(read_medit_mesh(path, medit).ok);
  TetMesh m;
  ASSERT_TRUE(m.build(medit.points, medit.tets).ok);
  const double volume = testing::total_volume(medit.points, medit.tets);
  double min_orig = 0, mean_orig = 0;
  live_stretch_range(m, &min_orig, &mean_orig);
  perturb_inner_vertices(m, 0.4, 5);
  const TetMesh before = m;
  const ImproveVolumeStats s = improve_volume(m);
  std::printf("fandisk: undeformed min %.4f mean %.4f; perturbed min %.4f mean %.4f -> min %.4f mean %.4f; "
              "moved %zu refused %zu; flips 2-3 %zu 3-2 %zu 4-4 %zu; %d rounds, %.3f s\n",
              min_orig, mean_orig, s.min_stretch_before, s.mean_stretch_before, s.min_stretch_after,
              s.mean_stretch_after, s.moved, s.refused, s.flips_23, s.flips_32, s.flips_44, s.rounds, s.seconds);
  expect_valid_and_boundary_fixed(before, m, volume);
  EXPECT_GE(s.min_stretch_after, s.min_stretch_before);
  EXPECT_GT(s.mean_stretch_after, s.mean_stretch_before);
  // The goal of 0.3 is out of reach here: the undeformed part has boundary
  // tets of 0.1055 that moving inner vertices cannot repair. Reached: 0.2132
  // and mean 0.674 (undeformed 0.624).
  EXPECT_GE(s.min_stretch_after, std::max(min_orig, 0.2));
  EXPECT_GE(s.mean_stretch_after, mean_orig);
}

}  // namespace
}  // namespace femorph
