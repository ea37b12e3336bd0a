// Inverted element removal by half-edge collapse, thesis 2.6.2 Fig. 2.39.
#include "improve/remove_inverted_elements.h"

#include "improve/collapse_min_stretch.h"
#include "improve/untangle_vertex.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace femorph {
namespace {

double tet_stretch_of(const TetMesh& m, const Tet& T) {
  return tet_stretch(m.point(T[0]), m.point(T[1]), m.point(T[2]), m.point(T[3]));
}

double mesh_min_stretch(const TetMesh& m) {
  double q = std::numeric_limits<double>::infinity();
  for (index_t t = 0; t < m.tet_slots(); ++t)
    if (m.tet_alive(t)) q = std::min(q, tet_stretch_of(m, m.tet(t)));
  return q;
}

struct Candidate {
  double score;
  index_t remove, keep;
};

}  // namespace

InvertedRemovalStats remove_inverted_elements(TetMesh& mesh, const InvertedRemovalOptions& options) {
  InvertedRemovalStats st;
  st.min_stretch_before = mesh_min_stretch(mesh);
  std::vector<std::pair<double, index_t>> inverted;
  auto collect = [&] {
    inverted.clear();
    for (index_t t = 0; t < mesh.tet_slots(); ++t)
      if (mesh.tet_alive(t) && mesh.orientation(t) < 0) inverted.emplace_back(tet_stretch_of(mesh, mesh.tet(t)), t);
    std::sort(inverted.begin(), inverted.end());  // minimum stretch first
  };
  collect();
  st.initial_inverted = inverted.size();
  std::vector<Candidate> candidates;
  // Passes of ordinary half-edge collapses (every remaining tet of the
  // removed vertex's ball positive). When a pass repairs nothing, inverted
  // tets may block each other (each lies in the ball of the vertex another
  // one would remove): then one collapse that leaves such already inverted
  // neighbours inverted (TetMesh::half_edge_collapse_keeping_inverted) is
  // made, the one for the worst tet that succeeds, and ordinary passes resume.
  // Both kinds lower the number of inverted tets, so the loop ends.
  bool tolerant = false;
  for (int pass = 0; pass < options.max_passes && !inverted.empty(); ++pass) {
    std::size_t repaired = 0;
    for (const auto& entry : inverted) {
      const index_t t = entry.second;
      if (!mesh.tet_alive(t) || mesh.orientation(t) >= 0) continue;
      const Tet T = mesh.tet(t);
      // The twelve half-edge collapses of the tet's edges that Fig. 2.37
      // allows: not a forbidden edge, removed vertex not more constrained.
      candidates.clear();
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          if (i == j) continue;
          const index_t r = T[i], k = T[j];
          if (mesh.vertex_class(r) > mesh.vertex_class(k)) continue;
          if (mesh.plan_collapse_by_rules(r, k, t).status != OpStatus::Ok) continue;
          candidates.push_back({collapse_min_stretch(mesh, k, r, mesh.point(k)), r, k});
        }
      // Best minimum stretch first (Fig. 2.39); ties by ids, deterministic.
      std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
        if (a.score != b.score) return a.score > b.score;
        return a.remove != b.remove ? a.remove < b.remove : a.keep < b.keep;
      });
      bool done = false;
      for (const Candidate& c : candidates)
        if (mesh.half_edge_collapse(Keep{c.keep}, Remove{c.remove}) == OpStatus::Ok) {
          done = true;
          break;
        }
      if (!done && tolerant)
        for (const Candidate& c : candidates)
          if (mesh.half_edge_collapse_keeping_inverted(Keep{c.keep}, Remove{c.remove}) == OpStatus::Ok) {
            done = true;
            break;
          }
      if (done) {
        ++repaired;
        ++st.collapses;
        if (tolerant) break;  // one at a time, then ordinary passes again
      }
    }
    if (repaired == 0 && tolerant) {
      if (!options.relocate_vertices) break;
      // Fallback (not in the thesis): move a vertex of an inverted tet so
      // that its whole ball is positive, then collapse again.
      for (const auto& entry : inverted) {
        const index_t t = entry.second;
        if (!mesh.tet_alive(t) || mesh.orientation(t) >= 0) continue;
        const Tet T = mesh.tet(t);
        for (index_t v : T)
          if (untangle_vertex(mesh, v, options.project)) {
            ++repaired;
            ++st.relocations;
            break;
          }
      }
      collect();
      if (repaired == 0) break;
      tolerant = false;
      continue;
    }
    collect();
    tolerant = repaired == 0;
  }
  st.remaining_inverted = inverted.size();
  for (const auto& entry : inverted) st.remaining_tets.push_back(entry.second);
  std::sort(st.remaining_tets.begin(), st.remaining_tets.end());
  st.min_stretch_after = mesh_min_stretch(mesh);
  return st;
}

}  // namespace femorph
