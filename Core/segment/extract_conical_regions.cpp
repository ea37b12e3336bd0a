// Conical region extraction, thesis 2.4.3 (A13): seeds with the tighter
// direction tolerance (Fig. 2.8 (c)); a cone is split into strips of seeds,
// so the initial fit is a RANSAC over the seeds of one smooth patch
// (2.4.3.3, Fig. 2.10).
#include "segment/segmentation_state.h"

#include <algorithm>
#include <map>

namespace femorph {
namespace segment {

std::vector<std::vector<index_t>> direction_seed_regions(const State& st, double angle);

void extract_conical_regions(State& st) {
  const double angle = degrees_to_radians(st.params.cone_angle_tolerance_deg);
  const std::vector<std::vector<index_t>> seeds = direction_seed_regions(st, angle);
  if (seeds.empty()) return;
  // Smooth patches of unassigned triangles: seeds in one patch are fitted
  // together (the thesis picks seed combinations at random; grouping them by
  // patch avoids the repeated wrong combinations it reported).
  const std::vector<std::vector<index_t>> patches =
      connected_components(st, true, [&](index_t f) { return st.triangle_region[f] < 0; });
  std::vector<index_t> patch_of(static_cast<std::size_t>(st.surface.num_triangles()), kInvalidIndex);
  for (std::size_t p = 0; p < patches.size(); ++p)
    for (index_t f : patches[p]) patch_of[f] = static_cast<index_t>(p);
  std::map<index_t, std::vector<index_t>> seeds_by_patch;
  for (const auto& seed : seeds)
    if (seed.size() >= 2) {
      auto& all = seeds_by_patch[patch_of[seed.front()]];
      all.insert(all.end(), seed.begin(), seed.end());
    }
  for (auto& [patch, seed] : seeds_by_patch) {
    seed.erase(std::remove_if(seed.begin(), seed.end(), [&](index_t f) { return st.triangle_region[f] >= 0; }),
               seed.end());
    if (seed.size() < 3) continue;
    const FitResult fit = fit_region(st, SurfaceType::Cone, seed);
    if (!fit.ok) continue;
    // RANSAC accepted a consensus; integrate from the seed triangles on it.
    WorkRegion region = integrate_region(st, SurfaceType::Cone, seed, fit);
    if (region.alive && region.triangles.size() >= 2) add_region(st, std::move(region));
  }
}

}  // namespace segment
}  // namespace femorph
