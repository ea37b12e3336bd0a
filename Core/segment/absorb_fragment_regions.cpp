// False-region re-recognition, thesis 2.4.4 (Fig. 2.13): a small region is
// made part of the neighbouring region having the longest boundary with it.
// Applied where the boundary curves are approximate: a face one or two
// triangles wide then has nearly all its vertices on its curves, off its
// surface, and growing cuts it into fragments with fits of other types and
// radii (a sphere a little wider than the cylinder it lies in, next to the
// corner sphere both are tangent to).
// A fragment joins the neighbour with the longest shared border whose
// surface every one of its triangles lies near (State::triangle_near), the
// smallest fragments first; one across a junction of faces, near none as a
// whole, is shared out triangle by triangle.
#include "segment/segmentation_state.h"

#include <algorithm>
#include <map>

namespace femorph {
namespace segment {

void absorb_fragment_regions(State& st) {
  if (!(st.curve_tolerance > st.tolerance)) return;
  const SurfaceMesh& s = st.surface;
  constexpr std::size_t kFragment = 30;
  std::vector<char> tried(st.regions.size(), 0);
  // Whether a region's surface is fitted to its present triangles: the fits
  // of growth are of partial regions (and, for narrow faces, of all their
  // vertices); a neighbour is refitted over its exact vertices before it is
  // judged.
  std::vector<char> fresh(st.regions.size(), 0);
  for (;;) {
    // The smallest fitted fragment not tried yet.
    index_t a = kInvalidIndex;
    for (std::size_t r = 0; r < st.regions.size(); ++r) {
      const WorkRegion& region = st.regions[r];
      if (!region.alive || tried[r] || region.type == SurfaceType::Unknown || region.triangles.size() >= kFragment)
        continue;
      if (a < 0 || region.triangles.size() < st.regions[a].triangles.size()) a = static_cast<index_t>(r);
    }
    if (a < 0) break;
    tried[a] = 1;
    WorkRegion& fragment = st.regions[a];
    // Shared border lengths in edges, per larger fitted neighbour.
    std::map<index_t, int> border;
    for (index_t f : fragment.triangles)
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0) continue;
        const index_t b = st.triangle_region[g];
        if (b < 0 || b == a || st.regions[b].type == SurfaceType::Unknown ||
            st.regions[b].triangles.size() <= fragment.triangles.size())
          continue;
        ++border[b];
      }
    std::vector<std::pair<int, index_t>> order;
    for (const auto& [b, n] : border) order.emplace_back(-n, b);
    std::sort(order.begin(), order.end());
    for (const auto& [minus_n, b] : order) {
      WorkRegion& into = st.regions[b];
      if (!fresh[b]) {
        const FitResult fit = refit_region(st, into.type, into.surface, into.triangles);
        if (fit.ok && plausible_fit(st, fit.surface, into.triangles)) into.surface = fit.surface;
        fresh[b] = 1;
      }
      if (!st.absorb_if_near(a, b)) continue;
      fresh[b] = 0;
      break;
    }
    if (!fragment.alive) continue;
    // A fragment across a junction of several faces: its triangles join, one
    // by one from its border, the neighbour (of those judged above) whose
    // surface each lies near, the one sharing more of its edges first.
    std::vector<index_t> rest = fragment.triangles;
    for (bool moved = true; moved && !rest.empty();) {
      moved = false;
      std::vector<index_t> kept;
      for (index_t f : rest) {
        index_t best = kInvalidIndex;
        int best_edges = 0;
        for (int k = 0; k < 3; ++k) {
          const index_t g = s.neighbors[f][k];
          const index_t b = g < 0 ? kInvalidIndex : st.triangle_region[g];
          if (b < 0 || b == a || !border.count(b) || !st.triangle_near(st.regions[b].surface, f)) continue;
          int edges = 0;
          for (int j = 0; j < 3; ++j) {
            const index_t h = s.neighbors[f][j];
            edges += h >= 0 && st.triangle_region[h] == b;
          }
          if (edges > best_edges) {
            best = b;
            best_edges = edges;
          }
        }
        if (best < 0) {
          kept.push_back(f);
          continue;
        }
        st.triangle_region[f] = best;
        st.regions[best].triangles.push_back(f);
        fresh[best] = 0;
        moved = true;
      }
      rest.swap(kept);
    }
    fragment.triangles = rest;
    fragment.alive = !rest.empty();
  }
}

}  // namespace segment
}  // namespace femorph
