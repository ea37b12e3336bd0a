// refuse_nonconformal (beyond the thesis): after the greedy pass (A2), no
// quad face may meet two triangles of other cells. Rounds of: find the
// cells with such a quad; adopt, in priority order, the free candidates on
// the two tets behind such a quad whose own quads are all conformal
// (typically the pyramid capping a hexahedron's quad that faces tets), for
// cells whose every offending quad has one; dissolve the cells still
// offending back into tets, never to be adopted again. Each round dissolves
// a cell for good or takes free tets, so the rounds end. Last, a greedy
// pass over the tets left adopts the candidates that are conformal as they
// are (e.g. a pyramid whose base is on the boundary).
#include "hex/tet_to_hex_internal.h"

#include <algorithm>
#include <cstddef>

namespace femorph {
namespace tet_to_hex {
namespace {

void sort_unique(std::vector<index_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

/// The live cells next to (or owning) the tets of `cell`.
void add_cells_around(const Cell& cell, const std::vector<index_t>& cell_of_tet,
                      const std::vector<index_t>& adjacency, std::vector<index_t>& out) {
  for (int i = 0; i < cell.num_tets; ++i)
    for (int f = 0; f < 4; ++f) {
      const index_t code = adjacency[4 * static_cast<std::size_t>(cell.tets[i]) + f];
      if (code >= 0 && cell_of_tet[code >> 2] != kInvalidIndex) out.push_back(cell_of_tet[code >> 2]);
    }
}

}  // namespace

std::size_t dissolve_nonconformal_cells(const std::vector<Candidate>& candidates,
                                        const std::vector<Vec3>& points,
                                        const std::vector<Tet>& tets,
                                        const std::vector<index_t>& adjacency,
                                        std::vector<Cell>& cells,
                                        std::vector<index_t>& cell_of_tet) {
  // Candidates of each tet (CSR, in priority order).
  const std::size_t nt = tets.size();
  std::vector<std::size_t> offsets(nt + 1, 0);
  for (const Candidate& c : candidates)
    for (int k = 0; k < c.num_tets; ++k) ++offsets[c.tets[k] + 1];
  for (std::size_t t = 0; t < nt; ++t) offsets[t + 1] += offsets[t];
  std::vector<index_t> of_tet(offsets[nt]);
  {
    std::vector<std::size_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t i = 0; i < candidates.size(); ++i)
      for (int k = 0; k < candidates[i].num_tets; ++k)
        of_tet[fill[candidates[i].tets[k]]++] = static_cast<index_t>(i);
  }
  std::vector<std::uint8_t> banned(candidates.size(), 0);
  for (const Cell& c : cells) banned[c.candidate] = c.alive ? 0 : 1;

  auto offending = [&](const Cell& cell) {
    const std::array<std::int8_t, 4>* quads = nullptr;
    const int nq = cell_quads(cell.kind, quads);
    for (int q = 0; q < nq; ++q)
      if (!quad_is_conformal(cell, q, cells, cell_of_tet, tets, adjacency)) return true;
    return false;
  };
  auto all_free = [&cell_of_tet](const Candidate& c) {
    for (int k = 0; k < c.num_tets; ++k)
      if (cell_of_tet[c.tets[k]] != kInvalidIndex) return false;
    return true;
  };
  // Necessary for a conformal candidate, without its walk: only its
  // triangular faces (0 hexahedron, 2 wedge, 4 pyramid) may face free tets.
  auto may_be_conformal = [&](const Candidate& c) {
    const CellKind kind = search_trees()[c.tree].kind;
    const int allowed = kind == CellKind::Pyramid ? 4 : kind == CellKind::Wedge ? 2 : 0;
    int facing_free = 0;
    for (int k = 0; k < c.num_tets; ++k)
      for (int f = 0; f < 4; ++f) {
        const index_t code = adjacency[4 * static_cast<std::size_t>(c.tets[k]) + f];
        if (code < 0 || cell_of_tet[code >> 2] != kInvalidIndex) continue;
        const index_t n = code >> 2;
        if (std::find(c.tets.begin(), c.tets.begin() + c.num_tets, n) == c.tets.begin() + c.num_tets &&
            ++facing_free > allowed)
          return false;
      }
    return true;
  };

  // Adopts candidate i when its tets are free and all its quads conformal.
  auto adopt_if_conformal = [&](index_t i) {
    const Candidate& c = candidates[i];
    if (!all_free(c) || !may_be_conformal(c)) return false;
    Cell cell = candidate_cell(c, i, points, tets, adjacency);
    if (offending(cell)) return false;
    for (int k = 0; k < c.num_tets; ++k) cell_of_tet[c.tets[k]] = static_cast<index_t>(cells.size());
    cells.push_back(cell);
    return true;
  };

  std::size_t dissolved = 0;
  std::vector<index_t> dirty(cells.size()), bad, fixes, cell_fixes, next;
  for (std::size_t c = 0; c < cells.size(); ++c) dirty[c] = static_cast<index_t>(c);
  while (!dirty.empty()) {
    sort_unique(dirty);
    bad.clear();
    for (index_t c : dirty)
      if (cells[c].alive && offending(cells[c])) bad.push_back(c);
    if (bad.empty()) break;
    next.clear();

    // The fixes of a cell's offending quads: free candidates on the two
    // tets behind each (a pyramid on the quad, ...). A cell with a quad
    // that nothing can fix is left to dissolve: its neighbours keep the tets.
    fixes.clear();
    for (index_t c : bad) {
      const Cell& cell = cells[c];
      const std::array<std::int8_t, 4>* quads = nullptr;
      const int nq = cell_quads(cell.kind, quads);
      bool doomed = false;
      cell_fixes.clear();
      for (int q = 0; q < nq && !doomed; ++q) {
        if (quad_is_conformal(cell, q, cells, cell_of_tet, tets, adjacency)) continue;
        std::array<index_t, 2> across;
        doomed = !quad_across(cell, q, tets, adjacency, across) || across[0] == kInvalidIndex ||
                 across[1] == kInvalidIndex || cell_of_tet[across[0]] != kInvalidIndex ||
                 cell_of_tet[across[1]] != kInvalidIndex;
        if (doomed) break;
        const std::size_t before = cell_fixes.size();
        for (std::size_t k = offsets[across[0]]; k < offsets[across[0] + 1]; ++k) {
          const Candidate& f = candidates[of_tet[k]];
          if (!banned[of_tet[k]] &&
              std::find(f.tets.begin(), f.tets.begin() + f.num_tets, across[1]) != f.tets.begin() + f.num_tets &&
              all_free(f))
            cell_fixes.push_back(of_tet[k]);
        }
        doomed = cell_fixes.size() == before;
      }
      if (!doomed) fixes.insert(fixes.end(), cell_fixes.begin(), cell_fixes.end());
    }
    // Adopted in priority order when all their quads are conformal.
    sort_unique(fixes);
    for (index_t i : fixes)
      if (adopt_if_conformal(i)) add_cells_around(cells.back(), cell_of_tet, adjacency, next);

    // The cells still offending go back to tets.
    for (index_t c : bad) {
      Cell& cell = cells[c];
      if (!offending(cell)) continue;
      cell.alive = false;
      banned[cell.candidate] = 1;
      ++dissolved;
      for (int k = 0; k < cell.num_tets; ++k) cell_of_tet[cell.tets[k]] = kInvalidIndex;
      add_cells_around(cell, cell_of_tet, adjacency, next);
    }
    dirty.swap(next);
  }

  // Greedy again on the tets left, for candidates whose quads are all
  // conformal (on the boundary, or matching a cell's quad); adopting one
  // never makes another cell's quad non-conformal.
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (!banned[i]) adopt_if_conformal(static_cast<index_t>(i));
  return dissolved;
}

}  // namespace tet_to_hex
}  // namespace femorph
