// Tet To Hex (thesis 4.5): structured hex blocks decomposed by the tables of
// Fig. 4.5 come back as the same hexahedra; every triangulation of a hex,
// wedge and pyramid is recognised; the quad angle (delta_angle) and the
// minimum scaled Jacobian act as in Table 4.3; non-conformal interfaces are
// counted and refused on demand; bad input fails with a message.
#include "hex/hex_decomposition_types.h"
#include "hex/tet_to_hex.h"
#include "hex/tet_to_hex_internal.h"
#include "quality/tet_quality.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <vector>

namespace femorph {
namespace {

struct HexGrid {
  int nx = 0, ny = 0, nz = 0;
  std::vector<Vec3> points;
  std::vector<std::array<index_t, 8>> hexes;  // VTK order
};

/// nx x ny x nz boxes of size 1 x 0.75 x 1.25.
HexGrid make_grid(int nx, int ny, int nz) {
  HexGrid g{ nx, ny, nz, {}, {} };
  auto id = [&](int i, int j, int k) { return static_cast<index_t>((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) g.points.emplace_back(1.0 * i, 0.75 * j, 1.25 * k);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        g.hexes.push_back({ id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                            id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1) });
  return g;
}

/// Each hex split by the local tets `choose(h)` (over its VTK node ids).
std::vector<Tet> decompose(const HexGrid& g, const std::function<const std::vector<LocalTet>&(std::size_t)>& choose) {
  std::vector<Tet> tets;
  for (std::size_t h = 0; h < g.hexes.size(); ++h)
    for (const LocalTet& t : choose(h))
      tets.push_back({ g.hexes[h][t[0]], g.hexes[h][t[1]], g.hexes[h][t[2]], g.hexes[h][t[3]] });
  return tets;
}

std::vector<Tet> decompose(const HexGrid& g, HexDecompositionType type, bool mirrored) {
  const HexDecomposition& d = hex_decomposition(type, mirrored);
  return decompose(g, [&d](std::size_t) -> const std::vector<LocalTet>& { return d.tets; });
}

/// Conforming: every face is matched except the 2 triangles of each quad of the block's boundary.
bool conforming(const HexGrid& g, const std::vector<Tet>& tets) {
  std::vector<index_t> adjacency;
  if (!tet_to_hex::build_tet_adjacency(static_cast<index_t>(g.points.size()), tets, adjacency)) return false;
  const long boundary = std::count(adjacency.begin(), adjacency.end(), kInvalidIndex);
  return boundary == 4L * (g.nx * g.ny + g.ny * g.nz + g.nx * g.nz);
}

double tets_volume(const std::vector<Vec3>& p, const std::vector<Tet>& tets) {
  double v = 0;
  for (const Tet& t : tets) v += tet_signed_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
  return v;
}

/// Volume of an output cell from its nodes (exact for planar faces), by a
/// decomposition table of its kind.
double cell_volume(const std::vector<Vec3>& p, CellKind kind, const index_t* n) {
  std::vector<LocalTet> local;
  switch (kind) {
    case CellKind::Tetra: local = { LocalTet{ 0, 1, 2, 3 } }; break;
    case CellKind::Pyramid: {
      const auto t = pyramid_decomposition(0);
      local.assign(t.begin(), t.end());
      break;
    }
    case CellKind::Wedge: {
      std::array<LocalTet, 3> t;
      for (int d = 0; d < 8 && local.empty(); ++d)
        if (wedge_decomposition(static_cast<std::uint8_t>(d), t)) local.assign(t.begin(), t.end());
      break;
    }
    case CellKind::Hexahedron: local = hex_decomposition(HexDecompositionType::C, false).tets; break;
  }
  double v = 0;
  for (const LocalTet& t : local) v += tet_signed_volume(p[n[t[0]]], p[n[t[1]]], p[n[t[2]]], p[n[t[3]]]);
  return v;
}

/// Checks shared by every run: each input tet in exactly one output cell,
/// cells of positive volume (node orders), the Jacobians and stats agree.
void expect_consistent(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                       const TetToHexParams& params, const TetToHexResult& r) {
  const MixedCells& cells = r.cells;
  ASSERT_EQ(r.source_offsets.size(), static_cast<std::size_t>(cells.size()) + 1);
  ASSERT_EQ(r.min_scaled_jacobian.size(), static_cast<std::size_t>(cells.size()));
  std::vector<int> used(tets.size(), 0);
  for (index_t t : r.source_tets) ++used[t];
  EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](int u) { return u == 1; }))
      << "every input tet in exactly one output cell";
  std::array<std::size_t, 4> count{};
  for (index_t c = 0; c < cells.size(); ++c) {
    const CellKind kind = cells.kinds[c];
    ++count[static_cast<int>(kind)];
    ASSERT_EQ(cells.node_count(c), cell_node_count(kind));
    Vec3 corners[8];
    for (int k = 0; k < cell_node_count(kind); ++k) corners[k] = points[cells.nodes(c)[k]];
    EXPECT_EQ(r.min_scaled_jacobian[c], min_scaled_jacobian(kind, corners));
    EXPECT_GT(r.min_scaled_jacobian[c], 0) << "cell " << c;
    if (kind != CellKind::Tetra) {
      EXPECT_GE(r.min_scaled_jacobian[c], params.min_scaled_jacobian) << "cell " << c;
    }
    // The cell's nodes are its source tets' vertices.
    std::set<index_t> nodes(cells.nodes(c), cells.nodes(c) + cells.node_count(c)), vertices;
    for (index_t s = r.source_offsets[c]; s < r.source_offsets[c + 1]; ++s)
      vertices.insert(tets[r.source_tets[s]].begin(), tets[r.source_tets[s]].end());
    EXPECT_EQ(nodes, vertices) << "cell " << c;
    const int expected_sources = kind == CellKind::Tetra ? 1 : kind == CellKind::Pyramid ? 2 : kind == CellKind::Wedge ? 3 : 0;
    const index_t sources = r.source_offsets[c + 1] - r.source_offsets[c];
    if (expected_sources)
      EXPECT_EQ(sources, expected_sources);
    else
      EXPECT_TRUE(sources == 5 || sources == 6);
    EXPECT_GT(cell_volume(points, kind, cells.nodes(c)), 0) << "cell " << c;
  }
  EXPECT_EQ(count, r.stats.cells);
  EXPECT_NEAR(r.stats.total_volume, tets_volume(points, tets), 1e-9 * std::abs(r.stats.total_volume));
  double by_kind = 0;
  for (double v : r.stats.volume) by_kind += v;
  EXPECT_NEAR(by_kind, r.stats.total_volume, 1e-9 * std::abs(r.stats.total_volume));
  // Hexahedra first, then wedges, pyramids, tets.
  auto rank = [](CellKind k) { return k == CellKind::Hexahedron ? 0 : k == CellKind::Wedge ? 1 : k == CellKind::Pyramid ? 2 : 3; };
  EXPECT_TRUE(std::is_sorted(cells.kinds.begin(), cells.kinds.end(),
                             [&](CellKind a, CellKind b) { return rank(a) < rank(b); }));
}

/// A block decomposed into tets comes back as its hexahedra, exactly.
void expect_all_hexes(const HexGrid& g, const std::vector<Tet>& tets) {
  ASSERT_TRUE(conforming(g, tets));
  TetToHexParams params;
  TetToHexResult r;
  const Status s = recombine_tetrahedra(g.points, tets, params, r);
  ASSERT_TRUE(s) << s.message;
  expect_consistent(g.points, tets, params, r);
  ASSERT_EQ(r.cells.size(), static_cast<index_t>(g.hexes.size()));
  EXPECT_EQ(r.stats.cells[static_cast<int>(CellKind::Hexahedron)], g.hexes.size());
  double volume = 0;
  for (index_t c = 0; c < r.cells.size(); ++c) {
    ASSERT_EQ(r.cells.kinds[c], CellKind::Hexahedron);
    EXPECT_NEAR(r.min_scaled_jacobian[c], 1.0, 1e-12);
    volume += cell_volume(g.points, CellKind::Hexahedron, r.cells.nodes(c));
    // One of the grid's boxes.
    std::set<index_t> nodes(r.cells.nodes(c), r.cells.nodes(c) + 8);
    bool found = false;
    for (const auto& h : g.hexes) found = found || nodes == std::set<index_t>(h.begin(), h.end());
    EXPECT_TRUE(found) << "cell " << c << " is not a box of the grid";
  }
  const double expected = 1.0 * g.nx * 0.75 * g.ny * 1.25 * g.nz;
  EXPECT_NEAR(volume, expected, 1e-9 * expected);
  EXPECT_NEAR(r.stats.volume[static_cast<int>(CellKind::Hexahedron)], expected, 1e-9 * expected);
  EXPECT_EQ(r.stats.nonconformal_interfaces, 0u);
}

// Thesis Fig. 4.13: 60 hexahedra, 132 vertices (10 x 2 x 3), Type C+ -> 360 tets.
TEST(TetToHex, Figure413BlockTypeCPlus) {
  const HexGrid g = make_grid(10, 2, 3);
  ASSERT_EQ(g.points.size(), 132u);
  const std::vector<Tet> tets = decompose(g, HexDecompositionType::C, false);
  ASSERT_EQ(tets.size(), 360u);
  expect_all_hexes(g, tets);
}

// The other types that conform on a structured grid when every hex takes
// the same one.
TEST(TetToHex, BlockOtherConformingTypes) {
  const HexGrid g = make_grid(5, 4, 3);
  const std::pair<HexDecompositionType, bool> types[] = {
    { HexDecompositionType::C, true }, { HexDecompositionType::E, false }, { HexDecompositionType::E, true } };
  for (const auto& type : types) {
    SCOPED_TRACE(std::string(to_string(type.first)) + (type.second ? "-" : "+"));
    expect_all_hexes(g, decompose(g, type.first, type.second));
  }
}

// A mix of types in many orientations: each quad split along its diagonal
// through its vertex of smallest (random) rank, which conforms, and each
// hex takes one of the triangulations realising its diagonals.
TEST(TetToHex, BlockMixedTypes) {
  const HexGrid g = make_grid(5, 4, 3);
  std::vector<index_t> rank(g.points.size());
  std::iota(rank.begin(), rank.end(), 0);
  std::shuffle(rank.begin(), rank.end(), std::mt19937(5));
  std::set<int> types;
  const std::vector<Tet> tets = decompose(g, [&](std::size_t h) -> const std::vector<LocalTet>& {
    std::uint8_t bits = 0;
    for (int f = 0; f < 6; ++f) {
      index_t smallest = std::numeric_limits<index_t>::max();
      int at = 0;
      for (int k = 0; k < 4; ++k)
        if (rank[g.hexes[h][kHexFaces[f][k]]] < smallest) {
          smallest = rank[g.hexes[h][kHexFaces[f][k]]];
          at = k;
        }
      if (at % 2) bits = static_cast<std::uint8_t>(bits | (1u << f));
    }
    const auto list = hex_decompositions_with_diagonals(bits);
    const HexDecomposition* d = list[(h * 7) % list.size()];
    types.insert(static_cast<int>(d->type));
    return d->tets;
  });
  EXPECT_GE(types.size(), 3u);
  expect_all_hexes(g, tets);
}

// Every triangulation of a hexahedron without new vertices (74, all six
// types in every orientation), of a wedge (6) and of a pyramid (2) is
// recognised on a single cell.
TEST(TetToHex, EveryTriangulationOfOneCell) {
  const HexGrid g = make_grid(1, 1, 1);
  for (const HexDecomposition& d : all_hex_decompositions()) {
    SCOPED_TRACE(std::string(to_string(d.type)) + (d.mirrored ? "-" : "+"));
    const std::vector<Tet> tets = decompose(g, [&d](std::size_t) -> const std::vector<LocalTet>& { return d.tets; });
    TetToHexResult r;
    ASSERT_TRUE(recombine_tetrahedra(g.points, tets, TetToHexParams(), r));
    ASSERT_EQ(r.cells.size(), 1);
    EXPECT_EQ(r.cells.kinds[0], CellKind::Hexahedron);
    EXPECT_NEAR(r.min_scaled_jacobian[0], 1.0, 1e-12);
    EXPECT_EQ(r.stats.candidates[static_cast<int>(CellKind::Hexahedron)], 1u);
  }

  // Wedges: every valid diagonal pattern, with shuffled point ids.
  const std::vector<Vec3> wedge = { Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0),
                                    Vec3(0, 0, 2), Vec3(0, 1, 2), Vec3(1, 0, 2) };
  Vec3 reference[6];
  std::copy(wedge.begin(), wedge.end(), reference);
  const double wedge_sj = min_scaled_jacobian(CellKind::Wedge, reference);
  int patterns = 0;
  std::mt19937 rng(7);
  for (int d = 0; d < 8; ++d) {
    std::array<LocalTet, 3> local;
    if (!wedge_decomposition(static_cast<std::uint8_t>(d), local)) continue;
    ++patterns;
    std::vector<index_t> perm(6);
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<Vec3> points(6);
    for (int i = 0; i < 6; ++i) points[perm[i]] = wedge[i];
    std::vector<Tet> tets;
    for (const LocalTet& t : local) tets.push_back({ perm[t[0]], perm[t[1]], perm[t[2]], perm[t[3]] });
    TetToHexResult r;
    TetToHexParams params;
    ASSERT_TRUE(recombine_tetrahedra(points, tets, params, r));
    expect_consistent(points, tets, params, r);
    ASSERT_EQ(r.cells.size(), 1) << "pattern " << d;
    EXPECT_EQ(r.cells.kinds[0], CellKind::Wedge);
    EXPECT_NEAR(r.min_scaled_jacobian[0], wedge_sj, 1e-12);
    EXPECT_NEAR(cell_volume(points, CellKind::Wedge, r.cells.nodes(0)), 1.0, 1e-12);
  }
  EXPECT_EQ(patterns, 6);

  // Pyramids: both diagonals of the base; with pyramids off, two tets.
  const std::vector<Vec3> pyramid = { Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0), Vec3(1, 1, 1.5) };
  for (int diagonal = 0; diagonal < 2; ++diagonal) {
    std::vector<Tet> tets;
    for (const LocalTet& t : pyramid_decomposition(diagonal)) tets.push_back({ t[0], t[1], t[2], t[3] });
    TetToHexParams params;
    TetToHexResult r;
    ASSERT_TRUE(recombine_tetrahedra(pyramid, tets, params, r));
    expect_consistent(pyramid, tets, params, r);
    ASSERT_EQ(r.cells.size(), 1);
    EXPECT_EQ(r.cells.kinds[0], CellKind::Pyramid);
    EXPECT_NEAR(cell_volume(pyramid, CellKind::Pyramid, r.cells.nodes(0)), 2.0, 1e-12);
    params.pyramids = false;
    ASSERT_TRUE(recombine_tetrahedra(pyramid, tets, params, r));
    EXPECT_EQ(r.cells.size(), 2);
    EXPECT_EQ(r.stats.cells[static_cast<int>(CellKind::Tetra)], 2u);
  }
}

// The search trees come from the tables: the "-" variants of Fig. 4.5 are
// rotations of the "+" ones, so six hexahedron classes remain.
TEST(TetToHex, SearchTreesCoverTheSixTypes) {
  std::set<int> hex_types;
  for (const tet_to_hex::SearchTree& tree : tet_to_hex::search_trees()) {
    EXPECT_FALSE(tree.assignments.empty());
    EXPECT_LE(tree.assignments.size(), 12u);
    if (tree.kind == CellKind::Hexahedron) hex_types.insert(tree.decomposition);
  }
  EXPECT_EQ(hex_types, (std::set<int>{ 0, 1, 2, 3, 4, 5 }));
}

// Prisms and pyramids only: a C+ block gives no hexahedra; all off: tets.
TEST(TetToHex, KindsCanBeTurnedOff) {
  const HexGrid g = make_grid(3, 2, 2);
  const std::vector<Tet> tets = decompose(g, HexDecompositionType::C, false);
  TetToHexParams params;
  params.hexahedra = false;
  TetToHexResult r;
  ASSERT_TRUE(recombine_tetrahedra(g.points, tets, params, r));
  expect_consistent(g.points, tets, params, r);
  EXPECT_EQ(r.stats.cells[static_cast<int>(CellKind::Hexahedron)], 0u);
  EXPECT_EQ(r.stats.candidates[static_cast<int>(CellKind::Hexahedron)], 0u);
  EXPECT_EQ(r.stats.cells[static_cast<int>(CellKind::Wedge)], 2 * g.hexes.size());  // each box halved
  params.prisms = false;
  params.pyramids = false;
  ASSERT_TRUE(recombine_tetrahedra(g.points, tets, params, r));
  EXPECT_EQ(r.cells.size(), static_cast<index_t>(tets.size()));
  for (index_t c = 0; c < r.cells.size(); ++c) {
    EXPECT_EQ(r.cells.kinds[c], CellKind::Tetra);
    EXPECT_EQ(r.source_tets[c], c);  // the tets left keep their order
    EXPECT_TRUE(std::equal(r.cells.nodes(c), r.cells.nodes(c) + 4, tets[c].begin()));
  }
}

/// A 6 x 6 x 4 block, C+, whose interior vertices with i >= 3 move by up
/// to `amount` of the spacing (seeded): the boxes i < 2 stay boxes.
struct Deformed {
  HexGrid grid;
  std::vector<Tet> tets;
};

Deformed make_deformed(double amount, std::uint64_t seed) {
  Deformed d{ make_grid(6, 6, 4), {} };
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  HexGrid& g = d.grid;
  for (int k = 1; k < g.nz; ++k)
    for (int j = 1; j < g.ny; ++j)
      for (int i = 3; i < g.nx; ++i) {
        Vec3& p = g.points[(k * (g.ny + 1) + j) * (g.nx + 1) + i];
        p += amount * Vec3(u(rng) * 1.0, u(rng) * 0.75, u(rng) * 1.25);
      }
  d.tets = decompose(g, HexDecompositionType::C, false);
  return d;
}

// Table 4.3: the tighter the quad angle, the fewer hexahedra (the boxes
// away from the moved vertices stay, as the thesis' 24). No cell below the
// minimum scaled Jacobian, none inverted.
TEST(TetToHex, QuadAngleTradesHexahedraLikeTable43) {
  const Deformed d = make_deformed(0.3, 3);
  const double angles[] = { 90, 60, 45, 30, 20, 10, 5, 0 };
  std::vector<double> ratio;
  std::vector<std::size_t> hexes;
  for (double angle : angles) {
    SCOPED_TRACE(angle);
    TetToHexParams params;
    params.quad_angle_deg = angle;
    TetToHexResult r;
    ASSERT_TRUE(recombine_tetrahedra(d.grid.points, d.tets, params, r));
    expect_consistent(d.grid.points, d.tets, params, r);
    ratio.push_back(r.stats.volume[static_cast<int>(CellKind::Hexahedron)] / r.stats.total_volume);
    hexes.push_back(r.stats.cells[static_cast<int>(CellKind::Hexahedron)]);
  }
  for (std::size_t i = 1; i < ratio.size(); ++i) {
    EXPECT_LE(ratio[i], ratio[i - 1] + 1e-12) << angles[i] << " degrees";
    EXPECT_LE(hexes[i], hexes[i - 1]) << angles[i] << " degrees";
  }
  EXPECT_GT(ratio.front(), ratio.back() + 0.2);
  EXPECT_EQ(hexes.back(), 2u * 6 * 4);  // the boxes i < 2: their vertices did not move
  EXPECT_LT(hexes.back(), hexes.front());

  // A higher minimum scaled Jacobian refuses more candidates.
  TetToHexParams strict;
  strict.quad_angle_deg = 90;
  strict.min_scaled_jacobian = 0.8;
  TetToHexResult r;
  ASSERT_TRUE(recombine_tetrahedra(d.grid.points, d.tets, strict, r));
  expect_consistent(d.grid.points, d.tets, strict, r);
  EXPECT_LT(r.stats.cells[static_cast<int>(CellKind::Hexahedron)], hexes.front());
  for (int k = 1; k < 4; ++k) EXPECT_LE(r.stats.admissible[k], r.stats.candidates[k]);
}

// Two runs give the same cells; the mesh is large enough for the parallel
// search (kParallelMinItems tets). No two candidates share their tets.
TEST(TetToHex, DeterministicAndCandidatesUnique) {
  HexGrid g = make_grid(12, 12, 12);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  for (int k = 1; k < g.nz; ++k)
    for (int j = 1; j < g.ny; ++j)
      for (int i = 1; i < g.nx; ++i) g.points[(k * (g.ny + 1) + j) * (g.nx + 1) + i] += Vec3(u(rng), u(rng), u(rng));
  const std::vector<Tet> tets = decompose(g, HexDecompositionType::C, false);
  ASSERT_GE(static_cast<long>(tets.size()), kParallelMinItems);
  TetToHexParams params;
  TetToHexResult a, b;
  ASSERT_TRUE(recombine_tetrahedra(g.points, tets, params, a));
  ASSERT_TRUE(recombine_tetrahedra(g.points, tets, params, b));
  expect_consistent(g.points, tets, params, a);
  EXPECT_EQ(a.cells.kinds, b.cells.kinds);
  EXPECT_EQ(a.cells.connectivity, b.cells.connectivity);
  EXPECT_EQ(a.source_tets, b.source_tets);
  EXPECT_EQ(a.min_scaled_jacobian, b.min_scaled_jacobian);
  EXPECT_EQ(a.stats.candidates, b.stats.candidates);
  EXPECT_GT(a.stats.cells[static_cast<int>(CellKind::Hexahedron)], g.hexes.size() * 6 / 10);

  std::vector<index_t> adjacency;
  ASSERT_TRUE(tet_to_hex::build_tet_adjacency(static_cast<index_t>(g.points.size()), tets, adjacency));
  std::vector<tet_to_hex::Candidate> candidates;
  TetToHexStats stats;
  tet_to_hex::search_candidates(g.points, tets, adjacency, params, candidates, stats);
  std::set<std::vector<index_t>> seen;
  for (const auto& c : candidates)
    EXPECT_TRUE(seen.insert(std::vector<index_t>(c.tets.begin(), c.tets.begin() + c.num_tets)).second);
  tet_to_hex::sort_candidates(candidates);
  for (std::size_t i = 1; i < candidates.size(); ++i) ASSERT_GE(candidates[i - 1].priority, candidates[i].priority);
}

// Two boxes; the right one's far corner is pulled out, so only the left
// one is a hexahedron: with prisms and pyramids off its quad on the right
// meets two tets, one non-conformal interface. Refusing it dissolves it.
TEST(TetToHex, NonConformalInterfaceCountedAndRefused) {
  HexGrid g = make_grid(2, 1, 1);
  g.points[(1 * 2 + 1) * 3 + 2] += Vec3(0.4, 0.3, 0.5);  // node (2, 1, 1)
  const std::vector<Tet> tets = decompose(g, HexDecompositionType::C, false);
  TetToHexParams params;
  params.prisms = false;
  params.pyramids = false;
  TetToHexResult r;
  ASSERT_TRUE(recombine_tetrahedra(g.points, tets, params, r));
  expect_consistent(g.points, tets, params, r);
  EXPECT_EQ(r.stats.cells[static_cast<int>(CellKind::Hexahedron)], 1u);
  EXPECT_EQ(r.stats.cells[static_cast<int>(CellKind::Tetra)], 6u);
  EXPECT_EQ(r.stats.nonconformal_interfaces, 1u);
  EXPECT_EQ(r.stats.dissolved_nonconformal, 0u);

  params.refuse_nonconformal = true;
  ASSERT_TRUE(recombine_tetrahedra(g.points, tets, params, r));
  expect_consistent(g.points, tets, params, r);
  EXPECT_EQ(r.stats.nonconformal_interfaces, 0u);
  EXPECT_EQ(r.stats.dissolved_nonconformal, 1u);
  EXPECT_EQ(r.stats.cells[static_cast<int>(CellKind::Tetra)], 12u);

  // With pyramids, one caps the quad instead: the hexahedron stays.
  params.pyramids = true;
  ASSERT_TRUE(recombine_tetrahedra(g.points, tets, params, r));
  expect_consistent(g.points, tets, params, r);
  EXPECT_EQ(r.stats.nonconformal_interfaces, 0u);
  EXPECT_EQ(r.stats.cells[static_cast<int>(CellKind::Hexahedron)], 1u);
  EXPECT_GE(r.stats.cells[static_cast<int>(CellKind::Pyramid)], 1u);
}

// Refusing non-conformal cells on a deformed block: none left, and the
// result is still a partition of the input.
TEST(TetToHex, RefuseNonConformalOnDeformedBlock) {
  const Deformed d = make_deformed(0.3, 5);
  TetToHexParams params;
  params.quad_angle_deg = 30;
  TetToHexResult loose, strict;
  ASSERT_TRUE(recombine_tetrahedra(d.grid.points, d.tets, params, loose));
  params.refuse_nonconformal = true;
  ASSERT_TRUE(recombine_tetrahedra(d.grid.points, d.tets, params, strict));
  expect_consistent(d.grid.points, d.tets, params, strict);
  EXPECT_GT(loose.stats.nonconformal_interfaces, 0u);
  EXPECT_EQ(strict.stats.nonconformal_interfaces, 0u);
  EXPECT_GT(strict.stats.dissolved_nonconformal, 0u);
  // Some boxes far from the moved vertices keep their hexahedra.
  EXPECT_GT(strict.stats.cells[static_cast<int>(CellKind::Hexahedron)], 0u);
}

// Progress rises to 1 through the named steps; returning false stops the
// run with "aborted" and an empty result.
TEST(TetToHex, ProgressAndAbort) {
  const HexGrid g = make_grid(3, 3, 3);
  const std::vector<Tet> tets = decompose(g, HexDecompositionType::C, false);
  std::vector<double> fractions;
  std::vector<std::string> steps;
  TetToHexParams params;
  params.progress = [&](double f, const char* step) {
    fractions.push_back(f);
    steps.push_back(step);
    return true;
  };
  TetToHexResult r;
  ASSERT_TRUE(recombine_tetrahedra(g.points, tets, params, r));
  ASSERT_FALSE(fractions.empty());
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.back(), 1.0);
  for (const char* step : { "checking the mesh", "searching candidates", "sorting candidates", "adopting candidates" })
    EXPECT_NE(std::find(steps.begin(), steps.end(), step), steps.end()) << step;

  params.progress = [](double, const char* step) { return std::string(step) != "adopting candidates"; };
  const Status s = recombine_tetrahedra(g.points, tets, params, r);
  EXPECT_FALSE(s);
  EXPECT_EQ(s.message, "aborted");
  EXPECT_EQ(r.cells.size(), 0);
}

TEST(TetToHex, EmptyInput) {
  TetToHexResult r;
  ASSERT_TRUE(recombine_tetrahedra({}, {}, TetToHexParams(), r));
  EXPECT_EQ(r.cells.size(), 0);
  EXPECT_EQ(r.source_offsets.size(), 1u);
}

TEST(TetToHex, BadInputFailsWithAMessage) {
  const std::vector<Vec3> p = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 1, 1), Vec3(-1, -1, -1) };
  TetToHexResult r;
  auto message = [&](const std::vector<Vec3>& points, const std::vector<Tet>& tets, TetToHexParams params = {}) {
    const Status s = recombine_tetrahedra(points, tets, params, r);
    EXPECT_FALSE(s);
    return s.message;
  };
  EXPECT_NE(message(p, { { 0, 1, 2, 9 } }).find("refers to point 9"), std::string::npos);
  EXPECT_NE(message(p, { { 0, 2, 1, 3 } }).find("1 tetrahedron is inverted or flat"), std::string::npos);
  EXPECT_NE(message(p, { { 0, 1, 2, 2 } }).find("repeats a point"), std::string::npos);
  // Three tets on one face.
  EXPECT_NE(message(p, { { 0, 1, 2, 3 }, { 4, 1, 3, 2 }, { 5, 1, 3, 2 } }).find("more than two"), std::string::npos);
  // Two tets on the same side of a face (overlapping).
  EXPECT_NE(message(p, { { 0, 1, 2, 3 }, { 5, 1, 2, 3 } }).find("same side"), std::string::npos);
  std::vector<Vec3> nan = p;
  nan[4].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(nan, { { 0, 1, 2, 3 } }).find("NaN"), std::string::npos);
  TetToHexParams bad;
  bad.quad_angle_deg = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(p, { { 0, 1, 2, 3 } }, bad).find("quad angle"), std::string::npos);
  bad = TetToHexParams();
  bad.min_scaled_jacobian = 2;
  EXPECT_NE(message(p, { { 0, 1, 2, 3 } }, bad).find("scaled Jacobian"), std::string::npos);
}

}  // namespace
}  // namespace femorph
