// Beyond the thesis: triangles no seed reached (narrow chamfers and fillets
// whose vertices all lie on sharp edges have no curvature estimate) get the
// simplest primitive that fits them, tried on whole smooth patches and then
// on local neighbourhoods; what fits nothing becomes "unknown" regions, never
// a wrong primitive.
#include "segment/segmentation_state.h"

#include <algorithm>

namespace femorph {
namespace segment {

namespace {

constexpr SurfaceType kOrder[] = {SurfaceType::Plane, SurfaceType::Cylinder, SurfaceType::Sphere, SurfaceType::Cone,
                                  SurfaceType::Torus};

}  // namespace

bool fit_patch(State& st, const std::vector<index_t>& triangles) {
  const std::size_t nv = st.vertices_of(triangles).size();
  for (SurfaceType type : kOrder) {
    if (nv < min_vertices(type)) continue;
    const FitResult fit = fit_region(st, type, triangles);
    if (!fit.ok || fit.max_abs > st.tolerance || !plausible_fit(st, fit.surface, triangles)) continue;
    bool all_on = true;
    for (index_t f : triangles) all_on = all_on && st.triangle_near(fit.surface, f);
    if (!all_on) continue;
    WorkRegion region = integrate_region(st, type, triangles, fit);
    if (!region.alive) continue;
    add_region(st, std::move(region));
    return true;
  }
  return false;
}

namespace {

/// The unassigned triangles within `rings` edge-rings of f, inside `allowed`.
std::vector<index_t> neighbourhood(const State& st, index_t f, int rings, const std::vector<char>& allowed) {
  std::vector<index_t> out{f};
  std::size_t begin = 0;
  for (int r = 0; r < rings; ++r) {
    const std::size_t end = out.size();
    for (std::size_t i = begin; i < end; ++i)
      for (int k = 0; k < 3; ++k) {
        const index_t g = st.surface.neighbors[out[i]][k];
        if (g < 0 || !allowed[g] || st.triangle_region[g] >= 0) continue;
        if (std::find(out.begin(), out.end(), g) == out.end()) out.push_back(g);
      }
    begin = end;
  }
  return out;
}

}  // namespace

void classify_remaining_regions(State& st) {
  const index_t nf = st.surface.num_triangles();
  std::vector<std::vector<index_t>> patches =
      connected_components(st, true, [&](index_t f) { return st.triangle_region[f] < 0; });
  std::vector<char> allowed(static_cast<std::size_t>(nf), 0), tried(static_cast<std::size_t>(nf), 0);
  for (const std::vector<index_t>& patch : patches) {
    if (fit_patch(st, patch)) continue;
    // A patch of several surfaces: grow from local neighbourhoods. A
    // neighbourhood that fits nothing marks its triangles tried, so the
    // next seeds start elsewhere (a freeform patch would otherwise cost a
    // set of fits per triangle).
    for (index_t f : patch) allowed[f] = 1;
    for (index_t f : patch) {
      if (st.triangle_region[f] >= 0 || tried[f]) continue;
      bool found = false;
      std::vector<index_t> local;
      for (int rings : {2, 3}) {
        local = neighbourhood(st, f, rings, allowed);
        if ((found = fit_patch(st, local))) break;
      }
      if (!found)
        for (index_t g : local) tried[g] = 1;
    }
    for (index_t f : patch) allowed[f] = 0;
  }
  // What is left is freeform, or too small to tell: unknown regions.
  const std::vector<std::vector<index_t>> rest =
      connected_components(st, true, [&](index_t f) { return st.triangle_region[f] < 0; });
  for (const std::vector<index_t>& part : rest) {
    WorkRegion region;
    region.type = SurfaceType::Unknown;
    region.triangles = part;
    add_region(st, std::move(region));
  }
}

}  // namespace segment
}  // namespace femorph
