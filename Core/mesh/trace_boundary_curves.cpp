#include "mesh/trace_boundary_curves.h"

#include <algorithm>
#include <tuple>

namespace femorph {

namespace {

struct CurveEdge {
  index_t a, b;     // a < b
  index_t r0, r1;   // r0 < r1
};

}  // namespace

std::vector<std::vector<index_t>> trace_boundary_curves(const CompactMesh& mesh,
                                                        const std::vector<std::vector<index_t>>& old_curves,
                                                        const std::vector<std::array<index_t, 2>>& old_regions) {
  // Boundary edges with the regions of their faces; an edge seen with two
  // different regions is a curve edge.
  std::vector<std::tuple<index_t, index_t, index_t>> seen;  // (a, b, region)
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      const index_t r = t < mesh.face_regions.size() ? mesh.face_regions[t][f] : kInvalidIndex;
      if (r < 0) continue;
      index_t v[3];
      for (int i = 0, k = 0; i < 4; ++i)
        if (i != f) v[k++] = mesh.tets[t][i];
      for (int e = 0; e < 3; ++e)
        seen.emplace_back(std::min(v[e], v[(e + 1) % 3]), std::max(v[e], v[(e + 1) % 3]), r);
    }
  std::sort(seen.begin(), seen.end());
  std::vector<CurveEdge> edges;
  for (std::size_t i = 0; i < seen.size();) {
    std::size_t j = i;
    while (j < seen.size() && std::get<0>(seen[j]) == std::get<0>(seen[i]) && std::get<1>(seen[j]) == std::get<1>(seen[i]))
      ++j;
    const index_t lo = std::get<2>(seen[i]), hi = std::get<2>(seen[j - 1]);
    if (lo != hi) edges.push_back({std::get<0>(seen[i]), std::get<1>(seen[i]), lo, hi});
    i = j;
  }

  // Vertex -> incident curve edges; a vertex with other than two is a chain end.
  const std::size_t nv = mesh.points.size();
  std::vector<index_t> degree(nv, 0), first(nv + 1, 0), incident(2 * edges.size());
  for (const CurveEdge& e : edges) ++degree[e.a], ++degree[e.b];
  for (std::size_t v = 0; v < nv; ++v) first[v + 1] = first[v] + degree[v];
  std::vector<index_t> fill(first.begin(), first.end() - 1);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    incident[fill[edges[k].a]++] = static_cast<index_t>(k);
    incident[fill[edges[k].b]++] = static_cast<index_t>(k);
  }
  // Chains: walk from every end (and then from any unused edge: loops),
  // staying on edges of the same region pair.
  std::vector<char> used(edges.size(), 0);
  std::vector<std::vector<index_t>> chains;
  std::vector<std::array<index_t, 2>> chain_regions;
  std::vector<char> chain_closed;
  const auto walk = [&](index_t start, index_t k0) {
    std::vector<index_t> chain{start};
    const index_t r0 = edges[k0].r0, r1 = edges[k0].r1;
    index_t v = start, k = k0;
    bool closed = false;
    while (k >= 0) {
      used[k] = 1;
      v = edges[k].a == v ? edges[k].b : edges[k].a;
      if (v == start) {
        closed = true;
        break;
      }
      chain.push_back(v);
      k = -1;
      if (degree[v] != 2) break;
      for (index_t i = first[v]; i < first[v + 1]; ++i) {
        const CurveEdge& e = edges[incident[i]];
        if (!used[incident[i]] && e.r0 == r0 && e.r1 == r1) k = incident[i];
      }
    }
    chains.push_back(std::move(chain));
    chain_regions.push_back({r0, r1});
    chain_closed.push_back(closed);
  };
  for (std::size_t v = 0; v < nv; ++v)
    if (degree[v] != 2)
      for (index_t i = first[v]; i < first[v + 1]; ++i)
        if (!used[incident[i]]) walk(static_cast<index_t>(v), incident[i]);
  for (std::size_t k = 0; k < edges.size(); ++k)
    if (!used[k]) walk(edges[k].a, static_cast<index_t>(k));

  // Chain of each vertex, to count the overlap with the old curves.
  std::vector<index_t> chain_of(nv, kInvalidIndex);
  for (std::size_t c = 0; c < chains.size(); ++c)
    for (const index_t v : chains[c])
      if (degree[v] == 2) chain_of[v] = static_cast<index_t>(c);

  std::vector<std::vector<index_t>> out(old_curves.size());
  std::vector<int> votes(chains.size(), 0);
  for (std::size_t k = 0; k < old_curves.size(); ++k) {
    const index_t r0 = std::min(old_regions[k][0], old_regions[k][1]);
    const index_t r1 = std::max(old_regions[k][0], old_regions[k][1]);
    std::vector<index_t> touched;
    index_t best = kInvalidIndex;
    for (const index_t old : old_curves[k]) {
      if (old < 0 || static_cast<std::size_t>(old) >= mesh.vertex_map.size()) continue;
      const index_t v = mesh.vertex_map[old];
      if (v < 0 || chain_of[v] < 0) continue;
      const index_t c = chain_of[v];
      if (chain_regions[c][0] != r0 || chain_regions[c][1] != r1) continue;
      if (votes[c]++ == 0) touched.push_back(c);
      if (best < 0 || votes[c] > votes[best]) best = c;
    }
    for (const index_t c : touched) votes[c] = 0;
    if (best < 0) {  // no interior vertex survived: a chain between the same ends
      for (std::size_t c = 0; c < chains.size() && best < 0; ++c) {
        if (chain_regions[c][0] != r0 || chain_regions[c][1] != r1 || old_curves[k].empty()) continue;
        const index_t a = old_curves[k].front() < static_cast<index_t>(mesh.vertex_map.size())
                              ? mesh.vertex_map[old_curves[k].front()] : kInvalidIndex;
        if (a >= 0 && (chains[c].front() == a || chains[c].back() == a)) best = static_cast<index_t>(c);
      }
      if (best < 0) continue;
    }
    std::vector<index_t> chain = chains[best];
    // Orientation of the old list: its first surviving vertex comes first
    // (an open chain) or the direction of its first two survivors (a loop).
    std::vector<index_t> survivors;
    for (const index_t old : old_curves[k])
      if (old >= 0 && static_cast<std::size_t>(old) < mesh.vertex_map.size() && mesh.vertex_map[old] >= 0)
        survivors.push_back(mesh.vertex_map[old]);
    if (!chain_closed[best]) {
      if (!survivors.empty() && chain.back() == survivors.front()) std::reverse(chain.begin(), chain.end());
    } else if (survivors.size() >= 2) {
      const auto i = std::find(chain.begin(), chain.end(), survivors[0]);
      if (i != chain.end()) std::rotate(chain.begin(), i, chain.end());
      const auto j = std::find(chain.begin(), chain.end(), survivors[1]);
      if (j != chain.end() && static_cast<std::size_t>(j - chain.begin()) > chain.size() / 2)
        std::reverse(chain.begin() + 1, chain.end());
    }
    out[k] = std::move(chain);
  }
  return out;
}

}  // namespace femorph
