// Surface edge flip of Phased ODT, thesis 2.6.5.3 Fig. 2.45: to keep the
// tetrahedral mesh consistent, a boundary edge is flipped by an edge split
// followed by the collapse of a new edge lying on the surface.
#include "mesh/tet_mesh.h"

namespace femorph {

OpStatus TetMesh::flip_surface_edge(index_t a, index_t b, index_t hint) {
  std::vector<index_t>& ring = scratch_ball_;
  std::vector<index_t>& c = scratch_ball2_;
  bool boundary = false;
  if (!edge_ring_with_vertices(a, b, ring, c, &boundary, hint)) return OpStatus::InvalidArgument;
  if (!boundary) return OpStatus::InvalidArgument;  // not a surface edge
  // A single tet holding both boundary faces would vanish: not a flip.
  if (ring.size() < 2) return OpStatus::WrongValence;
  // The two boundary faces are (a, b, c.front()) and (a, b, c.back()).
  if (open_ring_on_curve(ring, c)) return OpStatus::ForbiddenByRule;  // flipping would move the curve
  const index_t apex = c.front(), other_apex = c.back();
  if (has_edge(apex, other_apex)) return OpStatus::DuplicateEntity;

  index_t m = kInvalidIndex;
  const OpStatus split = split_edge(a, b, nullptr, &m, ring.front());
  if (split != OpStatus::Ok) return split;
  const OpStatus collapse = collapse_edge(Keep{apex}, Remove{m}, nullptr);
  if (collapse == OpStatus::Ok) return OpStatus::Ok;
  // Undo the split: collapsing the new vertex back onto a restores the
  // original tets (same vertices, same regions; new slots).
  const OpStatus undo = collapse_edge(Keep{a}, Remove{m}, nullptr);
  (void)undo;
  touched_.clear();
  return collapse;
}

}  // namespace femorph
