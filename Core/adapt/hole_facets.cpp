// The PLC of a hole cut into a mesh (thesis 3.5.5): what tetrahedralize_hole
// must refill so that the kept mesh and the material interfaces stay as
// they are.
#include "adapt/adapt.h"

#include <algorithm>

namespace femorph {

std::vector<HoleFacet> hole_facets(const TetMesh& mesh, const std::vector<index_t>& removed,
                                   const std::function<int(index_t)>& tet_material) {
  std::vector<index_t> sorted = removed;
  std::sort(sorted.begin(), sorted.end());
  const auto is_removed = [&](index_t t) { return std::binary_search(sorted.begin(), sorted.end(), t); };
  std::vector<HoleFacet> facets;
  for (const index_t t : removed) {
    const Tet& T = mesh.tet(t);
    const int inside = tet_material(t);
    for (int f = 0; f < 4; ++f) {
      const index_t code = mesh.adjacency(t, f);
      // kTetFace orders a face so that its normal points out of t: front is
      // the neighbour's side.
      int outside = -1;
      if (code >= 0) {
        const index_t u = code >> 2;
        if (is_removed(u)) {
          // An inner face: an interface when the materials differ, listed
          // once (from the lower tet).
          outside = tet_material(u);
          if (outside == inside || u < t) continue;
        }
      }
      facets.push_back({{{T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]}}, outside, inside});
    }
  }
  return facets;
}

}  // namespace femorph
