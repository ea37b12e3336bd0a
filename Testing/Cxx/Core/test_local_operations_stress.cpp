// Randomized stress test of the local operations: at least 100,000 seeded
// random operations on a jittered cube of about 30,000 tets. After every
// batch the internal invariants and the independent validity checker run;
// volume and boundary must be preserved, since on a box every operation
// (rule-based collapses included) keeps both.
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace femorph {
namespace {

constexpr int kCells = 17;              // 17^3 * 6 = 29,478 tets
constexpr int kOperations = 100000;     // accepted operations
constexpr int kCheckEvery = 10000;

/// Every boundary face lies on its region's plane (region 2*axis + side is
/// the plane x_axis = side), exactly: midpoints of points on a coordinate
/// plane stay on it. Returns the number of faces off their plane.
std::size_t faces_off_their_plane(const TetMesh& m) {
  std::size_t bad = 0;
  for (index_t t = 0; t < m.tet_slots(); ++t) {
    if (!m.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f) {
      if (!m.is_boundary_face(t, f)) continue;
      const index_t r = m.face_region(t, f);
      if (r < 0 || r > 5) {
        ++bad;
        continue;
      }
      const int axis = r / 2;
      const double value = r % 2;
      for (int k = 0; k < 3; ++k)
        if (m.point(m.tet(t)[kTetFace[f][k]])[axis] != value) ++bad;
    }
  }
  return bad;
}

double boundary_area(const TetMesh& m) {
  double area = 0;
  for (index_t t = 0; t < m.tet_slots(); ++t) {
    if (!m.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f) {
      if (!m.is_boundary_face(t, f)) continue;
      const Vec3& a = m.point(m.tet(t)[kTetFace[f][0]]);
      const Vec3& b = m.point(m.tet(t)[kTetFace[f][1]]);
      const Vec3& c = m.point(m.tet(t)[kTetFace[f][2]]);
      area += 0.5 * (b - a).cross(c - a).norm();
    }
  }
  return area;
}

TEST(LocalOperationsStress, HundredThousandRandomOperations) {
  const testing::TestMesh cube = testing::make_cube_mesh(kCells, 0.1, 2026);
  BuildOptions opt;
  opt.face_regions = cube.face_regions;
  TetMesh m;
  ASSERT_TRUE(m.build(cube.points, cube.tets, opt).ok);
  ASSERT_GE(m.live_tets(), 20000u);
  const std::size_t target_tets = m.live_tets();

  std::mt19937_64 rng(12345);
  auto random_tet = [&] {
    std::uniform_int_distribution<index_t> pick(0, m.tet_slots() - 1);
    index_t t;
    do t = pick(rng);
    while (!m.tet_alive(t));
    return t;
  };
  auto random_edge = [&](index_t t, index_t* a, index_t* b) {
    static const int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    const int e = std::uniform_int_distribution<int>(0, 5)(rng);
    *a = m.tet(t)[edges[e][0]];
    *b = m.tet(t)[edges[e][1]];
  };

  enum Op { kSplitEdge, kSplitFace, kCollapse, kFlip23, kFlip32, kFlip44, kSurfaceFlip, kMove, kOpCount };
  const char* names[kOpCount] = {"split_edge", "split_face", "collapse_by_rules", "flip_23",
                                 "flip_32", "flip_44", "flip_surface_edge", "move_vertex"};
  std::size_t attempted[kOpCount] = {}, accepted[kOpCount] = {};
  int done = 0;
  long attempts = 0;
  while (done < kOperations) {
    ASSERT_LT(++attempts, 50L * kOperations) << "too many refusals";
    // Keep the size near the start: splits only when smaller, and more
    // collapse attempts when larger (many random edges are forbidden).
    const bool smaller = m.live_tets() < target_tets;
    const double split = smaller ? 0.5 : 0.0, collapse = smaller ? 0.5 : 3.0;
    std::discrete_distribution<int> choose({split, split, collapse, 1.0, 1.0, 0.5, 0.5, 0.5});
    const int drawn = choose(rng);
    if (drawn < 0 || drawn >= kOpCount) continue;
    const Op op = static_cast<Op>(drawn);
    const index_t t = random_tet();
    index_t a, b;
    random_edge(t, &a, &b);
    OpStatus s = OpStatus::InvalidArgument;
    switch (op) {
      case kSplitEdge: s = m.split_edge(a, b, nullptr, nullptr); break;
      case kSplitFace: s = m.split_face(t, std::uniform_int_distribution<int>(0, 3)(rng), nullptr, nullptr); break;
      case kCollapse: s = m.collapse_edge_by_rules(a, b, nullptr); break;
      case kFlip23: s = m.flip_23(t, std::uniform_int_distribution<int>(0, 3)(rng)); break;
      case kFlip32: s = m.flip_32(a, b); break;
      case kFlip44: s = m.flip_44(a, b, std::uniform_int_distribution<int>(0, 1)(rng)); break;
      case kSurfaceFlip: s = m.flip_surface_edge(a, b); break;
      case kMove: {
        // Inner vertices only (a boundary vertex would leave its plane).
        if (m.vertex_class(a) != VertexClass::Inner) break;
        std::uniform_real_distribution<double> d(-0.3 / kCells, 0.3 / kCells);
        s = m.move_vertex(a, m.point(a) + Vec3(d(rng), d(rng), d(rng)));
        break;
      }
      default: break;
    }
    ++attempted[op];
    if (s == OpStatus::Ok) {
      ++accepted[op];
      ++done;
      // Every touched tet is alive and positive.
      for (index_t u : m.touched_tets()) {
        ASSERT_TRUE(m.tet_alive(u));
        ASSERT_GT(m.orientation(u), 0) << names[op];
      }
      if (done % kCheckEvery == 0 || done == kOperations) {
        const Status c = m.check_consistency();
        ASSERT_TRUE(c.ok) << "after " << done << " operations: " << c.message;
        const CompactMesh out = m.compact();
        const ValidityReport r = check_validity(out.points, out.tets);
        ASSERT_TRUE(r.ok()) << "after " << done << " operations: " << r.summary();
        EXPECT_NEAR(testing::total_volume(out.points, out.tets), 1.0, 1e-12);
        EXPECT_EQ(faces_off_their_plane(m), 0u);
        EXPECT_NEAR(boundary_area(m), 6.0, 1e-11);
      }
    }
  }
  for (int op = 0; op < kOpCount; ++op) {
    std::printf("%-18s attempted %7zu accepted %7zu\n", names[op], attempted[op], accepted[op]);
    EXPECT_GT(accepted[op], 0u) << names[op] << " never succeeded";
  }
  std::printf("final mesh: %zu tets, %zu vertices\n", m.live_tets(), m.live_vertices());
}

}  // namespace
}  // namespace femorph
