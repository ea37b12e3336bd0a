// Thesis 4.4: hexahedra, wedges and pyramids split into tetrahedra without
// new vertices, by the decompositions of Fig. 4.5.
//
// Conformity is decided per quad face, not per cell: a quad shared by two
// cells must be cut by the same diagonal on both sides, so the diagonal is a
// function of the face alone (through its smallest vertex id). Each cell then
// takes a triangulation realising its faces' diagonals. The cell's smallest
// vertex carries the diagonals of its three faces (two for a wedge), and a
// triangulation always exists for such a pattern (hex_decomposition_types.h).
// Fixed-type mode applies one Fig. 4.5 type in every hex's own node order,
// as the thesis does on structured grids (C+), and counts the conflicts of
// Fig. 4.6(a) it produces.
#include "hex/hex_to_tet.h"

#include "geometry/predicates.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace femorph {
namespace {

using Tri = std::array<index_t, 3>;
using Quad = std::array<index_t, 4>;

Tri sorted_tri(index_t a, index_t b, index_t c) {
  Tri t{ { a, b, c } };
  std::sort(t.begin(), t.end());
  return t;
}

const char* kind_name(CellKind kind) {
  switch (kind) {
    case CellKind::Tetra: return "tetrahedron";
    case CellKind::Pyramid: return "pyramid";
    case CellKind::Wedge: return "wedge";
    case CellKind::Hexahedron: return "hexahedron";
  }
  return "cell";
}

/// The faces of the input tets. A quad of another cell that two of them
/// already split keeps their diagonal: a hex-dominant mesh with tets glued
/// to quads (Tet To Hex without its conformity option) comes back conforming.
class TetFaces {
 public:
  explicit TetFaces(const MixedCells& cells) {
    for (index_t c = 0; c < cells.size(); ++c) {
      if (cells.kinds[c] != CellKind::Tetra) continue;
      const index_t* v = cells.nodes(c);
      faces_.push_back(sorted_tri(v[1], v[2], v[3]));
      faces_.push_back(sorted_tri(v[0], v[2], v[3]));
      faces_.push_back(sorted_tri(v[0], v[1], v[3]));
      faces_.push_back(sorted_tri(v[0], v[1], v[2]));
    }
    std::sort(faces_.begin(), faces_.end());
    faces_.erase(std::unique(faces_.begin(), faces_.end()), faces_.end());
  }

  /// The diagonal the input tets cut quad g with: 0 (g0-g2), 1 (g1-g3), or
  /// -1 when no two tets lie on it (or both pairs do, which only overlapping
  /// tets can).
  bool empty() const { return faces_.empty(); }

  int diagonal(const Quad& g) const {
    if (faces_.empty()) return -1;
    const bool d0 = has(sorted_tri(g[0], g[1], g[2])) && has(sorted_tri(g[0], g[2], g[3]));
    const bool d1 = has(sorted_tri(g[0], g[1], g[3])) && has(sorted_tri(g[1], g[2], g[3]));
    if (d0 == d1) return -1;
    return d0 ? 0 : 1;
  }

 private:
  bool has(const Tri& t) const { return std::binary_search(faces_.begin(), faces_.end(), t); }
  std::vector<Tri> faces_;
};

/// The default rule: the diagonal through the quad's smallest vertex id.
/// Both cells on the quad see the same four ids, so they agree.
int min_id_diagonal(const Quad& g) {
  const int k = static_cast<int>(std::min_element(g.begin(), g.end()) - g.begin());
  return k & 1;
}

Quad global_quad(const index_t* nodes, const std::array<std::int8_t, 4>& local) {
  return Quad{ { nodes[local[0]], nodes[local[1]], nodes[local[2]], nodes[local[3]] } };
}

/// The diagonals of a cell's quads (bit f: quad f's, as in
/// HexDecomposition::diagonals) by the smallest-id rule, and those the input
/// tets impose (`forced_mask`: the quads two tets cut, `forced_bits`: how).
struct QuadPattern {
  std::uint8_t min_id_bits = 0;
  std::uint8_t forced_mask = 0;
  std::uint8_t forced_bits = 0;
};

template <std::size_t N>
QuadPattern quad_pattern(const index_t* nodes, const std::array<std::array<std::int8_t, 4>, N>& quads,
                         const TetFaces* tets) {
  QuadPattern p;
  for (std::size_t f = 0; f < N; ++f) {
    const Quad g = global_quad(nodes, quads[f]);
    p.min_id_bits |= static_cast<std::uint8_t>(min_id_diagonal(g) << f);
    const int d = tets ? tets->diagonal(g) : -1;
    if (d >= 0) {
      p.forced_mask |= static_cast<std::uint8_t>(1u << f);
      p.forced_bits |= static_cast<std::uint8_t>(d << f);
    }
  }
  return p;
}

int popcount(unsigned x) {
  int n = 0;
  for (; x; x &= x - 1) ++n;
  return n;
}

/// The patterns to try: the forced diagonals on as many forced quads as a
/// triangulation allows, the smallest-id rule elsewhere (which alone is
/// always realisable). `realisable(bits)` says whether a pattern is. Without
/// forced quads (every all-hex mesh) this is the smallest-id pattern alone.
template <typename Realisable>
std::vector<std::uint8_t> best_patterns(const QuadPattern& p, Realisable realisable) {
  std::vector<std::uint8_t> best;
  int kept = -1;
  // Every subset of the forced quads, the empty one last.
  for (unsigned sub = p.forced_mask;; sub = (sub - 1) & p.forced_mask) {
    const auto bits = static_cast<std::uint8_t>((p.forced_bits & sub) | (p.min_id_bits & ~sub));
    const int n = popcount(sub);
    if (n >= kept && realisable(bits) && std::find(best.begin(), best.end(), bits) == best.end()) {
      if (n > kept) best.clear();
      kept = n;
      best.push_back(bits);
    }
    if (sub == 0) break;
  }
  return best;
}

/// Minimum stretch (thesis Eq. 1.1) of a triangulation on the actual cell:
/// the choice among the triangulations of one diagonal pattern.
double min_stretch(const std::vector<LocalTet>& tets, const Vec3* corners) {
  double q = std::numeric_limits<double>::infinity();
  for (const LocalTet& t : tets)
    q = std::min(q, tet_stretch(corners[t[0]], corners[t[1]], corners[t[2]], corners[t[3]]));
  return q;
}

/// One quad face of a cell as cut: for matching the two sides.
struct QuadCut {
  Quad key;                            // sorted ids
  std::pair<index_t, index_t> diagonal;  // sorted end points
};

Status validate(const std::vector<Vec3>& points, const MixedCells& cells) {
  const index_t n = cells.size();
  if (cells.offsets.size() != static_cast<std::size_t>(n) + 1 || cells.offsets[0] != 0 ||
      static_cast<std::size_t>(cells.offsets.back()) != cells.connectivity.size())
    return Status::failure("the cell offsets do not match the cells and their connectivity");
  std::size_t nonfinite = 0;
  for (const Vec3& p : points) nonfinite += !p.allFinite();
  if (nonfinite > 0)
    return Status::failure(std::to_string(nonfinite) +
                           (nonfinite == 1 ? " point has" : " points have") +
                           " NaN or infinite coordinates");
  const index_t np = static_cast<index_t>(points.size());
  for (index_t c = 0; c < n; ++c) {
    const int expected = cell_node_count(cells.kinds[c]);
    if (cells.node_count(c) != expected)
      return Status::failure("cell " + std::to_string(c) + " (" + kind_name(cells.kinds[c]) + ") has " +
                             std::to_string(cells.node_count(c)) + " nodes instead of " +
                             std::to_string(expected));
    const index_t* v = cells.nodes(c);
    for (int i = 0; i < expected; ++i) {
      if (v[i] < 0 || v[i] >= np)
        return Status::failure("cell " + std::to_string(c) + " refers to point " + std::to_string(v[i]) +
                               " but there are " + std::to_string(np) + " points");
      for (int j = 0; j < i; ++j)
        if (v[j] == v[i])
          // A collapsed cell has no triangulation without flat tets, and its
          // quads no well-defined diagonal.
          return Status::failure("cell " + std::to_string(c) + " (" + kind_name(cells.kinds[c]) +
                                 ") uses point " + std::to_string(v[i]) +
                                 " twice; collapsed cells are not supported");
    }
  }
  return Status::success();
}

Status decompose(const std::vector<Vec3>& points, const MixedCells& cells, const HexToTetParams& params,
                 HexToTetResult& result) {
  if (Status s = validate(points, cells); !s) return s;

  const index_t n = cells.size();
  const TetFaces tet_faces(cells);
  const TetFaces* forcing = params.conforming ? &tet_faces : nullptr;
  result.hex_type.assign(static_cast<std::size_t>(n), -1);
  result.hex_mirrored.assign(static_cast<std::size_t>(n), -1);
  // Both sides of a quad follow the same rule when the mode is conforming
  // and no tets force diagonals: no conflict to look for (the tests check
  // it independently), and no 24 bytes per quad to spend.
  const bool count_conflicts = !params.conforming || !tet_faces.empty();
  std::vector<QuadCut> cuts;

  for (index_t c = 0; c < n; ++c) {
    const index_t* v = cells.nodes(c);
    const std::size_t first_tet = result.tets.size();
    auto emit = [&](const LocalTet& t) {
      result.tets.push_back(Tet{ { v[t[0]], v[t[1]], v[t[2]], v[t[3]] } });
      result.source_cell.push_back(c);
    };
    // Records the cut of each quad of the cell, for the conformity count.
    auto record = [&](const auto& quads, std::uint8_t bits) {
      for (std::size_t f = 0; f < quads.size(); ++f) {
        const Quad g = global_quad(v, quads[f]);
        const int d = (bits >> f) & 1;
        QuadCut cut;
        cut.key = g;
        std::sort(cut.key.begin(), cut.key.end());
        cut.diagonal = std::minmax(g[d], g[d + 2]);
        if (count_conflicts) cuts.push_back(cut);
        const int by_tets = tet_faces.diagonal(g);
        if (by_tets >= 0) {
          if (by_tets == d) ++result.quads_following_tets;
          else ++result.nonconforming_faces;
        }
      }
    };

    switch (cells.kinds[c]) {
      case CellKind::Tetra:
        emit(LocalTet{ { 0, 1, 2, 3 } });
        break;
      case CellKind::Pyramid: {
        static const std::array<std::array<std::int8_t, 4>, 1> base = { { { 0, 1, 2, 3 } } };
        const QuadPattern p = quad_pattern(v, base, forcing);
        const std::uint8_t bits = p.forced_mask ? p.forced_bits : p.min_id_bits;
        for (const LocalTet& t : pyramid_decomposition(bits & 1)) emit(t);
        record(base, bits);
        break;
      }
      case CellKind::Wedge: {
        // Tets may force one of the two cyclic patterns; the smallest-id
        // rule never does (two diagonals meet at the smallest vertex).
        std::array<LocalTet, 3> tets;
        const auto patterns = best_patterns(quad_pattern(v, kWedgeQuadFaces, forcing),
                                            [&](std::uint8_t bits) { return wedge_decomposition(bits, tets); });
        if (patterns.empty() || !wedge_decomposition(patterns.front(), tets))
          return Status::failure("internal error: no triangulation of wedge " + std::to_string(c));
        for (const LocalTet& t : tets) emit(t);
        record(kWedgeQuadFaces, patterns.front());
        break;
      }
      case CellKind::Hexahedron: {
        const HexDecomposition* chosen = nullptr;
        if (params.conforming) {
          std::vector<const HexDecomposition*> candidates;
          for (std::uint8_t bits : best_patterns(quad_pattern(v, kHexFaces, forcing), [](std::uint8_t bits) {
                 return !hex_decompositions_with_diagonals(bits).empty();
               })) {
            const auto list = hex_decompositions_with_diagonals(bits);
            candidates.insert(candidates.end(), list.begin(), list.end());
          }
          if (candidates.empty())
            return Status::failure("internal error: no triangulation of hexahedron " + std::to_string(c));
          chosen = candidates.front();
          if (candidates.size() > 1) {
            // Best worst tet: the first of equal ones, so the choice is
            // deterministic.
            Vec3 corners[8];
            for (int i = 0; i < 8; ++i) corners[i] = points[v[i]];
            double best = -std::numeric_limits<double>::infinity();
            for (const HexDecomposition* d : candidates) {
              const double q = min_stretch(d->tets, corners);
              if (q > best) {
                best = q;
                chosen = d;
              }
            }
          }
          result.hex_mirrored[c] = 0;
        } else {
          chosen = &hex_decomposition(params.type, params.mirrored);
          result.hex_mirrored[c] = params.mirrored ? 1 : 0;
        }
        result.hex_type[c] = static_cast<std::int8_t>(chosen->type);
        for (const LocalTet& t : chosen->tets) emit(t);
        record(kHexFaces, chosen->diagonals);
        break;
      }
    }

    // Exact orientation: a flat tet is as unusable as an inverted one.
    bool inverted = false;
    for (std::size_t t = first_tet; t < result.tets.size(); ++t) {
      const Tet& k = result.tets[t];
      const bool bad = orient3d_sign(points[k[0]], points[k[1]], points[k[2]], points[k[3]]) <= 0;
      result.tet_inverted.push_back(bad ? 1 : 0);
      inverted = inverted || bad;
    }
    if (inverted) result.inverted.push_back(c);
  }
  result.inverted_cells = result.inverted.size();

  // Quads cut by the cells on both sides: conflicting diagonals (Fig. 4.6(a)).
  std::sort(cuts.begin(), cuts.end(), [](const QuadCut& a, const QuadCut& b) {
    return a.key != b.key ? a.key < b.key : a.diagonal < b.diagonal;
  });
  for (std::size_t i = 0; i < cuts.size();) {
    std::size_t j = i + 1;
    while (j < cuts.size() && cuts[j].key == cuts[i].key) ++j;
    if (cuts[j - 1].diagonal != cuts[i].diagonal) ++result.nonconforming_faces;
    i = j;
  }
  return Status::success();
}

}  // namespace

Status decompose_to_tetrahedra(const std::vector<Vec3>& points, const MixedCells& cells,
                               const HexToTetParams& params, HexToTetResult& result) {
  result = HexToTetResult{};
  Status s = decompose(points, cells, params, result);
  // After decompose's checks of the cells' sizes and ids.
  const std::array<index_t, 2> twice = s ? find_duplicate_cells(cells) : std::array<index_t, 2>{{-1, -1}};
  if (twice[0] >= 0)
    s = Status::failure("cells " + std::to_string(twice[0]) + " and " + std::to_string(twice[1]) +
                        " have the same points: the mesh has a cell twice (its tetrahedra would overlap)");
  if (!s) result = HexToTetResult{};
  return s;
}

}  // namespace femorph
