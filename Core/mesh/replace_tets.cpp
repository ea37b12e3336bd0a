// Cavity replacement, the mechanism behind the local operations of thesis
// 2.6.1.3 and 2.6.5: live tets are replaced by new tets with the same
// outer boundary, and face adjacency is rebuilt inside and with the outside.
#include "mesh/tet_mesh.h"

#include "mesh/tet_mesh_internal.h"

#include <cstdint>
#include <vector>

namespace femorph {

void TetMesh::replace_tets(const std::vector<index_t>& old_tets, const std::vector<Tet>& new_tets,
                           const std::vector<index_t>& new_origins, index_t rename_from, index_t rename_to) {
  using internal::FaceSlot;
  std::vector<FaceSlot>& slots = internal::face_slot_scratch();
  slots.clear();
  const std::uint16_t in_cavity = next_tet_mark();
  std::vector<std::uint16_t>& mark = tet_marks_.stamp;
  for (index_t t : old_tets) mark[t] = in_cavity;
  auto make_slot = [](index_t x, index_t y, index_t z, index_t code, index_t is_new) {
    FaceSlot fs{{x, y, z}, code, is_new};
    internal::sort3_ids(fs.v);
    return fs;
  };
  // Outer faces of the cavity, with the renaming applied.
  for (index_t t : old_tets) {
    const TetRecord& R = rec_[t];
    for (int f = 0; f < 4; ++f) {
      const index_t code = R.n[f];
      if (code >= 0 && mark[code >> 2] == in_cavity) continue;  // inside the cavity
      index_t w[3];
      for (int k = 0; k < 3; ++k) {
        w[k] = R.v[kTetFace[f][k]];
        // Outer tets survive: let their vertices point at them for now.
        if (code >= 0 && w[k] != rename_from) vertex_tet_[w[k]] = code >> 2;
        if (w[k] == rename_from) w[k] = rename_to;
      }
      slots.push_back(make_slot(w[0], w[1], w[2], code, 0));
    }
  }
  for (index_t t : old_tets) delete_tet(t);
  touched_.clear();
  for (std::size_t i = 0; i < new_tets.size(); ++i) {
    const Tet& T = new_tets[i];
    const index_t t = new_tet(T, new_origins[i]);
    touched_.push_back(t);
    for (index_t w : T) vertex_tet_[w] = t;
    for (int f = 0; f < 4; ++f)
      slots.push_back(make_slot(T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]], 4 * t + f, 1));
  }

  // Every face key appears twice: two new faces (inside the new tets), a new
  // face and an outer face (cavity boundary), or two outer faces (a vanished
  // tet between them, zipped). A key seen once is a boundary face subdivided
  // by a split (outer (a, b, x) -> new (a, m, x) and (m, b, x)). Pairs are
  // found with a small open-addressing table (cavities hold tens of faces).
  thread_local std::vector<std::int32_t> table;
  thread_local std::vector<char> matched;
  std::size_t capacity = 64;
  while (capacity < 2 * slots.size()) capacity *= 2;
  table.assign(capacity, -1);
  matched.assign(slots.size(), 0);
  const std::size_t mask = capacity - 1;
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const FaceSlot& fs = slots[i];
    std::size_t h = (static_cast<std::uint32_t>(fs.v[0]) * 2654435761u ^ static_cast<std::uint32_t>(fs.v[1]) * 40503u ^
                     static_cast<std::uint32_t>(fs.v[2]) * 2246822519u) >> 4;
    for (h &= mask;; h = (h + 1) & mask) {
      const std::int32_t e = table[h];
      if (e < 0) {
        table[h] = static_cast<std::int32_t>(i);
        break;
      }
      if (!matched[e] && slots[e].same_face(fs)) {
        link_faces(slots[e], fs);
        matched[e] = matched[i] = 1;
        break;
      }
    }
  }
  // A subdivided boundary face passes its region to its pieces: the piece
  // shares two vertices with it (the third is the new vertex).
  for (std::size_t i = 0; i < slots.size(); ++i) {
    if (matched[i] || !slots[i].is_new) continue;
    for (std::size_t j = 0; j < slots.size(); ++j) {
      if (matched[j] || slots[j].is_new) continue;
      const FaceSlot& n = slots[i];
      const FaceSlot& o = slots[j];
      int shared = 0;
      for (int k = 0; k < 3; ++k) shared += (n.v[k] == o.v[0] || n.v[k] == o.v[1] || n.v[k] == o.v[2]);
      if (shared == 2) {
        rec_[n.code >> 2].n[n.code & 3] = o.code;
        break;
      }
    }
  }
}

void TetMesh::link_faces(const internal::FaceSlot& p, const internal::FaceSlot& q) {
  const index_t cp = p.code, cq = q.code;
  if (p.is_new && q.is_new) {
    rec_[cp >> 2].n[cp & 3] = cq;
    rec_[cq >> 2].n[cq & 3] = cp;
  } else if (p.is_new || q.is_new) {
    const index_t cn = p.is_new ? cp : cq, co = p.is_new ? cq : cp;
    rec_[cn >> 2].n[cn & 3] = co;
    if (co >= 0) rec_[co >> 2].n[co & 3] = cn;
  } else if (cp >= 0 && cq >= 0) {
    rec_[cp >> 2].n[cp & 3] = cq;
    rec_[cq >> 2].n[cq & 3] = cp;
  } else if (cp >= 0) {
    rec_[cp >> 2].n[cp & 3] = cq;  // takes the boundary code (region) over
  } else if (cq >= 0) {
    rec_[cq >> 2].n[cq & 3] = cp;
  }
}

}  // namespace femorph
