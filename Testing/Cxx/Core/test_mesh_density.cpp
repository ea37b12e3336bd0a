// Mesh density (thesis 2.6.3 Eq. 2.32, 2.33, 2.35) and its control by edge
// split and collapse (Fig. 2.40).
#include "improve/control_mesh_density.h"
#include "improve/boundary_geometry.h"
#include "improve/edge_queue.h"
#include "improve/mesh_density.h"
#include "improve/odt_smooth_surface.h"
#include "improve/relax_edge_lengths.h"
#include "mesh/tet_mesh.h"
#include "mesh/unique_edges.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"

#include "../test_meshes.h"
#include "../test_surfaces.h"
#include "../test_threads.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <ostream>
#include <queue>
#include <random>
#include <string>

namespace femorph {
namespace {

using testing::make_cube_mesh;
using testing::TestMesh;
using testing::total_volume;

// Kuhn cube (make_cube_mesh, no jitter, cell size h): an interior vertex has
// 14 edges, 6 along the axes (h), 6 face diagonals (h sqrt 2) along
// +-(1,1,0), +-(1,0,1), +-(0,1,1) and 2 body diagonals (h sqrt 3) along
// +-(1,1,1); the corner (0,0,0) has half of each (3, 3, 1). Eq. 2.32 gives
//   interior: (6 + 6/sqrt2 + 2/sqrt3) / (14 h)
//   corner:   (3 + 3/sqrt2 + 1/sqrt3) / (7 h)   (the same value)
// and a vertex in the middle of the face z = 0: 9 edges, 4 axis (in the
// face) + 1 axis (inward), 2 face diagonals in the face, 2 out of it
// ((1,0,1), (0,1,1)), 1 body diagonal: (5 + 4/sqrt2 + 1/sqrt3) / (10 h).
TEST(MeshDensity, VertexDensityKuhnCubeClosedForm) {
  const int n = 4;
  const double h = 1.0 / n;
  const TestMesh m = make_cube_mesh(n, 0.0, 1);
  const std::vector<double> rho = vertex_density(m.points, m.tets);
  const auto id = [n](int i, int j, int k) { return static_cast<std::size_t>((k * (n + 1) + j) * (n + 1) + i); };
  const double s2 = std::sqrt(2.0), s3 = std::sqrt(3.0);
  const double interior = (6 + 6 / s2 + 2 / s3) / (14 * h);
  EXPECT_NEAR(rho[id(2, 2, 2)], interior, 1e-12);
  EXPECT_NEAR(rho[id(1, 3, 2)], interior, 1e-12);
  EXPECT_NEAR(rho[id(0, 0, 0)], interior, 1e-12);
  EXPECT_NEAR(rho[id(n, n, n)], interior, 1e-12);
  EXPECT_NEAR(rho[id(2, 2, 0)], (5 + 4 / s2 + 1 / s3) / (10 * h), 1e-12);
  EXPECT_NEAR(interior * h, 0.8141, 1e-4);  // "1/h-ish"

  // The TetMesh overload agrees, and so does a uniformly scaled mesh / s.
  TetMesh mesh;
  ASSERT_TRUE(mesh.build(m.points, m.tets).ok);
  const std::vector<double> rho_mesh = vertex_density(mesh);
  ASSERT_EQ(rho_mesh.size(), rho.size());
  for (std::size_t i = 0; i < rho.size(); ++i) EXPECT_DOUBLE_EQ(rho_mesh[i], rho[i]);
  std::vector<Vec3> scaled = m.points;
  for (Vec3& p : scaled) p *= 2.0;
  EXPECT_NEAR(vertex_density(scaled, m.tets)[id(2, 2, 2)], interior / 2, 1e-12);

  // Unused points get 0.
  std::vector<Vec3> extra = m.points;
  extra.push_back(Vec3(5, 5, 5));
  EXPECT_EQ(vertex_density(extra, m.tets).back(), 0.0);

  // Mean edge length: per cell 3 axis, 3 face and 1 body diagonal edges
  // plus the boundary's share; check against a direct count.
  EXPECT_GT(mean_edge_length(m.points, m.tets), h);
  EXPECT_LT(mean_edge_length(m.points, m.tets), h * s3);
  // vertex_density's by-product is the same number.
  double mean_length = 0;
  vertex_density(m.points, m.tets, &mean_length);
  EXPECT_EQ(mean_length, mean_edge_length(m.points, m.tets));
}

double linear_field(const Vec3& p) { return 1.0 + 0.3 * p.x() + 0.2 * p.y() - 0.1 * p.z(); }

TEST(MeshDensity, GridExactForLinearFields) {
  // Jittered mesh: Eq. 2.33 reproduces linear vertex values at every grid
  // point inside the mesh, and trilinear interpolation reproduces them between.
  const TestMesh m = make_cube_mesh(5, 0.1, 7);
  std::vector<double> values(m.points.size());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = linear_field(m.points[i]);
  DensityGrid grid;
  ASSERT_TRUE(grid.build(m.points, m.tets, values, 0.125));
  EXPECT_EQ(grid.cells()[0], 8);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int s = 0; s < 200; ++s) {
    const Vec3 p(u(rng), u(rng), u(rng));
    EXPECT_NEAR(grid.density_at(p), linear_field(p), 1e-12);
    // rho_GC: mean of the 8 corners = value at the cell centre.
    const Vec3 c = grid.origin() + grid.cell_size() * ((p - grid.origin()) / grid.cell_size()).array().floor().matrix() +
                   Vec3::Constant(0.5 * grid.cell_size());
    EXPECT_NEAR(grid.cell_density(p), linear_field(c), 1e-12);
  }
  for (int k = 0; k <= 8; ++k)
    for (int j = 0; j <= 8; ++j)
      for (int i = 0; i <= 8; ++i)
        EXPECT_NEAR(grid.point_value(i, j, k), linear_field(Vec3(i, j, k) * 0.125), 1e-12);

  // A spacing that overshoots the box: points outside the mesh are filled
  // from their neighbours, points inside stay exact.
  DensityGrid coarse;
  ASSERT_TRUE(coarse.build(m.points, m.tets, values, 0.3));
  EXPECT_EQ(coarse.cells()[0], 4);
  EXPECT_EQ(coarse.point_value(4, 4, 4), 0.0);  // (1.2, 1.2, 1.2): outside
  for (int s = 0; s < 100; ++s) {
    const Vec3 p = 0.9 * Vec3(u(rng), u(rng), u(rng));
    EXPECT_NEAR(coarse.density_at(p), linear_field(p), 1e-12);
  }
  const Vec3 outside(1.15, 1.15, 1.15);
  EXPECT_GT(coarse.density_at(outside), 0.0);
  EXPECT_GT(coarse.cell_density(outside), 0.0);
  // Far outside: clamped to the grid.
  EXPECT_DOUBLE_EQ(coarse.density_at(Vec3(-10, 0.5, 0.5)), coarse.density_at(Vec3(0, 0.5, 0.5)));

  // Cell lookups only (as Improve builds it): the same cell values, and a
  // trilinear lookup answers with the cell value, not a stale or empty one.
  DensityGrid cells_only;
  ASSERT_TRUE(cells_only.build(m.points, m.tets, values, 0.3, std::size_t(1) << 27, false));
  for (int s = 0; s < 100; ++s) {
    const Vec3 p = 1.1 * Vec3(u(rng), u(rng), u(rng));
    EXPECT_EQ(cells_only.cell_density(p), coarse.cell_density(p));
    EXPECT_EQ(cells_only.density_at(p), coarse.cell_density(p));
  }

  // Default spacing: half the mean edge length.
  DensityGrid def;
  ASSERT_TRUE(def.build(m.points, m.tets, values, 0.0));
  EXPECT_DOUBLE_EQ(def.cell_size(), 0.5 * mean_edge_length(m.points, m.tets));
  // Refusals.
  EXPECT_FALSE(DensityGrid().build(m.points, {}, values, 0.1));
  EXPECT_FALSE(DensityGrid().build(m.points, m.tets, values, 1e-4, 1000));
  EXPECT_TRUE(DensityGrid().empty());
}

TEST(MeshDensity, GridDoesNotDependOnThreadCount) {
  // The tets are scanned in parallel; a grid point on a face shared by two
  // tets (the unjittered cube with the grid on its lattice has many) takes
  // the value from the first tet, whatever the number of threads.
  for (const double jitter : {0.0, 0.1}) {
    const TestMesh m = make_cube_mesh(12, jitter, 5);
    ASSERT_GE(m.tets.size(), 10000u);  // past the parallel threshold
    std::vector<double> values(m.points.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] = 2.0 + std::sin(7 * m.points[i].x()) * std::cos(5 * m.points[i].y()) + m.points[i].z();
    // On the lattice, and overshooting the cube: a layer of grid points
    // outside, filled from their neighbours.
    for (const double cell : {1.0 / 24, 1.0 / 23.4}) {
      DensityGrid one, two;
      ASSERT_TRUE(testing::with_threads(1, [&] { return one.build(m.points, m.tets, values, cell); }));
      ASSERT_TRUE(testing::with_threads(2, [&] { return two.build(m.points, m.tets, values, cell); }));
      ASSERT_EQ(one.cells(), two.cells());
      const auto n = one.cells();
      std::size_t differing = 0;
      for (int k = 0; k <= n[2]; ++k)
        for (int j = 0; j <= n[1]; ++j)
          for (int i = 0; i <= n[0]; ++i) differing += one.point_value(i, j, k) != two.point_value(i, j, k);
      std::mt19937_64 rng(9);
      std::uniform_real_distribution<double> u(-0.1, 1.1);
      for (int s = 0; s < 2000; ++s) {
        const Vec3 p(u(rng), u(rng), u(rng));
        differing += one.cell_density(p) != two.cell_density(p);
        differing += one.density_at(p) != two.density_at(p);
      }
      EXPECT_EQ(differing, 0u) << "jitter " << jitter << ", cell " << cell;
      if (cell > 1.0 / 24) {
        EXPECT_EQ(one.point_value(n[0], n[1], n[2]), 0.0);     // outside the cube
        EXPECT_GT(one.density_at(Vec3::Constant(1.02)), 0.0);  // filled
      }
    }
  }
}

TEST(MeshDensity, MeanDensityErrorClosedForm) {
  // Kuhn cube against a constant field rho: eps = |1/L - rho| / rho per edge.
  const int n = 3;
  const double h = 1.0 / n;
  const TestMesh m = make_cube_mesh(n, 0.0, 1);
  const double rho = 1.0 / h;  // axis edges exact
  DensityGrid grid;
  ASSERT_TRUE(grid.build(m.points, m.tets, std::vector<double>(m.points.size(), rho), 0.5 * h));
  const DensityError e = mean_density_error(m.points, m.tets, grid);
  // Edges: axis 3 n (n+1)^2, face diagonals 3 n^2 (n+1), body diagonals n^3.
  const double axis = 3.0 * n * (n + 1) * (n + 1), face = 3.0 * n * n * (n + 1), body = 1.0 * n * n * n;
  const double expected = (face * (1 - 1 / std::sqrt(2.0)) + body * (1 - 1 / std::sqrt(3.0))) / (axis + face + body);
  EXPECT_EQ(e.edges, static_cast<std::size_t>(axis + face + body));
  EXPECT_NEAR(e.mean, expected, 1e-12);
  EXPECT_NEAR(e.max, 1 - 1 / std::sqrt(3.0), 1e-12);
  TetMesh mesh;
  ASSERT_TRUE(mesh.build(m.points, m.tets).ok);
  EXPECT_NEAR(mean_density_error(mesh, grid).mean, expected, 1e-12);
}

struct DensityRun {
  DensityControlStats stats;
  CompactMesh out;
  std::vector<Vec3> deformed;  // the input of the control, indexed as the reference
  double reference_error = 0;  // Eq. 2.35 of the reference mesh against its own field
  double min_stretch_before = 0;
};

double min_stretch(const std::vector<Vec3>& points, const std::vector<Tet>& tets) {
  double worst = 1;
  for (const Tet& t : tets)
    worst = std::min(worst, tet_stretch(points[t[0]], points[t[1]], points[t[2]], points[t[3]]));
  return worst;
}

double mean_stretch(const std::vector<Vec3>& points, const std::vector<Tet>& tets) {
  double sum = 0;
  for (const Tet& t : tets) sum += tet_stretch(points[t[0]], points[t[1]], points[t[2]], points[t[3]]);
  return tets.empty() ? 0.0 : sum / static_cast<double>(tets.size());
}

/// The thesis case (b) in spirit (2.7.4, Fig. 2.53: the distance between two
/// parallel planes changed): a cube mesh stretched by `factor` along x (all
/// points scaled). The target field is built as in Fig. 2.40 (b): a grid
/// over the deformed mesh whose grid points take the original vertex
/// densities, interpolated in the deformed tets (same connectivity). So the
/// density travels with the material and the field asks for the original
/// edge lengths in the stretched domain. Cell size: half the mean edge
/// length of the original mesh (the thesis' suggestion).
DensityRun run_stretched(int n, double jitter, double factor, const DensityControlOptions& options) {
  const TestMesh ref = make_cube_mesh(n, jitter, 11);
  const std::vector<double> rho = vertex_density(ref.points, ref.tets);
  const double cell = 0.5 * mean_edge_length(ref.points, ref.tets);
  DensityRun run;
  run.deformed = ref.points;
  for (Vec3& p : run.deformed) p.x() *= factor;
  DensityGrid grid;
  EXPECT_TRUE(grid.build(run.deformed, ref.tets, rho, cell));
  DensityGrid ref_grid;
  EXPECT_TRUE(ref_grid.build(ref.points, ref.tets, rho, cell));
  run.reference_error = mean_density_error(ref.points, ref.tets, ref_grid).mean;
  run.min_stretch_before = min_stretch(run.deformed, ref.tets);
  TetMesh mesh;
  BuildOptions build;
  build.face_regions = ref.face_regions;
  EXPECT_TRUE(mesh.build(run.deformed, ref.tets, build).ok);
  run.stats = control_mesh_density(mesh, grid, options);
  EXPECT_TRUE(mesh.check_consistency().ok);
  run.out = mesh.compact();
  return run;
}

void expect_valid_box(const CompactMesh& out, double factor) {
  const ValidityReport report = check_validity(out.points, out.tets);
  EXPECT_TRUE(report.ok()) << report.summary();
  for (const Tet& t : out.tets)
    EXPECT_GT(tet_signed_volume(out.points[t[0]], out.points[t[1]], out.points[t[2]], out.points[t[3]]), 0.0);
  EXPECT_NEAR(total_volume(out.points, out.tets), factor, 1e-12 * factor);
  // Boundary faces stay on the cube's planes, exactly.
  const double extent[3] = {factor, 1.0, 1.0};
  std::size_t checked = 0;
  for (std::size_t t = 0; t < out.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      const index_t region = out.face_regions[t][f];
      if (region < 0) continue;
      const int axis = region / 2;
      const double plane = region % 2 ? extent[axis] : 0.0;
      for (int q = 0; q < 3; ++q) {
        EXPECT_EQ(out.points[out.tets[t][kTetFace[f][q]]][axis], plane);
        ++checked;
      }
    }
  EXPECT_GT(checked, 0u);
}

// Improve's density goal, 0.15, is the thesis' result (Table 2.14: 0.26 ->
// 0.15 on a NETGEN mesh, density control inside Phased ODT smoothing). A Kuhn
// cube is a poor reference for Eq. 2.35: its edges are h, h sqrt 2 and h sqrt 3
// while 1 / rho = 1.228 h (VertexDensityKuhnCubeClosedForm), so the
// reference itself scores 0.193 (jitter 0.1, boundary included); the interior
// limit is (3 * 0.2284 + 3 * 0.1314 + 0.2908) / 7 = 0.196 (per cell 3 axis,
// 3 face and 1 body diagonal edges, eps = |1 / (r rho h) - 1| with
// rho h = 0.8141 and r = 1, sqrt 2, sqrt 3). Splits and
// collapses alone (no smoothing: another part of 2.6) are asked to bring the
// stretched mesh back to within 0.01 of the reference's own error at x1.6;
// at x3 they stop at 0.305 (the short edges they leave need ODT smoothing to
// be collapsible), bounded here at 0.32.
struct StretchCase {
  double factor;
  double bound;  // on error_after.mean, absolute; < 0: reference_error + |bound|
};

void PrintTo(const StretchCase& c, std::ostream* os) { *os << "stretch x" << c.factor << ", bound " << c.bound; }

class StretchedCube : public ::testing::TestWithParam<StretchCase> {};

TEST_P(StretchedCube, DensityControlRecoversTheReferenceDensity) {
  const double factor = GetParam().factor;
  DensityControlOptions options;
  const DensityRun run = run_stretched(6, 0.1, factor, options);
  const DensityControlStats& s = run.stats;
  const double after_min_stretch = min_stretch(run.out.points, run.out.tets);
  std::printf("x%.1f: reference eps %.3f, before %.3f (max %.2f), after %.3f (max %.2f); %zu splits, %zu collapses, "
              "refused %zu/%zu, %d rounds%s, %zu tets, min stretch %.3f -> %.3f\n",
              factor, run.reference_error, s.error_before.mean, s.error_before.max, s.error_after.mean,
              s.error_after.max, s.splits, s.collapses, s.refused_splits, s.refused_collapses, s.iterations,
              s.converged ? " (converged)" : "", run.out.tets.size(), run.min_stretch_before, after_min_stretch);
  EXPECT_GT(s.splits, 0u);
  EXPECT_GT(s.collapses, 0u);
  EXPECT_TRUE(s.converged);
  const double bound = GetParam().bound < 0 ? run.reference_error - GetParam().bound : GetParam().bound;
  EXPECT_LE(s.error_after.mean, bound);
  EXPECT_LT(s.error_after.mean, 0.8 * s.error_before.mean);
  expect_valid_box(run.out, factor);
  // The stretch floor: nothing worse than the floor unless the input was.
  EXPECT_GE(after_min_stretch, std::min(options.min_stretch, run.min_stretch_before));

  // Deterministic.
  const DensityRun again = run_stretched(6, 0.1, factor, options);
  EXPECT_EQ(again.out.tets, run.out.tets);
  EXPECT_EQ(again.out.points, run.out.points);
}

INSTANTIATE_TEST_SUITE_P(MeshDensity, StretchedCube,
                         ::testing::Values(StretchCase{1.6, -0.01}, StretchCase{3.0, 0.32}),
                         [](const ::testing::TestParamInfo<StretchCase>& info) {
                           return "x" + std::to_string(static_cast<int>(std::lround(10 * info.param.factor)));
                         });

TEST(MeshDensity, ControlAtTheReferenceChangesLittle) {
  // The undeformed mesh against its own field: the Kuhn edges lie within
  // [beta2, beta1] / rho (ratios 0.81, 1.15, 1.41 inside, a little more at
  // the boundary), so nothing or almost nothing happens.
  DensityControlOptions options;
  const DensityRun run = run_stretched(5, 0.05, 1.0, options);
  std::printf("x1.0: before %.3f, after %.3f; %zu splits, %zu collapses\n", run.stats.error_before.mean,
              run.stats.error_after.mean, run.stats.splits, run.stats.collapses);
  EXPECT_TRUE(run.stats.converged);
  EXPECT_LE(run.stats.splits + run.stats.collapses, 10u);
  EXPECT_LE(run.stats.error_after.mean, run.stats.error_before.mean + 0.01);
  expect_valid_box(run.out, 1.0);
}

TEST(MeshDensity, VertexMaskRestrictsTheControl) {
  const double factor = 2.0;
  // No vertex flagged: nothing changes.
  DensityControlOptions none;
  none.vertex_mask.assign(7 * 7 * 7, 0);
  const DensityRun untouched = run_stretched(6, 0.1, factor, none);
  EXPECT_EQ(untouched.stats.splits + untouched.stats.collapses, 0u);
  EXPECT_EQ(untouched.out.points, untouched.deformed);

  // Left half flagged: every point right of it is an original one (splits
  // and collapses of flagged edges place vertices between flagged ends).
  DensityControlOptions half;
  const DensityRun probe = run_stretched(6, 0.1, factor, DensityControlOptions{});
  half.vertex_mask.assign(probe.deformed.size(), 0);
  for (std::size_t i = 0; i < probe.deformed.size(); ++i) half.vertex_mask[i] = probe.deformed[i].x() <= 0.5 * factor;
  const DensityRun run = run_stretched(6, 0.1, factor, half);
  EXPECT_GT(run.stats.splits, 0u);
  EXPECT_LT(run.stats.splits, probe.stats.splits);
  expect_valid_box(run.out, factor);
  std::size_t right = 0;
  for (const Vec3& p : run.out.points) {
    if (p.x() <= 0.5 * factor) continue;
    ++right;
    EXPECT_NE(std::find(run.deformed.begin(), run.deformed.end(), p), run.deformed.end()) << p.transpose();
  }
  EXPECT_GT(right, 0u);
}

// The split and collapse passes evaluate their candidates in parallel
// batches: the mesh they make must not depend on the number of threads (a
// cube squeezed to half its length, so that thousands of edges are
// collapsed, and one stretched x3, so that thousands are split).
TEST(MeshDensity, SplitsAndCollapsesDoNotDependOnThreadCount) {
  for (const double factor : {0.5, 3.0}) {
    const auto run = [factor] { return run_stretched(12, 0.1, factor, DensityControlOptions{}); };
    const DensityRun one = testing::with_threads(1, run);
    const DensityRun two = testing::with_threads(2, run);
    std::printf("x%.1f: splits %zu / %zu, collapses %zu / %zu, refused %zu / %zu\n", factor, one.stats.splits,
                two.stats.splits, one.stats.collapses, two.stats.collapses, one.stats.refused_collapses,
                two.stats.refused_collapses);
    EXPECT_GT(factor < 1 ? one.stats.collapses : one.stats.splits, 1000u);
    EXPECT_EQ(one.stats.splits, two.stats.splits);
    EXPECT_EQ(one.stats.collapses, two.stats.collapses);
    EXPECT_EQ(one.stats.refused_collapses, two.stats.refused_collapses);
    EXPECT_EQ(one.out.points, two.out.points);
    EXPECT_EQ(one.out.tets, two.out.tets);
    expect_valid_box(two.out, factor);
  }
}

/// A jittered Kuhn cube (n cells, 8 by default) whose part x > from_x is
/// stretched by `factor` along x (from_x = 0: all of it), and the target
/// field that asks for its original densities there.
struct StretchedField {
  TestMesh ref;
  std::vector<Vec3> deformed;
  DensityGrid grid;
};

StretchedField stretched_field(double factor, int n = 8, double jitter = 0.1, std::uint64_t seed = 11,
                               double from_x = 0.0) {
  StretchedField out;
  out.ref = make_cube_mesh(n, jitter, seed);
  const std::vector<double> rho = vertex_density(out.ref.points, out.ref.tets);
  out.deformed = out.ref.points;
  for (Vec3& p : out.deformed)
    if (p.x() > from_x) p.x() = from_x + factor * (p.x() - from_x);
  out.grid.build(out.deformed, out.ref.tets, rho, 0.5 * mean_edge_length(out.ref.points, out.ref.tets));
  return out;
}

/// The deformed cube of `field` as a TetMesh with the cube's face regions.
void build_deformed(const StretchedField& field, TetMesh* mesh) {
  BuildOptions build;
  build.face_regions = field.ref.face_regions;
  ASSERT_TRUE(mesh->build(field.deformed, field.ref.tets, build).ok);
}

TEST(MeshDensity, CollapsePassTakesTheSplitPassScan) {
  // control_mesh_density hands the collapse pass the short edges found by
  // the split pass's scan and around its new vertices; the public passes
  // scan the mesh each. Both must give the same mesh, also when
  // projections move new boundary vertices.
  const double factor = 3.0;
  const Vec3 box(factor, 1, 1);
  const StretchedField field = stretched_field(factor);
  const TestMesh& ref = field.ref;
  const std::vector<Vec3>& deformed = field.deformed;
  const DensityGrid& grid = field.grid;
  ASSERT_FALSE(grid.empty());
  for (const bool bulge : {false, true}) {
    DensityControlOptions options;
    options.max_iterations = 1;
    if (bulge) options.project = [&](index_t, const Vec3& p) { return Vec3(p + 0.01 * (p - 0.5 * box).normalized()); };
    BuildOptions build;
    build.face_regions = ref.face_regions;
    TetMesh together, apart;
    ASSERT_TRUE(together.build(deformed, ref.tets, build).ok);
    ASSERT_TRUE(apart.build(deformed, ref.tets, build).ok);
    const DensityControlStats stats = control_mesh_density(together, grid, options);
    DensityControlStats apart_stats;
    std::vector<char> mask;
    const std::size_t splits = split_long_edges(apart, grid, options, mask, &apart_stats);
    const std::size_t collapses = collapse_short_edges(apart, grid, options, mask, &apart_stats);
    std::printf("x%.0f%s: %zu splits, %zu collapses, %zu projections\n", factor, bulge ? " bulged" : "", stats.splits,
                stats.collapses, stats.projections);
    EXPECT_GT(stats.splits, 1000u);
    EXPECT_GT(stats.collapses, 100u);
    if (bulge) {
      EXPECT_GT(stats.projections, 0u);
    }
    EXPECT_EQ(stats.splits, splits);
    EXPECT_EQ(stats.collapses, collapses);
    EXPECT_EQ(stats.projections, apart_stats.projections);
    const CompactMesh a = together.compact(), b = apart.compact();
    EXPECT_EQ(a.points, b.points);
    EXPECT_EQ(a.tets, b.tets);
  }
}

TEST(MeshDensity, ProjectionCallbackSeesNewBoundaryVertices) {
  // An identity projection is called for new boundary vertices only and
  // changes nothing.
  const double factor = 1.6;
  DensityControlOptions plain;
  const DensityRun reference = run_stretched(4, 0.1, factor, plain);
  DensityControlOptions options;
  std::size_t calls = 0, off_boundary = 0;
  const Vec3 box(factor, 1, 1);
  options.project = [&](index_t, const Vec3& p) {
    ++calls;
    bool on_face = false;
    for (int a = 0; a < 3; ++a) on_face = on_face || p[a] == 0.0 || p[a] == box[a];
    if (!on_face) ++off_boundary;
    return p;
  };
  const DensityRun run = run_stretched(4, 0.1, factor, options);
  EXPECT_GT(calls, 0u);
  EXPECT_EQ(off_boundary, 0u);
  EXPECT_EQ(run.stats.projections, 0u);
  EXPECT_EQ(run.out.points, reference.out.points);
  EXPECT_EQ(run.out.tets, reference.out.tets);

  // A projection that would push vertices out of the box is applied only
  // where the mesh stays valid; the volume changes but the mesh stays valid.
  DensityControlOptions bulge;
  bulge.project = [&](index_t, const Vec3& p) { return Vec3(p + 0.01 * (p - 0.5 * box).normalized()); };
  const DensityRun bulged = run_stretched(4, 0.1, factor, bulge);
  EXPECT_GT(bulged.stats.projections, 0u);
  const ValidityReport report = check_validity(bulged.out.points, bulged.out.tets);
  EXPECT_TRUE(report.ok()) << report.summary();
}

TEST(MeshDensity, PoorRingsAreStillRefined) {
  // A cube stretched x12: its tets start at stretch 0.074, and halving their
  // long edges makes tets a little worse before the collapses tidy up. A
  // floor relative to the whole worst tet replaced (1.0, the collapses'
  // rule) refuses thousands of splits and leaves the error high; at 0.5
  // none is refused.
  DensityControlOptions options;
  ASSERT_EQ(options.split_relative_floor, 0.5);
  DensityControlOptions strict;
  strict.split_relative_floor = 1.0;
  const DensityRun run = run_stretched(6, 0.1, 12.0, options);
  const DensityRun refused = run_stretched(6, 0.1, 12.0, strict);
  const double after = min_stretch(run.out.points, run.out.tets);
  std::printf("x12: before %.3f (min stretch %.3f); relative floor 0.5: after %.3f (min stretch %.3f), %zu splits, "
              "%zu refused; 1.0: after %.3f, %zu splits, %zu refused\n",
              run.stats.error_before.mean, run.min_stretch_before, run.stats.error_after.mean, after, run.stats.splits,
              run.stats.refused_splits, refused.stats.error_after.mean, refused.stats.splits,
              refused.stats.refused_splits);
  EXPECT_TRUE(run.stats.converged);
  EXPECT_EQ(run.stats.refused_splits, 0u);
  EXPECT_GT(refused.stats.refused_splits, 1000u);
  EXPECT_LT(run.stats.error_after.mean, refused.stats.error_after.mean - 0.05);
  EXPECT_LE(run.stats.error_after.mean, 0.37);
  expect_valid_box(run.out, 12.0);
  EXPECT_GE(after, options.split_relative_floor * std::min(options.min_stretch, run.min_stretch_before));
}

// split_in_thirds (beyond the thesis): on a cube stretched x3 along x, the
// axis edges at about 3 / rho become three pieces near the target instead
// of two or four halves; the density error ends lower (0.30 -> 0.20), and
// the mesh is valid, its boundary on the box.
TEST(MeshDensity, SplitInThirdsLowersTheErrorOfAThreefoldStretch) {
  DensityControlOptions halves;
  halves.split_in_thirds = false;
  const DensityRun thirds = run_stretched(8, 0.1, 3.0, DensityControlOptions{});
  const DensityRun halved = run_stretched(8, 0.1, 3.0, halves);
  std::printf("x3: density error %.3f -> %.3f in thirds (%zu splits), %.3f in halves (%zu splits)\n",
              thirds.stats.error_before.mean, thirds.stats.error_after.mean, thirds.stats.splits,
              halved.stats.error_after.mean, halved.stats.splits);
  EXPECT_LT(thirds.stats.error_after.mean, halved.stats.error_after.mean - 0.05);
  expect_valid_box(thirds.out, 3.0);
}

TEST(MeshDensity, OneSplitPassHalvesTwice) {
  // Beyond the thesis, a split pass pushes the halves of the edges it
  // started with back into its heap: on a Kuhn cube stretched x5 (axis edges
  // 4.1 times their target, halves 2.0) one pass leaves far fewer long edges
  // than the thesis' single halving (most of those left are new edges from a
  // midpoint across its ring).
  const TestMesh ref = make_cube_mesh(6, 0.0, 11);
  const std::vector<double> rho = vertex_density(ref.points, ref.tets);
  std::vector<Vec3> deformed = ref.points;
  for (Vec3& p : deformed) p.x() *= 5.0;
  DensityGrid grid;
  ASSERT_TRUE(grid.build(deformed, ref.tets, rho, 0.5 * mean_edge_length(ref.points, ref.tets)));
  const auto long_edges_after_one_pass = [&](bool resplit, std::size_t* splits) {
    TetMesh mesh;
    EXPECT_TRUE(mesh.build(deformed, ref.tets).ok);
    DensityControlOptions options;
    options.resplit_halves = resplit;
    std::vector<char> mask;
    *splits = split_long_edges(mesh, grid, options, mask, nullptr);
    EXPECT_TRUE(mesh.check_consistency().ok);
    const CompactMesh out = mesh.compact();
    const ValidityReport report = check_validity(out.points, out.tets);
    EXPECT_TRUE(report.ok()) << report.summary();
    std::size_t n = 0;
    for (const Edge& e : unique_edges(mesh)) {
      const Vec3 &a = mesh.point(e.first), &b = mesh.point(e.second);
      n += (b - a).norm() * grid.density_at(0.5 * (a + b), DensityLookup::Cell) >= options.split_threshold;
    }
    return n;
  };
  std::size_t splits_twice = 0, splits_once = 0;
  const std::size_t twice = long_edges_after_one_pass(true, &splits_twice);
  const std::size_t once = long_edges_after_one_pass(false, &splits_once);
  std::printf("x5, one split pass: halves split again: %zu splits, %zu long edges left; thesis: %zu splits, %zu left\n",
              splits_twice, twice, splits_once, once);
  EXPECT_GT(splits_twice, 2 * splits_once);
  EXPECT_LT(twice, once * 6 / 10);
}

// Beyond the thesis, a split pass merges a new inner midpoint into an inner
// vertex it made earlier when they are closer than beta2 of the target
// (the midpoints of two split edges of one triangle, in a stretched layer).
// Against the same pass without it: fewer collapses for the same density,
// a valid mesh on the same box, the stretch floor kept.
TEST(MeshDensity, SplitPassMergesNearbyNewMidpoints) {
  for (const double factor : {1.6, 3.0}) {
    DensityControlOptions merging, plain;
    plain.merge_new_midpoints = false;
    const DensityRun with = run_stretched(8, 0.1, factor, merging);
    const DensityRun without = run_stretched(8, 0.1, factor, plain);
    std::printf("x%.1f: merged %zu of %zu splits; collapses %zu (without merging %zu); error %.3f (%.3f); %zu tets "
                "(%zu), min stretch %.3f (%.3f)\n",
                factor, with.stats.merged_midpoints, with.stats.splits, with.stats.collapses, without.stats.collapses,
                with.stats.error_after.mean, without.stats.error_after.mean, with.out.tets.size(),
                without.out.tets.size(), min_stretch(with.out.points, with.out.tets),
                min_stretch(without.out.points, without.out.tets));
    EXPECT_GT(with.stats.merged_midpoints, 0u);
    EXPECT_EQ(without.stats.merged_midpoints, 0u);
    EXPECT_LT(with.stats.collapses, without.stats.collapses);
    EXPECT_LE(with.stats.error_after.mean, without.stats.error_after.mean + 0.01);
    expect_valid_box(with.out, factor);
    EXPECT_GE(min_stretch(with.out.points, with.out.tets), std::min(merging.min_stretch, with.min_stretch_before));
  }
}

// DensityControlOptions::touched marks every vertex whose position or
// neighbours the splits, merges and collapses changed (Improve smooths
// only there in a boundary phase's last loop): on a cube whose half x > 0.5
// is stretched x2 (splits and merges) or squeezed x0.5 (collapses), every
// unmarked vertex has kept its position and its neighbours (read off the
// tets before and after), and the undeformed half keeps a part of its
// vertices unmarked (the jitter gives it a few operations of its own).
TEST(MeshDensity, TouchedMarksEveryVertexAnOperationChanged) {
  const TestMesh ref = make_cube_mesh(8, 0.1, 11);
  const auto neighbours_of = [](const std::vector<Tet>& tets, std::size_t n) {
    std::vector<std::vector<index_t>> nb(n);
    for (const Tet& t : tets)
      for (const index_t a : t)
        for (const index_t b : t)
          if (a != b) nb[static_cast<std::size_t>(a)].push_back(b);
    for (auto& v : nb) {
      std::sort(v.begin(), v.end());
      v.erase(std::unique(v.begin(), v.end()), v.end());
    }
    return nb;
  };
  const std::vector<std::vector<index_t>> before = neighbours_of(ref.tets, ref.points.size());
  for (const double factor : {2.0, 0.5}) {
    const StretchedField field = stretched_field(factor, 8, 0.1, 11, 0.5);
    const std::vector<Vec3>& deformed = field.deformed;
    const DensityGrid& grid = field.grid;
    ASSERT_FALSE(grid.empty());
    TetMesh mesh;
    build_deformed(field, &mesh);
    std::vector<char> touched;
    DensityControlOptions options;
    options.touched = &touched;
    const DensityControlStats stats = control_mesh_density(mesh, grid, options);
    ASSERT_GT(stats.splits + stats.collapses, 0u);
    const CompactMesh out = mesh.compact();
    const std::vector<std::vector<index_t>> after = neighbours_of(out.tets, out.points.size());
    std::vector<index_t> slot_of(out.points.size(), kInvalidIndex);
    for (std::size_t s = 0; s < out.vertex_map.size(); ++s)
      if (out.vertex_map[s] >= 0) slot_of[static_cast<std::size_t>(out.vertex_map[s])] = static_cast<index_t>(s);
    std::size_t unmarked = 0, unmarked_left = 0, left = 0;
    for (std::size_t v = 0; v < ref.points.size(); ++v) {
      left += ref.points[v].x() < 0.4;
      if (v < touched.size() && touched[v]) continue;
      ++unmarked;
      unmarked_left += ref.points[v].x() < 0.4;
      const index_t id = out.vertex_map[v];
      ASSERT_GE(id, 0) << "x" << factor << ": vertex " << v << " removed but not marked";
      EXPECT_EQ(out.points[static_cast<std::size_t>(id)], deformed[v]) << "vertex " << v << " moved, not marked";
      std::vector<index_t> now;
      for (const index_t w : after[static_cast<std::size_t>(id)]) now.push_back(slot_of[static_cast<std::size_t>(w)]);
      std::sort(now.begin(), now.end());
      EXPECT_EQ(now, before[v]) << "x" << factor << ": vertex " << v << " has other neighbours, not marked";
    }
    std::printf("x%.1f: %zu splits, %zu merges, %zu collapses; %zu of %zu original vertices unmarked (%zu of %zu "
                "with x < 0.4)\n",
                factor, stats.splits, stats.merged_midpoints, stats.collapses, unmarked, ref.points.size(),
                unmarked_left, left);
    EXPECT_GT(unmarked_left, left / 10);
    EXPECT_LT(unmarked, ref.points.size());
  }
}

// relax_edge_lengths (beyond the thesis) pulls the inner vertices' edges
// toward 1 / rho_GC after the density control of a jittered cube stretched
// x2 along x: the density error (Eq. 2.35) drops, the mesh stays valid with
// its boundary where it was, the topology is kept and the worst tet is no
// worse than min(before, 0.35), as the guard promises.
TEST(MeshDensity, RelaxEdgeLengthsLowersTheDensityError) {
  const StretchedField field = stretched_field(2.0, 10, 0.2, 5);
  const DensityGrid& grid = field.grid;
  ASSERT_FALSE(grid.empty());
  TetMesh mesh;
  build_deformed(field, &mesh);
  control_mesh_density(mesh, grid, DensityControlOptions{});
  const CompactMesh before = mesh.compact();
  const double error_before = mean_density_error(before.points, before.tets, grid, DensityLookup::Cell).mean;
  const double min_before = min_stretch(before.points, before.tets);
  const OdtSmoothReport report = relax_edge_lengths(mesh, grid, RelaxEdgeLengthsOptions{});
  const CompactMesh after = mesh.compact();
  const double error_after = mean_density_error(after.points, after.tets, grid, DensityLookup::Cell).mean;
  const double min_after = min_stretch(after.points, after.tets);
  std::printf("moved %zu; density error %.4f -> %.4f, min stretch %.3f -> %.3f, mean %.3f -> %.3f\n", report.moved,
              error_before, error_after, min_before, min_after, mean_stretch(before.points, before.tets),
              mean_stretch(after.points, after.tets));
  EXPECT_GT(report.moved, 0u);
  EXPECT_LT(error_after, 0.95 * error_before);
  EXPECT_GE(min_after, std::min(min_before, 0.35) - 1e-12);
  ASSERT_EQ(after.tets, before.tets);
  expect_valid_box(after, 2.0);
  for (std::size_t v = 0; v < after.points.size(); ++v) {
    if (after.vertex_classes[v] != VertexClass::Inner) {
      EXPECT_EQ(after.points[v], before.points[v]) << v;
    }
  }
}

// relax_surface_edge_lengths (beyond the thesis) moves the surface vertices
// of a jittered cube along its six planes toward their springs' rest
// position under a field that asks for edges 2.3x shorter at x = 1 than at
// x = 0: the density error of the surface edges drops, and by more than the
// surface ODT smoothing (Eq. 2.34, blind to the field) lowers it; every
// surface vertex stays on its plane, the others stay where they are, the
// topology and the volume are kept, and the worst tet is no worse than
// min(before, 0.35), as the guard promises.
TEST(MeshDensity, RelaxSurfaceEdgeLengthsFollowsTheFieldOnTheSurface) {
  const TestMesh ref = make_cube_mesh(10, 0.2, 5);
  std::vector<double> rho = vertex_density(ref.points, ref.tets);
  for (std::size_t v = 0; v < rho.size(); ++v) rho[v] *= 0.6 + 0.8 * ref.points[v].x();
  DensityGrid grid;
  grid.build(ref.points, ref.tets, rho, 0.5 * mean_edge_length(ref.points, ref.tets));
  BuildOptions build;
  build.face_regions = ref.face_regions;
  TetMesh mesh;
  ASSERT_TRUE(mesh.build(ref.points, ref.tets, build).ok);
  BoundaryGeometry geometry;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      geometry.regions.push_back(test_surfaces::plane(side * Vec3::Unit(axis), Vec3::Unit(axis)));
  // Eq. 2.35 over the edges with both ends on the boundary.
  const auto surface_error = [&grid](const CompactMesh& m) {
    double sum = 0;
    std::size_t n = 0;
    for (const Edge& e : unique_edges(m.tets, static_cast<index_t>(m.points.size()))) {
      if (m.vertex_classes[e.first] == VertexClass::Inner || m.vertex_classes[e.second] == VertexClass::Inner) continue;
      const Vec3 &a = m.points[e.first], &b = m.points[e.second];
      const double r = grid.density_at(0.5 * (a + b), DensityLookup::Cell);
      sum += std::abs(1 / (a - b).norm() - r) / r;
      ++n;
    }
    return sum / static_cast<double>(n);
  };
  const CompactMesh before = mesh.compact();
  const double error_before = surface_error(before), min_before = min_stretch(before.points, before.tets);
  RelaxEdgeLengthsOptions options;
  options.iterations = 5;
  TetMesh odt = mesh;
  BoundarySmoothOptions bso;
  bso.iterations = options.iterations;
  odt_smooth_surface(odt, geometry, bso);
  const double error_odt = surface_error(odt.compact());
  const OdtSmoothReport report = relax_surface_edge_lengths(mesh, geometry, grid, options);
  const CompactMesh after = mesh.compact();
  const double error_after = surface_error(after), min_after = min_stretch(after.points, after.tets);
  std::printf("moved %zu; surface density error %.4f -> %.4f (surface ODT: %.4f), min stretch %.3f -> %.3f\n",
              report.moved, error_before, error_after, error_odt, min_before, min_after);
  EXPECT_GT(report.moved, 0u);
  EXPECT_LT(error_after, 0.95 * error_before);
  EXPECT_LT(error_after, 0.97 * error_odt);
  EXPECT_GE(min_after, std::min(min_before, 0.35) - 1e-12);
  ASSERT_EQ(after.tets, before.tets);
  const ValidityReport validity = check_validity(after.points, after.tets);
  EXPECT_TRUE(validity.ok()) << validity.summary();
  EXPECT_NEAR(total_volume(after.points, after.tets), 1.0, 1e-12);
  for (std::size_t t = 0; t < after.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      const index_t region = after.face_regions[t][f];
      if (region < 0) continue;
      for (int q = 0; q < 3; ++q) EXPECT_NEAR(after.points[after.tets[t][kTetFace[f][q]]][region / 2], region % 2, 1e-12);
    }
  std::size_t surface_moved = 0;
  for (std::size_t v = 0; v < after.points.size(); ++v) {
    if (after.vertex_classes[v] != VertexClass::Surface) {
      EXPECT_EQ(after.points[v], before.points[v]) << v;
    } else {
      surface_moved += after.points[v] != before.points[v];
    }
  }
  EXPECT_GT(surface_moved, 0u);
}

// The collapse pass takes a heap entry as current, without a density
// lookup, when neither end has moved since it was queued (a clock per pass).
// A length compare would not do: repeated halving makes equal, parallel
// edges, and two vertices can move by bit-identical vectors. The check looks
// every such entry up anyway: none may have become long or changed length.
TEST(MeshDensity, CollapseQueueTakesOnlyCurrentEntriesWithoutLookup) {
  for (const double factor : {0.5, 3.0}) {
    DensityControlOptions options;
    options.check_queue = true;
    const DensityRun run = run_stretched(10, 0.1, factor, options);
    std::printf("x%.1f: %zu collapses, %zu entries taken without lookup, %zu disagree\n", factor,
                run.stats.collapses, run.stats.queue_checked, run.stats.queue_disagreements);
    EXPECT_GT(run.stats.collapses, 500u);
    EXPECT_GT(run.stats.queue_checked, run.stats.collapses / 2);
    EXPECT_EQ(run.stats.queue_disagreements, 0u);
    // The check only looks: the same mesh as without it.
    const DensityRun plain = run_stretched(10, 0.1, factor, DensityControlOptions{});
    EXPECT_EQ(plain.out.points, run.out.points);
    EXPECT_EQ(plain.out.tets, run.out.tets);
  }
}

// A projection callback that may run in parallel is called in the collapse
// pass's parallel evaluation instead of in a second, serial evaluation at
// the commit: the same mesh either way (a cube stretched x3 whose new
// boundary vertices are pushed off their planes, so that boundary collapses
// move their kept vertex and are projected).
TEST(MeshDensity, ProjectionInParallelGivesTheSameMesh) {
  const double factor = 3.0;
  const Vec3 box(factor, 1, 1);
  const StretchedField field = stretched_field(factor);
  const TestMesh& ref = field.ref;
  const std::vector<Vec3>& deformed = field.deformed;
  const DensityGrid& grid = field.grid;
  ASSERT_FALSE(grid.empty());
  CompactMesh meshes[2];
  DensityControlStats stats[2];
  std::atomic<int> in_parallel[2] = {0, 0};
  for (const bool parallel : {false, true}) {
    DensityControlOptions options;
    options.project = [&](index_t, const Vec3& p) {
      if (femorph::in_parallel()) ++in_parallel[parallel];
      return Vec3(p + 0.01 * (p - 0.5 * box).normalized());
    };
    options.project_in_parallel = parallel;
    BuildOptions build;
    build.face_regions = ref.face_regions;
    TetMesh mesh;
    ASSERT_TRUE(mesh.build(deformed, ref.tets, build).ok);
    stats[parallel] = testing::with_threads(2, [&] { return control_mesh_density(mesh, grid, options); });
    EXPECT_TRUE(mesh.check_consistency().ok);
    meshes[parallel] = mesh.compact();
  }
  std::printf("%zu collapses, %zu projections, %d callback calls in a parallel region\n", stats[1].collapses,
              stats[1].projections, in_parallel[1].load());
  EXPECT_GT(stats[1].collapses, 100u);
  EXPECT_EQ(in_parallel[0], 0);
  EXPECT_GT(in_parallel[1], 0);  // projected in the parallel evaluation
  EXPECT_EQ(stats[0].projections, stats[1].projections);
  EXPECT_EQ(meshes[0].points, meshes[1].points);
  EXPECT_EQ(meshes[0].tets, meshes[1].tets);
}

// EdgeQueue (the scan's edges sorted once plus a heap for later pushes) must
// pop in the order of one std::priority_queue of all entries, with pushes
// between pops and many equal lengths (ties broken by the ends).
template <class Lower>
void expect_pops_as_one_heap(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> length(0, 12), end(0, 40), action(0, 2);
  const auto random_edge = [&] {
    const index_t a = end(rng), b = end(rng);
    return HeapEdge{0.125 * length(rng), std::min(a, b), std::max(a, b)};
  };
  std::vector<HeapEdge> scanned(400);
  for (HeapEdge& e : scanned) e = random_edge();
  EdgeQueue<Lower> queue(scanned);
  std::priority_queue<HeapEdge, std::vector<HeapEdge>, Lower> one_heap(Lower(), scanned);
  std::size_t pops = 0, pushes = 0;
  while (!one_heap.empty()) {
    ASSERT_FALSE(queue.empty());
    if (action(rng) == 0 && pushes < 600) {
      const HeapEdge e = random_edge();
      queue.push(e);
      one_heap.push(e);
      ++pushes;
      continue;
    }
    const HeapEdge x = queue.pop(), y = one_heap.top();
    one_heap.pop();
    ASSERT_EQ(x.length, y.length) << "pop " << pops;
    ASSERT_EQ(x.a, y.a) << "pop " << pops;
    ASSERT_EQ(x.b, y.b) << "pop " << pops;
    ++pops;
  }
  EXPECT_TRUE(queue.empty());
  EXPECT_EQ(pops, scanned.size() + pushes);
  EXPECT_GT(pushes, 100u);
}

TEST(EdgeQueue, PopsInTheOrderOfOneHeap) {
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    expect_pops_as_one_heap<Longer>(seed);
    expect_pops_as_one_heap<Shorter>(seed);
  }
}

}  // namespace
}  // namespace femorph
