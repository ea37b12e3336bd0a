// Face adjacency of a tet mesh: the LINK edges of the extended RF-graph
// (thesis 4.5.2). Faces are matched through the tets around one of their
// vertices (the one in fewest tets), one parallel pass over the tets.
#include "hex/tet_to_hex_internal.h"
#include "common/parallel.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

namespace femorph {
namespace tet_to_hex {
namespace {

// Face opposite local vertex f, outward for a positive tet.
constexpr int kOutwardFace[4][3] = { { 1, 2, 3 }, { 0, 3, 2 }, { 0, 1, 3 }, { 0, 2, 1 } };

enum class FaceProblem { None, NonManifold, SameSide };

struct FaceMatch {
  index_t code = -1;  // 4 n + g
  FaceProblem problem = FaceProblem::None;
  index_t other = -1;  // the second tet for the message
};

bool contains(const Tet& t, index_t v) { return t[0] == v || t[1] == v || t[2] == v || t[3] == v; }

FaceMatch match_face(const std::vector<Tet>& tets, const std::vector<index_t>& offsets,
                     const std::vector<index_t>& incident, index_t t, int f) {
  const Tet& tet = tets[t];
  const index_t a = tet[kOutwardFace[f][0]], b = tet[kOutwardFace[f][1]], c = tet[kOutwardFace[f][2]];
  // Walk the shortest of the three vertices' tet lists.
  index_t pivot = a;
  for (index_t v : { b, c })
    if (offsets[v + 1] - offsets[v] < offsets[pivot + 1] - offsets[pivot]) pivot = v;
  FaceMatch m;
  for (index_t i = offsets[pivot]; i < offsets[pivot + 1]; ++i) {
    const index_t n = incident[i];
    if (n == t) continue;
    const Tet& other = tets[n];
    if (!contains(other, a) || !contains(other, b) || !contains(other, c)) continue;
    if (m.code >= 0) {
      m.problem = FaceProblem::NonManifold;
      m.other = n;
      return m;
    }
    int g = 0;
    while (other[g] == a || other[g] == b || other[g] == c) ++g;
    // The neighbour's outward face must run the other way round: after a
    // comes c, not b.
    const int* face = kOutwardFace[g];
    int k = 0;
    while (other[face[k]] != a) ++k;
    if (other[face[(k + 1) % 3]] != c) {
      m.problem = FaceProblem::SameSide;
      m.other = n;
      return m;
    }
    m.code = 4 * n + g;
  }
  return m;
}

}  // namespace

Status build_tet_adjacency(index_t num_points, const std::vector<Tet>& tets,
                           std::vector<index_t>& adjacency) {
  adjacency.clear();
  if (tets.size() > static_cast<std::size_t>(std::numeric_limits<index_t>::max() / 4))
    return Status::failure("too many tetrahedra (" + std::to_string(tets.size()) + ")");
  const index_t nt = static_cast<index_t>(tets.size());
  for (index_t t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k)
      if (tets[t][k] < 0 || tets[t][k] >= num_points)
        return Status::failure("tetrahedron " + std::to_string(t) + " refers to point " +
                               std::to_string(tets[t][k]) + " but there are " +
                               std::to_string(num_points) + " points");
  for (index_t t = 0; t < nt; ++t) {
    const Tet& v = tets[t];
    if (v[0] == v[1] || v[0] == v[2] || v[0] == v[3] || v[1] == v[2] || v[1] == v[3] || v[2] == v[3])
      return Status::failure("tetrahedron " + std::to_string(t) + " repeats a point");
  }

  // Tets around each vertex (CSR, tets in increasing order).
  std::vector<index_t> offsets(static_cast<std::size_t>(num_points) + 1, 0);
  for (const Tet& t : tets)
    for (index_t v : t) ++offsets[v + 1];
  for (index_t v = 0; v < num_points; ++v) offsets[v + 1] += offsets[v];
  std::vector<index_t> incident(static_cast<std::size_t>(offsets[num_points]));
  {
    std::vector<index_t> fill(offsets.begin(), offsets.end() - 1);
    for (index_t t = 0; t < nt; ++t)
      for (index_t v : tets[t]) incident[fill[v]++] = t;
  }

  adjacency.assign(static_cast<std::size_t>(nt) * 4, -1);
  const std::int64_t first_bad = parallel_reduce(
      static_cast<long>(nt), std::numeric_limits<std::int64_t>::max(),
      [&](long begin, long end, int) {
        std::int64_t first = std::numeric_limits<std::int64_t>::max();
        for (index_t t = static_cast<index_t>(begin); t < static_cast<index_t>(end); ++t)
          for (int f = 0; f < 4; ++f) {
            const FaceMatch m = match_face(tets, offsets, incident, t, f);
            if (m.problem != FaceProblem::None) {
              first = std::min<std::int64_t>(first, 4 * static_cast<std::int64_t>(t) + f);
              continue;
            }
            adjacency[4 * t + f] = m.code;
          }
        return first;
      },
      [](std::int64_t a, std::int64_t b) { return std::min(a, b); });
  if (first_bad == std::numeric_limits<std::int64_t>::max()) return Status::success();

  // The first problem, again, for the message.
  const index_t t = static_cast<index_t>(first_bad / 4);
  const int f = static_cast<int>(first_bad % 4);
  const FaceMatch m = match_face(tets, offsets, incident, t, f);
  adjacency.clear();
  std::string face;
  for (int k = 0; k < 3; ++k) face += (k ? ", " : "") + std::to_string(tets[t][kOutwardFace[f][k]]);
  if (m.problem == FaceProblem::NonManifold)
    return Status::failure("the face (" + face + ") is shared by more than two tetrahedra (" +
                           std::to_string(t) + ", " + std::to_string(m.other) +
                           " and more): the mesh is not conforming");
  return Status::failure("tetrahedra " + std::to_string(t) + " and " + std::to_string(m.other) +
                         " lie on the same side of their common face (" + face +
                         "): they overlap or are inconsistently oriented");
}

}  // namespace tet_to_hex
}  // namespace femorph
