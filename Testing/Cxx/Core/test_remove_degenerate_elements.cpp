// Degenerated and inverted element removal (thesis 2.6.2, Fig. 2.38, 2.39)
// on jittered cube meshes with a vertex moved to make a sliver, a cap or a
// spade, and the thesis' case (c): surface vertices slid along their face
// planes until tets flatten and invert.
#include "improve/remove_degenerate_elements.h"
#include "improve/remove_inverted_elements.h"
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace femorph {
namespace {

constexpr double kThreshold = 0.05;

double stretch_of(const TetMesh& m, index_t t) {
  const Tet& T = m.tet(t);
  return tet_stretch(m.point(T[0]), m.point(T[1]), m.point(T[2]), m.point(T[3]));
}

double min_stretch(const TetMesh& m) {
  double q = 1e300;
  for (index_t t = 0; t < m.tet_slots(); ++t)
    if (m.tet_alive(t)) q = std::min(q, stretch_of(m, t));
  return q;
}

std::size_t count_inverted(const TetMesh& m) {
  std::size_t n = 0;
  for (index_t t = 0; t < m.tet_slots(); ++t) n += m.tet_alive(t) && m.orientation(t) < 0;
  return n;
}

double volume(const TetMesh& m) {
  const CompactMesh c = m.compact();
  return testing::total_volume(c.points, c.tets);
}

bool on_unit_cube_surface(const Vec3& p) {
  for (int a = 0; a < 3; ++a)
    if (std::abs(p[a]) <= 1e-12 || std::abs(p[a] - 1) <= 1e-12) return true;
  return false;
}

void expect_valid(const TetMesh& m) {
  ASSERT_TRUE(m.check_consistency().ok) << m.check_consistency().message;
  const CompactMesh c = m.compact();
  const ValidityReport r = check_validity(c.points, c.tets);
  EXPECT_TRUE(r.ok()) << r.summary();
}

/// Boundary vertices of the input keep their positions, and every boundary
/// vertex of the result lies on the cube's surface.
void expect_boundary_kept(const TetMesh& m, const std::vector<std::pair<index_t, Vec3>>& boundary) {
  for (const auto& [v, p] : boundary) {
    ASSERT_TRUE(m.vertex_alive(v)) << "boundary vertex " << v << " removed";
    EXPECT_EQ(m.point(v), p) << "boundary vertex " << v << " moved";
  }
  for (index_t v = 0; v < m.vertex_slots(); ++v)
    if (m.vertex_alive(v) && m.on_boundary(v)) {
      EXPECT_TRUE(on_unit_cube_surface(m.point(v))) << v;
    }
}

std::vector<std::pair<index_t, Vec3>> boundary_vertices(const TetMesh& m) {
  std::vector<std::pair<index_t, Vec3>> out;
  for (index_t v = 0; v < m.vertex_slots(); ++v)
    if (m.vertex_alive(v) && m.on_boundary(v)) out.emplace_back(v, m.point(v));
  return out;
}

TetMesh build(const testing::TestMesh& tm, bool allow_inverted = false) {
  TetMesh m;
  BuildOptions opt;
  opt.allow_inverted = allow_inverted;
  opt.face_regions = tm.face_regions;
  const Status s = m.build(tm.points, tm.tets, opt);
  EXPECT_TRUE(s.ok) << s.message;
  return m;
}

/// Moves one inner vertex of a jittered cube toward the plane of the face
/// opposite it in one of its tets (kind Cap / Sliver: toward the face's
/// plane; Spade: toward the line of one of the face's edges), keeping every
/// tet positive, until that tet is below the threshold and classifies as the
/// wanted kind. Returns the mesh; *target the vertex ids of the flat tet.
testing::TestMesh make_flat_tet(DegenerateKind kind, Tet* target) {
  testing::TestMesh tm = testing::make_cube_mesh(4, 0.1, 7);
  const int n1 = 5;
  for (index_t v = 0; v < static_cast<index_t>(tm.points.size()); ++v) {
    const int i = v % n1, j = (v / n1) % n1, k = v / (n1 * n1);
    if (i == 0 || j == 0 || k == 0 || i == 4 || j == 4 || k == 4) continue;
    for (const Tet& T : tm.tets) {
      int lv = -1;
      for (int q = 0; q < 4; ++q)
        if (T[q] == v) lv = q;
      if (lv < 0) continue;
      const Vec3& a = tm.points[T[kTetFace[lv][0]]];
      const Vec3& b = tm.points[T[kTetFace[lv][1]]];
      const Vec3& c = tm.points[T[kTetFace[lv][2]]];
      const Vec3 p = tm.points[v];
      std::vector<Vec3> goals;
      if (kind == DegenerateKind::Spade) {
        const Vec3* e[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
        for (auto& ed : e) {
          const Vec3 d = *ed[1] - *ed[0];
          const double s = std::min(0.7, std::max(0.3, (p - *ed[0]).dot(d) / d.squaredNorm()));
          goals.push_back(*ed[0] + s * d);
        }
      } else {
        const Vec3 nrm = (b - a).cross(c - a).normalized();
        goals.push_back(p - (p - a).dot(nrm) * nrm);
      }
      for (const Vec3& goal : goals)
        for (double lambda : {0.9, 0.95, 0.98}) {
          testing::TestMesh trial = tm;
          trial.points[v] = p + lambda * (goal - p);
          bool positive = true;
          for (const Tet& U : trial.tets) {
            const auto& P = trial.points;
            if (tet_signed_volume(P[U[0]], P[U[1]], P[U[2]], P[U[3]]) <= 0) positive = false;
          }
          if (!positive) continue;
          const auto& P = trial.points;
          std::array<Vec3, 4> q{{P[T[0]], P[T[1]], P[T[2]], P[T[3]]}};
          if (tet_stretch(q[0], q[1], q[2], q[3]) >= kThreshold) continue;
          if (classify_degenerate_tet(q).kind != kind) continue;
          *target = T;
          return trial;
        }
    }
  }
  ADD_FAILURE() << "no " << to_string(kind) << " found";
  return tm;
}

void remove_one_kind(DegenerateKind kind) {
  Tet target{};
  const testing::TestMesh tm = make_flat_tet(kind, &target);
  TetMesh m = build(tm);
  const double v0 = volume(m);
  const auto boundary = boundary_vertices(m);
  const DegenerateRemovalStats st = remove_degenerate_elements(m);
  std::printf("%s: %zu below before (min stretch %.4f), slivers %zu caps %zu spades %zu failed %zu, "
              "%zu below after (min stretch %.4f)\n",
              to_string(kind), st.initial_below, st.min_stretch_before, st.removed_slivers, st.removed_caps,
              st.removed_spades, st.failed, st.remaining_below, st.min_stretch_after);
  EXPECT_GE(st.initial_below, 1u);
  const std::size_t removed_kind = kind == DegenerateKind::Sliver ? st.removed_slivers
                                   : kind == DegenerateKind::Cap  ? st.removed_caps
                                                                  : st.removed_spades;
  EXPECT_GE(removed_kind, 1u);
  EXPECT_EQ(st.remaining_below, 0u);
  EXPECT_GE(min_stretch(m), kThreshold);
  expect_valid(m);
  EXPECT_NEAR(volume(m), v0, 1e-12 * v0);
  expect_boundary_kept(m, boundary);
}

TEST(DegenerateClassify, Shapes) {
  // Sliver: a square with one diagonal lifted slightly.
  std::array<Vec3, 4> sliver{{Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 0.01), Vec3(0, 1, 0.01)}};
  DegenerateShape s = classify_degenerate_tet(sliver);
  EXPECT_EQ(s.kind, DegenerateKind::Sliver);
  EXPECT_NEAR(s.s, 0.5, 1e-12);
  EXPECT_NEAR(s.t, 0.5, 1e-12);
  // Cap: apex above the centroid of a triangle.
  std::array<Vec3, 4> cap{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0.9, 0), Vec3(0.5, 0.3, 0.01)}};
  s = classify_degenerate_tet(cap);
  EXPECT_EQ(s.kind, DegenerateKind::Cap);
  EXPECT_EQ(s.v[2], 3);  // the apex is collapsed with the split vertex
  // Spade: vertex 3 near the middle of edge (0, 1).
  std::array<Vec3, 4> spade{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0.9, 0), Vec3(0.5, 0.02, 0.01)}};
  s = classify_degenerate_tet(spade);
  EXPECT_EQ(s.kind, DegenerateKind::Spade);
  EXPECT_EQ(s.v[2], 3);
  EXPECT_TRUE((s.v[0] == 0 && s.v[1] == 1) || (s.v[0] == 1 && s.v[1] == 0));
  EXPECT_NEAR(s.v[0] == 0 ? s.s : 1 - s.s, 0.5, 1e-12);
}

TEST(DegenerateRemoval, Sliver) { remove_one_kind(DegenerateKind::Sliver); }
TEST(DegenerateRemoval, Cap) { remove_one_kind(DegenerateKind::Cap); }
TEST(DegenerateRemoval, Spade) { remove_one_kind(DegenerateKind::Spade); }

TEST(DegenerateRemoval, GoodMeshUntouched) {
  TetMesh m = build(testing::make_cube_mesh(3, 0.1, 3));
  const CompactMesh before = m.compact();
  const DegenerateRemovalStats st = remove_degenerate_elements(m);
  EXPECT_EQ(st.initial_below, 0u);
  const CompactMesh after = m.compact();
  EXPECT_EQ(before.points, after.points);
  EXPECT_EQ(before.tets, after.tets);
}

/// Thesis case (c): surface vertices of a cube slid along their face plane
/// (curve and corner vertices stay), making slivers and inverted tets.
testing::TestMesh make_slid_cube(double slide, std::uint64_t seed) {
  const int n = 5, n1 = n + 1;
  testing::TestMesh tm = testing::make_cube_mesh(n, 0.05, seed);
  std::mt19937_64 rng(seed + 1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (index_t v = 0; v < static_cast<index_t>(tm.points.size()); ++v) {
    const int idx[3] = {v % n1, (v / n1) % n1, v / (n1 * n1)};
    int on = 0;
    for (int a = 0; a < 3; ++a) on += idx[a] == 0 || idx[a] == n;
    const double d[3] = {u(rng), u(rng), u(rng)};
    if (on != 1) continue;
    for (int a = 0; a < 3; ++a)
      if (idx[a] != 0 && idx[a] != n) tm.points[v][a] += slide * d[a] / n;
  }
  return tm;
}

struct CaseCResult {
  std::size_t inverted_before = 0, inverted_after = 0, below_before = 0, below_after = 0;
  double min_after = 0;
  CompactMesh mesh;
};

CaseCResult run_case_c(double slide, std::uint64_t seed) {
  CaseCResult r;
  const testing::TestMesh tm = make_slid_cube(slide, seed);
  TetMesh m = build(tm, /*allow_inverted=*/true);
  r.inverted_before = count_inverted(m);
  const double v0 = volume(m);
  EXPECT_NEAR(v0, 1.0, 1e-12);
  const InvertedRemovalStats inv = remove_inverted_elements(m);
  // The reported unrepaired tets are exactly the inverted ones, ids valid.
  EXPECT_EQ(inv.remaining_inverted, inv.remaining_tets.size());
  EXPECT_EQ(inv.remaining_inverted, count_inverted(m));
  for (index_t t : inv.remaining_tets) EXPECT_TRUE(m.tet_alive(t) && m.orientation(t) < 0) << t;
  // Degenerate removal targets positive tets only, but its collapses may
  // take inverted tets on the collapsed edge with them.
  const DegenerateRemovalStats deg = remove_degenerate_elements(m);
  EXPECT_LE(count_inverted(m), inv.remaining_inverted);
  r.inverted_after = count_inverted(m);
  r.below_before = deg.initial_below;
  r.below_after = deg.remaining_below;
  r.min_after = min_stretch(m);
  std::printf("case (c) slide %.2f seed %llu: %zu inverted (min stretch %.4f) -> %zu collapses %zu moves, %zu remain %s; "
              "%zu below %.2f -> slivers %zu caps %zu spades %zu failed %zu, %zu remain; min stretch %.4f; "
              "%zu tets\n",
              slide, static_cast<unsigned long long>(seed), inv.initial_inverted, inv.min_stretch_before,
              inv.collapses, inv.relocations, inv.remaining_inverted, inv.remaining_inverted ? "(not repaired locally)" : "",
              deg.initial_below, kThreshold, deg.removed_slivers, deg.removed_caps, deg.removed_spades, deg.failed,
              deg.remaining_below, r.min_after, m.live_tets());
  if (r.inverted_after == 0) {
    expect_valid(m);
  } else {
    EXPECT_TRUE(m.check_consistency().ok) << m.check_consistency().message;
    const CompactMesh c = m.compact();
    ValidityOptions vo;
    vo.require_positive = false;
    EXPECT_TRUE(check_validity(c.points, c.tets, vo).ok());
  }
  EXPECT_NEAR(volume(m), 1.0, 1e-12);
  for (index_t v = 0; v < m.vertex_slots(); ++v)
    if (m.vertex_alive(v) && m.on_boundary(v)) {
      EXPECT_TRUE(on_unit_cube_surface(m.point(v))) << v;
    }
  r.mesh = m.compact();
  return r;
}

TEST(DegenerateRemoval, CaseCSlidSurfaceVertices) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const CaseCResult r = run_case_c(0.9, seed);
    EXPECT_GT(r.inverted_before, 0u) << "the test must create inverted tets";
    EXPECT_GT(r.below_before, 0u);
    EXPECT_EQ(r.inverted_after, 0u);
    // Removal alone (no smoothing) must lift every tet to the threshold.
    EXPECT_GE(r.min_after, kThreshold);
  }
}

TEST(DegenerateRemoval, CaseCSweep) {
  // More seeds and larger slides (up to 0.99 of a cell per axis: vertices
  // stay inside their face but cross their neighbours). Moderate slides must
  // be fully repaired; for the largest a few inverted tets may stay (tangles
  // of several folded boundary triangles no single local operation undoes,
  // see remove_inverted_elements.h); they must be few and reported.
  double worst = 1;
  std::size_t inverted_before = 0, inverted_after = 0, below_after = 0, cases_left = 0;
  for (double slide : {0.6, 0.9, 0.99})
    for (std::uint64_t seed = 10; seed < 40; ++seed) {
      const CaseCResult r = run_case_c(slide, seed);
      if (slide < 0.7) {
        EXPECT_EQ(r.inverted_after, 0u) << "slide " << slide << " seed " << seed;
        EXPECT_EQ(r.below_after, 0u) << "slide " << slide << " seed " << seed;
      }
      inverted_before += r.inverted_before;
      inverted_after += r.inverted_after;
      below_after += r.below_after;
      cases_left += r.inverted_after > 0;
      if (r.inverted_after == 0) worst = std::min(worst, r.min_after);
    }
  std::printf("case (c) sweep, 90 meshes: %zu -> %zu inverted (%zu meshes not fully repaired), %zu tets below %.2f "
              "left; worst min stretch of the repaired meshes %.4f\n",
              inverted_before, inverted_after, cases_left, below_after, kThreshold, worst);
  EXPECT_LE(inverted_after * 200, inverted_before);  // at least 99.5 % repaired
  EXPECT_LE(cases_left, 9u);                          // at most 10 % of the meshes
  EXPECT_GT(worst, 0.0);
}

// DegenerateRemovalOptions::touched marks the vertices of every tet an
// operation made or changed (Improve smooths only there in a boundary
// phase's last loop): on slid cubes, every unmarked vertex slot is still
// alive with its position and its neighbours, and many stay unmarked.
TEST(DegenerateRemoval, TouchedMarksEveryVertexAnOperationChanged) {
  const auto neighbours_of = [](const TetMesh& m) {
    std::vector<std::vector<index_t>> nb(static_cast<std::size_t>(m.vertex_slots()));
    for (index_t t = 0; t < m.tet_slots(); ++t) {
      if (!m.tet_alive(t)) continue;
      for (const index_t a : m.tet(t))
        for (const index_t b : m.tet(t))
          if (a != b) nb[static_cast<std::size_t>(a)].push_back(b);
    }
    for (auto& v : nb) {
      std::sort(v.begin(), v.end());
      v.erase(std::unique(v.begin(), v.end()), v.end());
    }
    return nb;
  };
  std::size_t operations = 0;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    TetMesh m = build(make_slid_cube(0.9, seed), /*allow_inverted=*/true);
    remove_inverted_elements(m);
    const TetMesh before = m;
    const std::vector<std::vector<index_t>> nb_before = neighbours_of(m);
    std::vector<char> touched;
    DegenerateRemovalOptions options;
    options.touched = &touched;
    const DegenerateRemovalStats st = remove_degenerate_elements(m, options);
    operations += st.removed_slivers + st.removed_caps + st.removed_spades;
    const std::vector<std::vector<index_t>> nb_after = neighbours_of(m);
    std::size_t unmarked = 0, alive = 0;
    for (index_t v = 0; v < before.vertex_slots(); ++v) {
      if (!before.vertex_alive(v)) continue;
      ++alive;
      if (static_cast<std::size_t>(v) < touched.size() && touched[v]) continue;
      ++unmarked;
      ASSERT_TRUE(m.vertex_alive(v)) << "seed " << seed << ": vertex " << v << " removed but not marked";
      EXPECT_EQ(m.point(v), before.point(v)) << "seed " << seed << ": vertex " << v << " moved, not marked";
      EXPECT_EQ(nb_after[v], nb_before[v]) << "seed " << seed << ": vertex " << v << " has other neighbours, not marked";
    }
    EXPECT_GT(unmarked, alive / 2) << "seed " << seed;
  }
  EXPECT_GT(operations, 0u);
}

TEST(DegenerateRemoval, CaseCDeterministic) {
  const CaseCResult a = run_case_c(0.9, 5);
  const CaseCResult b = run_case_c(0.9, 5);
  EXPECT_EQ(a.mesh.points, b.mesh.points);
  EXPECT_EQ(a.mesh.tets, b.mesh.tets);
}

}  // namespace
}  // namespace femorph

namespace femorph {
namespace {

// TetMesh::half_edge_collapse_keeping_inverted, added for the inverted
// element removal: refused on meshes that do not allow inverted tets; on a
// tangled mesh it succeeds where half_edge_collapse is refused only because
// an already inverted tet of the removed vertex's ball stays inverted, and
// then lowers the number of inverted tets and keeps the mesh consistent.
TEST(DegenerateRemoval, HalfEdgeCollapseKeepingInverted) {
  {
    TetMesh good = build(testing::make_cube_mesh(2, 0.0, 1));
    const Tet T = good.tet(0);
    EXPECT_EQ(good.half_edge_collapse_keeping_inverted(Keep{T[1]}, Remove{T[0]}), OpStatus::InvalidArgument);
  }
  const TetMesh m = build(make_slid_cube(0.9, 23), /*allow_inverted=*/true);
  const std::size_t inverted = count_inverted(m);
  ASSERT_GT(inverted, 0u);
  std::size_t tried = 0, found = 0;
  for (index_t t = 0; t < m.tet_slots(); ++t) {
    if (!m.tet_alive(t) || m.orientation(t) >= 0) continue;
    const Tet T = m.tet(t);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        // Inner removed vertex: the boundary, hence the volume, stays.
        if (i == j || m.vertex_class(T[i]) != VertexClass::Inner) continue;
        TetMesh a = m;
        const OpStatus plain = a.half_edge_collapse(Keep{T[j]}, Remove{T[i]});
        TetMesh b = m;
        const OpStatus tolerant = b.half_edge_collapse_keeping_inverted(Keep{T[j]}, Remove{T[i]});
        ++tried;
        if (plain == OpStatus::Ok) {
          // Nothing to tolerate: the same result.
          EXPECT_EQ(tolerant, OpStatus::Ok);
          EXPECT_EQ(a.compact().tets, b.compact().tets);
          continue;
        }
        if (tolerant != OpStatus::Ok) continue;
        ++found;
        EXPECT_EQ(plain, OpStatus::Inverted);
        EXPECT_LT(count_inverted(b), inverted);
        EXPECT_TRUE(b.check_consistency().ok) << b.check_consistency().message;
        const CompactMesh c = b.compact();
        ValidityOptions vo;
        vo.require_positive = false;
        EXPECT_TRUE(check_validity(c.points, c.tets, vo).ok());
        EXPECT_NEAR(testing::total_volume(c.points, c.tets), 1.0, 1e-12);
        EXPECT_FALSE(b.vertex_alive(T[i]));
      }
  }
  std::printf("keeping inverted: %zu collapses tried, %zu accepted only by the tolerant variant\n", tried, found);
  EXPECT_GT(found, 0u);
}

}  // namespace
}  // namespace femorph

namespace femorph {
namespace {

// The projection callback sees boundary vertices only; an identity
// projection gives the same mesh as none.
TEST(DegenerateRemoval, ProjectionCallback) {
  const testing::TestMesh tm = make_slid_cube(0.9, 1);
  TetMesh a = build(tm, true), b = build(tm, true);
  remove_inverted_elements(a);
  remove_inverted_elements(b);
  remove_degenerate_elements(a);
  std::size_t calls = 0;
  DegenerateRemovalOptions opt;
  opt.project = [&](index_t v, const Vec3& p) {
    ++calls;
    EXPECT_NE(b.vertex_class(v), VertexClass::Inner);
    EXPECT_TRUE(on_unit_cube_surface(p));
    return p;
  };
  remove_degenerate_elements(b, opt);
  std::printf("projection calls: %zu\n", calls);
  EXPECT_GT(calls, 0u);
  EXPECT_EQ(a.compact().points, b.compact().points);
  EXPECT_EQ(a.compact().tets, b.compact().tets);
}

}  // namespace
}  // namespace femorph

namespace femorph {
namespace {

// Without the relocation fallback the removal still ends, reports the tets it
// left, and leaves a consistent mesh; with it, no more remain than without.
TEST(DegenerateRemoval, InvertedWithoutRelocation) {
  for (std::uint64_t seed : {13u, 17u, 23u}) {
    const testing::TestMesh tm = make_slid_cube(0.99, seed);
    TetMesh a = build(tm, true), b = build(tm, true);
    InvertedRemovalOptions off;
    off.relocate_vertices = false;
    const InvertedRemovalStats sa = remove_inverted_elements(a, off);
    const InvertedRemovalStats sb = remove_inverted_elements(b);
    std::printf("seed %llu: %zu inverted -> %zu without relocation, %zu with (%zu moves); left:",
                static_cast<unsigned long long>(seed), sa.initial_inverted, sa.remaining_inverted,
                sb.remaining_inverted, sb.relocations);
    for (index_t t : sb.remaining_tets) std::printf(" %d", t);
    std::printf("\n");
    EXPECT_EQ(sa.relocations, 0u);
    EXPECT_EQ(sa.remaining_inverted, count_inverted(a));
    EXPECT_EQ(sa.remaining_tets.size(), sa.remaining_inverted);
    EXPECT_LE(sb.remaining_inverted, sa.remaining_inverted);
    EXPECT_TRUE(a.check_consistency().ok) << a.check_consistency().message;
    EXPECT_NEAR(volume(a), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace femorph
