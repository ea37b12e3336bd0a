// Two cells over the same nodes: a mesh file with a cell written twice. The
// decomposition of such a mesh would put one face in more than two tets.
#include "hex/mixed_cells.h"

#include <algorithm>
#include <array>
#include <vector>

namespace femorph {

std::array<index_t, 2> find_duplicate_cells(const MixedCells& cells) {
  // Each cell's sorted nodes, padded with -1, and its id: equal keys sort
  // next to each other.
  struct Key {
    std::array<index_t, 8> nodes;
    index_t cell;
  };
  std::vector<Key> keys(static_cast<std::size_t>(cells.size()));
  for (index_t c = 0; c < cells.size(); ++c) {
    Key& k = keys[static_cast<std::size_t>(c)];
    k.nodes.fill(-1);
    std::copy(cells.nodes(c), cells.nodes(c) + cells.node_count(c), k.nodes.begin());
    std::sort(k.nodes.begin(), k.nodes.begin() + cells.node_count(c));
    k.cell = c;
  }
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    return a.nodes != b.nodes ? a.nodes < b.nodes : a.cell < b.cell;
  });
  std::array<index_t, 2> first{{kInvalidIndex, kInvalidIndex}};
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i].nodes == keys[i - 1].nodes && (first[0] < 0 || keys[i - 1].cell < first[0]))
      first = {{keys[i - 1].cell, keys[i].cell}};
  return first;
}

}  // namespace femorph
