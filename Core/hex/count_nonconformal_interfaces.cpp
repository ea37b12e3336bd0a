// Non-conformal interfaces of a hex-dominant mesh (beyond the thesis, which
// leaves them to later work; Botella 2016 counts them): a quad face of a
// hexahedron, prism or pyramid base that is inside the mesh but not matched
// by the same quad (same four vertices) of the cell on its other side, i.e.
// it meets two triangles of other cells.
#include "hex/tet_to_hex_internal.h"
#include "common/parallel.h"

#include <algorithm>
#include <cstddef>

namespace femorph {
namespace tet_to_hex {
namespace {

std::array<index_t, 4> sorted_quad(const Cell& cell, const std::array<std::int8_t, 4>& q) {
  std::array<index_t, 4> v = { cell.nodes[q[0]], cell.nodes[q[1]], cell.nodes[q[2]], cell.nodes[q[3]] };
  std::sort(v.begin(), v.end());
  return v;
}

bool in(const std::array<index_t, 4>& quad, index_t v) {
  return quad[0] == v || quad[1] == v || quad[2] == v || quad[3] == v;
}

}  // namespace

bool quad_across(const Cell& cell, int q, const std::vector<Tet>& tets,
                 const std::vector<index_t>& adjacency, std::array<index_t, 2>& across) {
  const std::array<std::int8_t, 4>* quads = nullptr;
  cell_quads(cell.kind, quads);
  const std::array<index_t, 4> quad = sorted_quad(cell, quads[q]);
  int found = 0;
  for (int i = 0; i < cell.num_tets; ++i) {
    const Tet& t = tets[cell.tets[i]];
    for (int f = 0; f < 4; ++f) {
      bool on_quad = true;
      for (int k = 0; k < 4 && on_quad; ++k) on_quad = k == f || in(quad, t[k]);
      if (!on_quad) continue;
      if (found == 2) return false;  // not a cell of this kind
      const index_t code = adjacency[4 * static_cast<std::size_t>(cell.tets[i]) + f];
      across[found++] = code < 0 ? kInvalidIndex : code >> 2;
    }
  }
  return found == 2;
}

bool quad_is_conformal(const Cell& cell, int q, const std::vector<Cell>& cells,
                       const std::vector<index_t>& cell_of_tet, const std::vector<Tet>& tets,
                       const std::vector<index_t>& adjacency) {
  std::array<index_t, 2> across;
  if (!quad_across(cell, q, tets, adjacency, across)) return false;
  if (across[0] == kInvalidIndex && across[1] == kInvalidIndex) return true;  // boundary
  if (across[0] == kInvalidIndex || across[1] == kInvalidIndex) return false;
  const index_t other = cell_of_tet[across[0]];
  if (other == kInvalidIndex || other != cell_of_tet[across[1]]) return false;
  const Cell& o = cells[other];
  const std::array<std::int8_t, 4>* quads = nullptr;
  const std::array<std::int8_t, 4>* other_quads = nullptr;
  cell_quads(cell.kind, quads);
  const std::array<index_t, 4> quad = sorted_quad(cell, quads[q]);
  const int n = cell_quads(o.kind, other_quads);
  for (int k = 0; k < n; ++k)
    if (sorted_quad(o, other_quads[k]) == quad) return true;
  return false;
}

std::size_t count_nonconformal_interfaces(const std::vector<Cell>& cells,
                                          const std::vector<index_t>& cell_of_tet,
                                          const std::vector<Tet>& tets,
                                          const std::vector<index_t>& adjacency,
                                          std::vector<std::uint8_t>* flags) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(cells.size());
  if (flags) flags->assign(cells.size(), 0);
  return parallel_reduce(
      static_cast<long>(n), std::size_t(0),
      [&](long begin, long end, int) {
        std::size_t count = 0;
        for (std::ptrdiff_t c = begin; c < end; ++c) {
          if (!cells[c].alive) continue;
          const std::array<std::int8_t, 4>* quads = nullptr;
          const int nq = cell_quads(cells[c].kind, quads);
          for (int q = 0; q < nq; ++q)
            if (!quad_is_conformal(cells[c], q, cells, cell_of_tet, tets, adjacency)) {
              ++count;
              if (flags) (*flags)[c] = 1;
            }
        }
        return count;
      },
      [](std::size_t a, std::size_t b) { return a + b; });
}

}  // namespace tet_to_hex
}  // namespace femorph
