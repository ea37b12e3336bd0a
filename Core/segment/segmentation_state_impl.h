// Template definitions for segmentation_state.h.
#pragma once

namespace femorph {
namespace segment {

template <class Member>
std::vector<std::vector<index_t>> connected_components(const State& state, bool stop_at_sharp, Member member) {
  const SurfaceMesh& s = state.surface;
  const index_t n = s.num_triangles();
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  std::vector<std::vector<index_t>> components;
  std::vector<index_t> stack;
  for (index_t f0 = 0; f0 < n; ++f0) {
    if (seen[f0] || !member(f0)) continue;
    components.emplace_back();
    std::vector<index_t>& c = components.back();
    seen[f0] = 1;
    stack.assign(1, f0);
    while (!stack.empty()) {
      const index_t f = stack.back();
      stack.pop_back();
      c.push_back(f);
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0 || seen[g]) continue;
        if (stop_at_sharp && state.sharp.edge[3 * f + k]) continue;
        if (!member(g)) continue;
        seen[g] = 1;
        stack.push_back(g);
      }
    }
  }
  return components;
}

}  // namespace segment
}  // namespace femorph
