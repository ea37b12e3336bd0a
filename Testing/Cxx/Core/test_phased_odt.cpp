// Phased ODT (thesis 2.6, Fig. 2.34) in the core: the loop on a jittered
// cube (planar: volume and faces exact), the region restriction and abort;
// shape approximation accuracy control (2.6.4) and the curve vertex lists
// traced after it on an annulus; the edge enumeration.
#include "improve/boundary_geometry.h"
#include "improve/control_mesh_density.h"
#include "improve/control_shape_accuracy.h"
#include "improve/improve_target.h"
#include "improve/mesh_density.h"
#include "improve/phased_odt.h"
#include "mesh/tet_mesh.h"
#include "mesh/trace_boundary_curves.h"
#include "mesh/unique_edges.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"
#include "test_improve_meshes.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <set>

namespace femorph {
namespace {

using namespace testing::improve_meshes;

BoundaryGeometry cube_geometry() {
  BoundaryGeometry g;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) g.regions.push_back(plane(side * Vec3::Unit(axis), Vec3::Unit(axis)));
  return g;
}

/// Every inner vertex by up to 40% of its mean edge length (Improve's
/// acceptance case (a), docs/ARCHITECTURE.md); moves that would invert are
/// refused by TetMesh.
void jitter_inner(TetMesh& mesh, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<index_t> nb;
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    if (!mesh.vertex_alive(v) || mesh.on_boundary(v)) continue;
    mesh.vertex_neighbors(v, nb);
    double len = 0;
    for (const index_t w : nb) len += (mesh.point(w) - mesh.point(v)).norm();
    len /= static_cast<double>(nb.size());
    Vec3 d;
    do d = Vec3(u(rng), u(rng), u(rng));
    while (d.squaredNorm() > 1);
    mesh.move_vertex(v, mesh.point(v) + 0.4 * len * d);
  }
}

struct Measured {
  double min = std::numeric_limits<double>::infinity(), mean = 0, volume = 0;
};

Measured measure(const CompactMesh& m) {
  Measured q;
  for (const Tet& t : m.tets) {
    const double s = tet_stretch(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
    q.min = std::min(q.min, s);
    q.mean += s;
    q.volume += tet_signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
  }
  q.mean /= static_cast<double>(m.tets.size());
  return q;
}

TEST(UniqueEdges, MatchesTheEdgesOfTheTets) {
  // 384 tets (serial) and 10,368 (past the parallel threshold).
  for (const int n : {4, 12}) {
    const testing::TestMesh m = testing::make_cube_mesh(n, 0.1, 3);
    std::set<Edge> expected;
    for (const Tet& t : m.tets)
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) expected.insert({std::min(t[i], t[j]), std::max(t[i], t[j])});
    const auto edges = unique_edges(m.tets, static_cast<index_t>(m.points.size()));
    EXPECT_EQ(std::vector<Edge>(expected.begin(), expected.end()), edges);
    TetMesh mesh = build(m);
    EXPECT_EQ(unique_edges(mesh), edges);
    // With a mask: only edges between flagged vertices.
    std::vector<char> mask(m.points.size(), 0);
    for (std::size_t v = 0; v < mask.size(); v += 2) mask[v] = 1;
    std::vector<Edge> flagged;
    for (const Edge& e : edges)
      if (mask[e.first] && mask[e.second]) flagged.push_back(e);
    EXPECT_EQ(unique_edges(mesh, &mask), flagged);
  }
}

// Acceptance case (a) on a planar part: inner vertices jittered by 40%, the
// target density the unjittered mesh's. The loop of Fig. 2.34 gives min
// stretch >= 0.3, the faces stay on their planes, the volume is exact.
TEST(PhasedOdt, JitteredCubeReachesTheQualityGoal) {
  const testing::TestMesh m = testing::make_cube_mesh(8, 0.1, 5);
  TetMesh mesh = build(m);
  const Measured undeformed = measure(mesh.compact());
  DensityGrid grid;
  ASSERT_TRUE(grid.build(m.points, m.tets, vertex_density(m.points, m.tets), 0));
  jitter_inner(mesh, 9);
  const Measured jittered = measure(mesh.compact());
  ASSERT_LT(jittered.min, 0.1);
  PhasedOdtTarget target;
  target.density = &grid;
  const PhasedOdtStats stats = phased_odt(mesh, cube_geometry(), target);
  ASSERT_TRUE(mesh.check_consistency().ok) << mesh.check_consistency().message;
  const CompactMesh out = mesh.compact();
  const ValidityReport report = check_validity(out.points, out.tets);
  EXPECT_TRUE(report.ok()) << report.summary();
  const Measured after = measure(out);
  EXPECT_GE(after.min, 0.3);
  EXPECT_EQ(stats.below_floor, 0u);
  EXPECT_GE(after.mean, undeformed.mean);
  EXPECT_NEAR(after.volume, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(stats.min_stretch_after, after.min);
  EXPECT_TRUE(stats.remaining_inverted.empty());
  EXPECT_LE(stats.density_error_after.mean, stats.density_error_before.mean);
  // Boundary points on their planes.
  for (std::size_t v = 0; v < out.points.size(); ++v) {
    if (out.vertex_classes[v] == VertexClass::Inner) continue;
    double d = 1;
    for (int a = 0; a < 3; ++a) d = std::min({d, std::abs(out.points[v][a]), std::abs(out.points[v][a] - 1)});
    EXPECT_LE(d, 1e-15) << "boundary point " << v;
  }
}

// Acceptance case: an input already perfect is left as it is, fast. The
// unjittered Kuhn cube against its own density: every tet at 0.3 or more,
// no edge beyond the density thresholds. Left bit for bit as it is, in one
// pass over the edges; jittered, the same mesh is worked on.
TEST(PhasedOdt, PerfectInputIsLeftAsItIs) {
  const testing::TestMesh m = testing::make_cube_mesh(6, 0, 1);
  TetMesh mesh = build(m);
  DensityGrid grid;
  ASSERT_TRUE(grid.build(m.points, m.tets, vertex_density(m.points, m.tets), 0));
  PhasedOdtTarget target;
  target.density = &grid;
  const PhasedOdtStats stats = phased_odt(mesh, cube_geometry(), target);
  ASSERT_GE(stats.min_stretch_before, 0.3);
  EXPECT_TRUE(stats.skipped);
  EXPECT_EQ(mesh.points(), m.points);
  EXPECT_EQ(mesh.compact().tets, m.tets);
  // The same with Poor Elements Only: no tet below the floor, nothing to do.
  PhasedOdtOptions repair;
  repair.poor_elements_only = true;
  EXPECT_TRUE(phased_odt(mesh, cube_geometry(), target, repair).skipped);
  EXPECT_EQ(mesh.points(), m.points);

  TetMesh jittered = build(testing::make_cube_mesh(6, 0.1, 1));
  jitter_inner(jittered, 2);
  EXPECT_FALSE(phased_odt(jittered, cube_geometry(), target).skipped);
}

// Issue 29: Improve with default settings made a perfect lattice of 48 tets
// (2 x 2 x 2 cubes of 6 Kuhn tets) worse: 84 tets, minimum stretch 0.586 ->
// 0.550. The result's minimum may never fall below min(the input's minimum,
// the quality floor) (PhasedOdtOptions::keep_minimum), checked on perfect and
// near-perfect inputs with the density target the filter makes without a
// Reference (the input's own); with keep_input_minimum, as the filter runs
// without a Reference, not below the input's minimum, and the lattice comes
// out as it went in.
TEST(PhasedOdt, NeverEndsBelowTheInputMinimumOrTheFloor) {
  for (const int n : {2, 3, 4}) {
    for (const double jitter : {0.0, 0.02, 0.08}) {
      for (const bool own_minimum : {false, true}) {
        SCOPED_TRACE(::testing::Message() << n << " cells across, jitter " << jitter << ", own minimum "
                                          << own_minimum);
        const testing::TestMesh m = testing::make_cube_mesh(n, jitter, 7);
        TetMesh mesh = build(m);
        const BoundaryGeometry geometry = cube_geometry();
        const ImproveTarget target = make_improve_target(mesh, &geometry, nullptr);
        PhasedOdtOptions options;
        options.keep_input_minimum = own_minimum;
        const PhasedOdtStats stats = phased_odt(mesh, geometry, target.view(), options);
        const CompactMesh out = mesh.compact();
        const double bound =
            own_minimum ? stats.min_stretch_before : std::min(stats.min_stretch_before, options.quality_floor);
        EXPECT_GE(measure(out).min, bound);
        EXPECT_GE(stats.min_stretch_after, bound);
        const ValidityReport report = check_validity(out.points, out.tets);
        EXPECT_TRUE(report.ok()) << report.summary();
        if (stats.kept_input) {
          EXPECT_LT(stats.min_stretch_rejected, bound);
          EXPECT_EQ(out.tets.size(), m.tets.size());
          EXPECT_EQ(out.points, m.points);
        }
        if (n == 2 && jitter == 0 && own_minimum) {
          // The lattice: as it went in.
          EXPECT_EQ(out.tets.size(), 48u);
          EXPECT_EQ(measure(out).min, stats.min_stretch_before);
        }
      }
    }
  }
}

// The region restriction: the tets of the lower half (input tets with a
// vertex below z = 0.5 unflagged) keep their points.
TEST(PhasedOdt, TetMaskKeepsTheRestUnchanged) {
  const testing::TestMesh m = testing::make_cube_mesh(6, 0.1, 7);
  TetMesh mesh = build(m);
  jitter_inner(mesh, 4);
  const std::vector<Vec3> before = mesh.points();
  PhasedOdtOptions options;
  options.tet_mask.assign(m.tets.size(), 1);
  std::vector<char> fixed(before.size(), 0);
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (const index_t v : m.tets[t])
      if (before[v].z() < 0.5) {
        options.tet_mask[t] = 0;
        for (const index_t w : m.tets[t]) fixed[w] = 1;
      }
  phased_odt(mesh, cube_geometry(), PhasedOdtTarget(), options);
  const ValidityReport report = check_validity(mesh.compact().points, mesh.compact().tets);
  EXPECT_TRUE(report.ok()) << report.summary();
  std::size_t changed = 0, improved = 0;
  for (std::size_t v = 0; v < before.size(); ++v) {
    const bool moved = !mesh.vertex_alive(static_cast<index_t>(v)) || mesh.point(static_cast<index_t>(v)) != before[v];
    (fixed[v] ? changed : improved) += moved;
  }
  EXPECT_EQ(changed, 0u);
  EXPECT_GT(improved, 50u);  // the upper half was worked on
}

// poor_elements_only: the jittered half x < 0.45 of a perfect cube is
// repaired, and the rest stays as it is: every input tet away from the
// tets below the floor (0.3) and from their neighbours keeps its vertices
// and their points.
TEST(PhasedOdt, PoorElementsOnlyRepairsAndLeavesTheRest) {
  const testing::TestMesh m = testing::make_cube_mesh(8, 0, 5);
  TetMesh mesh = build(m);
  {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
      if (mesh.on_boundary(v) || mesh.point(v).x() >= 0.45) continue;
      const Vec3 d(u(rng), u(rng), u(rng));
      mesh.move_vertex(v, mesh.point(v) + 0.4 * 0.125 * d);
    }
  }
  const TetMesh input = mesh;
  std::vector<char> near(static_cast<std::size_t>(input.vertex_slots()), 0);
  std::vector<index_t> ring;
  std::size_t poor = 0;
  for (index_t t = 0; t < input.tet_slots(); ++t) {
    const Tet& T = input.tet(t);
    if (tet_stretch(input.point(T[0]), input.point(T[1]), input.point(T[2]), input.point(T[3])) >= 0.3) continue;
    ++poor;
    for (const index_t v : T) {
      input.vertex_neighbors(v, ring);
      near[v] = 1;
      for (const index_t w : ring) near[w] = 1;
    }
  }
  ASSERT_GT(poor, 50u);
  PhasedOdtOptions options;
  options.poor_elements_only = true;
  const PhasedOdtStats stats = phased_odt(mesh, cube_geometry(), PhasedOdtTarget(), options);
  ASSERT_TRUE(mesh.check_consistency().ok) << mesh.check_consistency().message;
  const CompactMesh out = mesh.compact();
  const ValidityReport report = check_validity(out.points, out.tets);
  EXPECT_TRUE(report.ok()) << report.summary();
  const Measured after = measure(out);
  std::printf("poor elements only: min %.3f -> %.3f, mean %.3f -> %.3f, %zu tets below 0.3\n", stats.min_stretch_before,
              after.min, stats.mean_stretch_before, after.mean, poor);
  EXPECT_LT(stats.min_stretch_before, 0.1);
  EXPECT_GE(after.min, 0.3);
  EXPECT_EQ(stats.below_floor, 0u);
  EXPECT_NEAR(after.volume, 1.0, 1e-12);
  EXPECT_EQ(stats.collapses, 0u);  // no density control
  std::size_t kept = 0, far = 0;
  for (index_t t = 0; t < input.tet_slots(); ++t) {
    const Tet& T = input.tet(t);
    if (std::any_of(T.begin(), T.end(), [&](index_t v) { return near[v]; })) continue;
    ++far;
    const index_t s = mesh.find_face(T[0], T[1], T[2]);
    kept += s >= 0 && mesh.local_index(s, T[3]) >= 0 &&
            std::all_of(T.begin(), T.end(), [&](index_t v) { return mesh.point(v) == input.point(v); });
  }
  EXPECT_GT(far, input.live_tets() / 4);  // much of the good half is there to check
  EXPECT_EQ(kept, far);
}

TEST(PhasedOdt, AbortLeavesAValidMesh) {
  const testing::TestMesh m = testing::make_cube_mesh(6, 0.1, 7);
  TetMesh mesh = build(m);
  jitter_inner(mesh, 4);
  PhasedOdtOptions options;
  int calls = 0;
  options.progress = [&calls](double, const char*) { return ++calls < 3; };
  const PhasedOdtStats stats = phased_odt(mesh, cube_geometry(), PhasedOdtTarget(), options);
  EXPECT_TRUE(stats.aborted);
  EXPECT_EQ(calls, 3);
  ASSERT_TRUE(mesh.check_consistency().ok);
  const CompactMesh out = mesh.compact();
  EXPECT_TRUE(check_validity(out.points, out.tets).ok());
}

// A region without a fit (the top face z = 1 of the cube, declared Unknown)
// whose surface vertices were moved along it: with move_unfitted_regions
// they move again, on the region's triangles as given (and its flat pairs of
// triangles flip), and the tets on that face get better than when they stay;
// the face stays exactly where it was.
TEST(PhasedOdt, UnfittedRegionVerticesMoveOnTheirTriangles) {
  const testing::TestMesh m = testing::make_cube_mesh(8, 0.1, 5);
  TetMesh jittered = build(m);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::size_t top = 0;
  for (index_t v = 0; v < jittered.vertex_slots(); ++v) {
    const Vec3 p = jittered.point(v);
    if (jittered.vertex_class(v) != VertexClass::Surface || p.z() != 1) continue;
    ++top;
    jittered.move_vertex(v, p + Vec3(0.05 * u(rng), 0.05 * u(rng), 0));  // 40% of the edge
  }
  ASSERT_GT(top, 30u);
  BoundaryGeometry geometry = cube_geometry();
  geometry.regions[5].type = SurfaceType::Unknown;  // z = 1
  double min_top[2] = {0, 0};
  for (const bool move : {false, true}) {
    TetMesh mesh = jittered;
    PhasedOdtOptions options;
    options.move_unfitted_regions = move;
    const PhasedOdtStats stats = phased_odt(mesh, geometry, PhasedOdtTarget(), options);
    const CompactMesh out = mesh.compact();
    EXPECT_TRUE(check_validity(out.points, out.tets).ok());
    EXPECT_NEAR(measure(out).volume, 1.0, 1e-12);
    if (move) {
      EXPECT_GT(stats.surface_flips, 0u);  // flat pairs of the face flip too
    }
    min_top[move] = std::numeric_limits<double>::infinity();
    std::size_t moved = 0;
    for (const Tet& t : out.tets) {
      bool on_top = false;
      for (const index_t v : t) on_top = on_top || out.points[v].z() == 1;
      if (on_top)
        min_top[move] = std::min(min_top[move], tet_stretch(out.points[t[0]], out.points[t[1]], out.points[t[2]],
                                                            out.points[t[3]]));
    }
    // The input's top vertices still there (a degenerate removal may take
    // one out, and a later split reuse its slot for a new vertex: its stencil
    // is no longer the input vertex's own).
    for (index_t v = 0; v < jittered.vertex_slots(); ++v)
      if (jittered.vertex_class(v) == VertexClass::Surface && jittered.point(v).z() == 1 && mesh.vertex_alive(v) &&
          mesh.vertex_origin(v).ids[0] == v) {
        EXPECT_EQ(mesh.point(v).z(), 1.0);  // exactly on the kept triangles
        moved += mesh.point(v) != jittered.point(v);
      }
    if (move)
      EXPECT_GT(moved, top / 2);
    else
      EXPECT_EQ(moved, 0u);
  }
  std::printf("tets on the unfitted face: min stretch %.3f kept, %.3f moved\n", min_top[0], min_top[1]);
  EXPECT_GT(min_top[1], min_top[0] + 0.05);
  EXPECT_GE(min_top[1], 0.3);
}

// Mesh density control asked for a mesh twice as coarse collapses cylinder
// edges and lengthens their chords; with the chord test of Phased ODT
// (collapse_chords_within_error) no cylinder ends beyond its acceptable error
// (here its error as given), without it they do.
// Improve's density goal: mean density error (Eq. 2.35) <= 0.15 against the
// reference, as the thesis' Fig. 2.53 (Netgen mesh, 0.26 -> 0.15). With a reference as
// uniform as that one (the BCC lattice box scores 0.08 against its own
// field), a slab stretched x3 (0.23 after the stretch) and x1.6 ends at or
// below 0.15; the mesh valid, min stretch >= 0.3, the box's planes and
// volume exact; at x3 the mesh renumbered in space after each density
// control (as meshes of 100,000 tets and more are). (A Gmsh mesh scores 0.17-0.21 against its own field, so
// there the error ends near that: test_vtk_improve.)
TEST(PhasedOdt, UniformReferenceDensityRecoveredWithin015) {
  const testing::TestMesh ref = testing::make_bcc_box_mesh(8, 2);
  ASSERT_TRUE(check_validity(ref.points, ref.tets).ok());
  const std::vector<double> rho = vertex_density(ref.points, ref.tets);
  DensityGrid own;
  ASSERT_TRUE(own.build(ref.points, ref.tets, rho, 0));
  const double own_error = mean_density_error(ref.points, ref.tets, own, DensityLookup::Cell).mean;
  EXPECT_LT(own_error, 0.1);
  for (const double factor : {3.0, 1.6}) {
    SCOPED_TRACE(factor);
    // z in [0.5, 1.5] stretched, above it moved up.
    testing::TestMesh deformed = ref;
    for (Vec3& p : deformed.points)
      p.z() = p.z() <= 0.5 ? p.z() : (p.z() >= 1.5 ? p.z() + (factor - 1) : 0.5 + factor * (p.z() - 0.5));
    const double top = 1.0 + factor;
    DensityGrid grid;  // the reference's density on the deformed positions
    ASSERT_TRUE(grid.build(deformed.points, ref.tets, rho, 0));
    TetMesh mesh = build(deformed);
    BoundaryGeometry geometry;
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side)
        geometry.regions.push_back(plane(side * (axis == 2 ? top : 1.0) * Vec3::Unit(axis), Vec3::Unit(axis)));
    PhasedOdtTarget target;
    target.density = &grid;
    PhasedOdtOptions options;
    if (factor == 3.0) options.sort_min_tets = 0;  // renumbered in space after each density control
    const PhasedOdtStats stats = phased_odt(mesh, geometry, target, options);
    std::printf("BCC box x%.1f: density error own %.3f, %.3f -> %.3f; tets %zu -> %zu; stretch min %.3f -> %.3f\n",
                factor, own_error, stats.density_error_before.mean, stats.density_error_after.mean,
                stats.tets_before, stats.tets_after, stats.min_stretch_before, stats.min_stretch_after);
    if (factor == 3.0) {
      EXPECT_GT(stats.density_error_before.mean, 0.2);
    }
    EXPECT_LE(stats.density_error_after.mean, 0.15);
    EXPECT_GT(stats.tets_after, stats.tets_before);
    const CompactMesh out = mesh.compact();
    const ValidityReport report = check_validity(out.points, out.tets);
    EXPECT_TRUE(report.ok()) << report.summary();
    const Measured after = measure(out);
    EXPECT_GE(after.min, 0.3);
    EXPECT_NEAR(after.volume, top, 1e-9 * top);
    for (std::size_t v = 0; v < out.points.size(); ++v) {
      if (out.vertex_classes[v] == VertexClass::Inner) continue;
      const Vec3& p = out.points[v];
      const double d = std::min({std::abs(p.x()), std::abs(p.x() - 1), std::abs(p.y()), std::abs(p.y() - 1),
                                 std::abs(p.z()), std::abs(p.z() - top)});
      EXPECT_LE(d, 1e-12 * top) << "boundary point " << v;
    }
  }
}

// What limits the quality is reported: the tets left below the floor, and
// those of them with all four vertices on the boundary (no inner vertex to
// move). A Kuhn cube flattened to a plate 0.1 thick: its tets are flat and
// most have no inner vertex; both counts match a count made here from the
// output (boundary vertices: those of faces used once).
TEST(PhasedOdt, ReportsTheTetsLeftBelowTheFloor) {
  testing::TestMesh m = testing::make_cube_mesh(3, 0.0, 1);
  for (Vec3& p : m.points) p.z() *= 0.1;
  TetMesh mesh = build(m);
  BoundaryGeometry geometry;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      geometry.regions.push_back(plane(side * (axis == 2 ? 0.1 : 1.0) * Vec3::Unit(axis), Vec3::Unit(axis)));
  const PhasedOdtStats stats = phased_odt(mesh, geometry, PhasedOdtTarget{});
  const CompactMesh out = mesh.compact();
  ASSERT_TRUE(check_validity(out.points, out.tets).ok());
  std::map<std::array<index_t, 3>, int> faces;
  for (const Tet& t : out.tets)
    for (int f = 0; f < 4; ++f) {
      std::array<index_t, 3> k{{t[kTetFace[f][0]], t[kTetFace[f][1]], t[kTetFace[f][2]]}};
      std::sort(k.begin(), k.end());
      ++faces[k];
    }
  std::vector<char> boundary(out.points.size(), 0);
  for (const auto& [k, n] : faces)
    if (n == 1)
      for (const index_t v : k) boundary[v] = 1;
  std::size_t below = 0, locked = 0;
  for (const Tet& t : out.tets) {
    if (!(tet_stretch(out.points[t[0]], out.points[t[1]], out.points[t[2]], out.points[t[3]]) < 0.3)) continue;
    ++below;
    locked += boundary[t[0]] && boundary[t[1]] && boundary[t[2]] && boundary[t[3]];
  }
  std::printf("plate: %zu tets, min stretch %.3f, %zu below 0.3, %zu of them without an inner vertex\n",
              out.tets.size(), stats.min_stretch_after, below, locked);
  EXPECT_GT(locked, 0u);
  EXPECT_EQ(stats.below_floor, below);
  EXPECT_EQ(stats.below_floor_on_boundary, locked);
}

TEST(ShapeAccuracy, DensityCollapsesKeepTheChordError) {
  const Annulus a = make_annulus();
  const GridMesh gm = make_grid_mesh(a.grid);
  const std::vector<double> given = region_geometric_error(build(gm.mesh), a.geometry);
  const std::vector<double> acceptable = {given[0], given[1], std::nan(""), std::nan("")};
  const double target = 0.5 / mean_edge_length(gm.mesh.points, gm.mesh.tets);
  DensityGrid grid;
  ASSERT_TRUE(grid.build(gm.mesh.points, gm.mesh.tets, std::vector<double>(gm.mesh.points.size(), target),
                         0.25 / target));
  const auto run = [&](bool chord_test, std::size_t* collapses) {
    TetMesh mesh = build(gm.mesh);
    DensityControlOptions options;
    options.max_iterations = 4;
    options.project = [&](index_t v, const Vec3& p) {
      Vec3 q;
      const VertexConstraint c = vertex_constraint(mesh, a.geometry, v);
      return (c.kind == VertexConstraint::Surface || c.kind == VertexConstraint::Curve) &&
                     project_to_constraint(c, p, &q)
                 ? q
                 : p;
    };
    if (chord_test)
      options.accept_boundary_collapse = [&](index_t keep, index_t remove, const Vec3& x,
                                             const std::vector<index_t>& bk, const std::vector<index_t>& br) {
        return collapse_chords_within_error(mesh, a.geometry, acceptable, keep, remove, x, bk, br);
      };
    *collapses = control_mesh_density(mesh, grid, options).collapses;
    const CompactMesh out = mesh.compact();
    EXPECT_TRUE(check_validity(out.points, out.tets).ok());
    return region_geometric_error(mesh, a.geometry);
  };
  std::size_t with_test = 0, without_test = 0;
  const std::vector<double> kept = run(true, &with_test), lost = run(false, &without_test);
  std::printf("chord error given %.4f / %.4f; density collapses with the chord test %zu: %.4f / %.4f; without %zu: "
              "%.4f / %.4f\n",
              given[0], given[1], with_test, kept[0], kept[1], without_test, lost[0], lost[1]);
  EXPECT_GT(with_test, 0u);
  EXPECT_LE(kept[0], acceptable[0]);
  EXPECT_LE(kept[1], acceptable[1]);
  EXPECT_GT(std::max(lost[0] / acceptable[0], lost[1] / acceptable[1]), 1.2);
}

// Accuracy control (2.6.4) on the annulus: asked for half the chord error
// of each cylinder, it splits cylinder edges and projects the new points on
// the cylinders until every edge midpoint is within it; the circles' vertex
// lists, traced on the new mesh, are closed chains of edges on the circles.
TEST(ShapeAccuracy, SplitsUntilTheCylindersAreWithinTheError) {
  const Annulus a = make_annulus();
  const GridMesh gm = make_grid_mesh(a.grid);
  TetMesh mesh = build(gm.mesh);
  const std::vector<double> error = region_geometric_error(mesh, a.geometry);
  ASSERT_EQ(error.size(), 4u);
  EXPECT_GT(error[0], 0);
  EXPECT_GT(error[1], 0);
  EXPECT_TRUE(std::isnan(error[2]) && std::isnan(error[3]));  // planes
  // The same from the tet list and its face regions (the filter's path for
  // a Reference mesh), bit for bit.
  const std::vector<double> from_arrays =
      region_geometric_error(gm.mesh.points, gm.mesh.tets, gm.mesh.face_regions, a.geometry);
  ASSERT_EQ(from_arrays.size(), 4u);
  EXPECT_EQ(from_arrays[0], error[0]);
  EXPECT_EQ(from_arrays[1], error[1]);
  EXPECT_TRUE(std::isnan(from_arrays[2]) && std::isnan(from_arrays[3]));
  std::vector<double> acceptable = {0.5 * error[0], 0.5 * error[1], std::nan(""), std::nan("")};
  AccuracyControlOptions options;
  options.min_stretch = 0;  // only validity: the goal here is the error
  const AccuracyControlStats stats = control_shape_accuracy(mesh, a.geometry, acceptable, options);
  EXPECT_GT(stats.splits, 0u);
  const std::vector<double> after = region_geometric_error(mesh, a.geometry);
  EXPECT_LE(after[0], acceptable[0]);
  EXPECT_LE(after[1], acceptable[1]);
  const CompactMesh out = mesh.compact();
  EXPECT_TRUE(check_validity(out.points, out.tets).ok());
  for (std::size_t v = 0; v < out.points.size(); ++v) {
    const double r = std::hypot(out.points[v].x(), out.points[v].y());
    if (out.vertex_classes[v] == VertexClass::Inner) continue;
    if (std::abs(r - a.r_in) < 0.1) {
      EXPECT_NEAR(r, a.r_in, 1e-12);
    } else if (std::abs(r - a.r_out) < 0.1) {
      EXPECT_NEAR(r, a.r_out, 1e-12);
    }
  }

  // The four circles' old vertex lists, in angular order.
  std::vector<std::vector<index_t>> old_curves(4);
  for (std::size_t v = 0; v < gm.ijk.size(); ++v) {
    const auto& c = gm.ijk[v];
    const bool in = c[0] == 0, outer = c[0] == a.grid.n[0], bottom = c[2] == 0, top = c[2] == a.grid.n[2];
    if ((in || outer) && (bottom || top)) old_curves[2 * (outer ? 1 : 0) + (top ? 1 : 0)].push_back(static_cast<index_t>(v));
  }
  for (auto& c : old_curves)
    std::sort(c.begin(), c.end(), [&](index_t x, index_t y) { return gm.ijk[x][1] < gm.ijk[y][1]; });
  const auto traced = trace_boundary_curves(out, old_curves, a.geometry.curve_regions);
  ASSERT_EQ(traced.size(), 4u);
  std::set<Edge> edges;
  for (const Edge& e : unique_edges(out.tets, static_cast<index_t>(out.points.size()))) edges.insert(e);
  for (int c = 0; c < 4; ++c) {
    const auto& list = traced[c];
    ASSERT_GE(list.size(), old_curves[c].size()) << "curve " << c;
    const double r = c < 2 ? a.r_in : a.r_out, z = (c % 2) * a.height;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const index_t u = list[i], w = list[(i + 1) % list.size()];  // closed
      EXPECT_TRUE(edges.count({std::min(u, w), std::max(u, w)})) << "curve " << c << " at " << i;
      EXPECT_NEAR(std::hypot(out.points[u].x(), out.points[u].y()), r, 1e-12);
      EXPECT_NEAR(out.points[u].z(), z, 1e-12);
    }
    // Oriented like the old list: the second survivor follows the first.
    EXPECT_EQ(list[0], out.vertex_map[old_curves[c][0]]);
    const auto second = std::find(list.begin(), list.end(), out.vertex_map[old_curves[c][1]]);
    EXPECT_LT(second - list.begin(), static_cast<long>(list.size() / 2));
  }
}

}  // namespace
}  // namespace femorph
