// Helpers shared by TetMesh's implementation files; not part of the API.
#pragma once

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace femorph {
namespace internal {

/// Adjacency code of a boundary face in region r (r >= -1): -2 - r.
inline index_t boundary_code(index_t region) { return -2 - region; }

/// Sorts three ids ascending.
inline void sort3_ids(index_t* v) {
  if (v[0] > v[1]) std::swap(v[0], v[1]);
  if (v[1] > v[2]) std::swap(v[1], v[2]);
  if (v[0] > v[1]) std::swap(v[0], v[1]);
}

/// Sorts three ids ascending; returns whether the permutation was odd.
inline bool sort3_parity(index_t* v) {
  bool odd = false;
  if (v[0] > v[1]) { std::swap(v[0], v[1]); odd = !odd; }
  if (v[1] > v[2]) { std::swap(v[1], v[2]); odd = !odd; }
  if (v[0] > v[1]) { std::swap(v[0], v[1]); odd = !odd; }
  return odd;
}

/// A face of a cavity being re-tetrahedralised (see TetMesh::replace_tets).
struct FaceSlot {
  index_t v[3];
  index_t code;    // 4 * t + f for a tet face; an outer code for outer faces
  index_t is_new;  // 1 for a face of a new tet (an int: whole-word stores)
  bool operator<(const FaceSlot& o) const {
    if (v[0] != o.v[0]) return v[0] < o.v[0];
    if (v[1] != o.v[1]) return v[1] < o.v[1];
    return v[2] < o.v[2];
  }
  bool same_face(const FaceSlot& o) const { return v[0] == o.v[0] && v[1] == o.v[1] && v[2] == o.v[2]; }
};

/// Per-thread scratch buffer for replace_tets (no allocation per operation).
std::vector<FaceSlot>& face_slot_scratch();

/// The other boundary face sharing edge (v, w) with boundary face f of tet t,
/// found by rotating around the edge through the interior. Returns its code
/// 4 * t' + f'.
index_t boundary_face_across_edge(const TetMesh& mesh, index_t t, int f, index_t v, index_t w);

/// Counts boundary edges with other than two boundary faces, and vertices
/// whose boundary faces form more than one fan.
void boundary_manifold_counts(const TetMesh& mesh, std::size_t* bad_edges, std::size_t* bad_fans);

}  // namespace internal
}  // namespace femorph
