// Beyond the thesis: triangles no seed reached (narrow chamfers and fillets
// whose vertices all lie on sharp edges have no curvature estimate) get the
// simplest primitive that fits them, tried on whole smooth patches and then
// on local neighbourhoods; what fits nothing becomes "unknown" regions, never
// a wrong primitive.
#include "segment/segmentation_state.h"

#include "common/parallel.h"

#include <algorithm>

namespace femorph {
namespace segment {

namespace {

constexpr SurfaceType kOrder[] = {SurfaceType::Plane, SurfaceType::Cylinder, SurfaceType::Sphere, SurfaceType::Cone,
                                  SurfaceType::Torus};
constexpr int kTypes = 5;
/// Most seeds judged at once (the batch doubles while every seed fails).
constexpr std::size_t kMaxBatch = 16;

/// A type's fit to a triangle set, and whether every triangle lies on it.
struct Verdict {
  FitResult fit;
  bool pass = false;
};

/// The read-only part of fit_patch for one type (safe to run concurrently).
Verdict judge(const State& st, SurfaceType type, const std::vector<index_t>& triangles) {
  Verdict v;
  if (st.vertices_of(triangles).size() < min_vertices(type)) return v;
  v.fit = fit_region(st, type, triangles);
  if (!v.fit.ok || v.fit.max_abs > st.tolerance || !plausible_fit(st, v.fit.surface, triangles)) return v;
  bool all_on = true;
  for (index_t f : triangles) all_on = all_on && st.triangle_near(v.fit.surface, f);
  v.pass = all_on;
  return v;
}

/// Adds the region of the first type (kOrder) in [first, end) that passed
/// and whose integrated region survives (`verdicts` indexed by type).
bool integrate_first(State& st, const std::vector<index_t>& triangles, const Verdict* verdicts, int first = 0,
                     int end = kTypes) {
  for (int t = first; t < end; ++t) {
    if (!verdicts[t].pass) continue;
    WorkRegion region = integrate_region(st, kOrder[t], triangles, verdicts[t].fit);
    if (!region.alive) continue;
    add_region(st, std::move(region));
    return true;
  }
  return false;
}

/// The verdicts of every type (slot k * kTypes + t) on each set, for the
/// slots in [first, end) (the others left failed). The fits run in parallel, each
/// result in its own slot, so they do not depend on the thread count.
std::vector<Verdict> judge_sets(const State& st, const std::vector<const std::vector<index_t>*>& sets,
                                std::size_t first = 0, std::size_t end = std::size_t(-1)) {
  std::vector<Verdict> out(sets.size() * kTypes);
  // Costliest fits first (tori, cones, spheres) for an even share of the threads.
  std::vector<std::size_t> jobs;
  for (int t = kTypes - 1; t >= 0; --t)
    for (std::size_t k = 0; k < sets.size(); ++k)
      if (k * kTypes + static_cast<std::size_t>(t) >= first && k * kTypes + static_cast<std::size_t>(t) < end)
        jobs.push_back(k * kTypes + static_cast<std::size_t>(t));
  parallel_for(
      static_cast<long>(jobs.size()),
      [&](long j) {
        const std::size_t slot = jobs[static_cast<std::size_t>(j)];
        out[slot] = judge(st, kOrder[slot % kTypes], *sets[slot / kTypes]);
      },
      2, 1);
  return out;
}

}  // namespace

/// The types in stages of growing cost, each stage's fits in parallel: the
/// plane alone (almost free), then cylinder and sphere, then cone and torus;
/// a stage runs only when the ones before gave no region, so a patch that
/// is a simple surface costs about what the serial order would.
bool fit_patch(State& st, const std::vector<index_t>& triangles) {
  const std::vector<const std::vector<index_t>*> sets{&triangles};
  for (int first : {0, 1, 3}) {
    const int end = first == 0 ? 1 : first + 2;
    const std::vector<Verdict> verdicts = judge_sets(st, sets, static_cast<std::size_t>(first),
                                                     static_cast<std::size_t>(end));
    if (integrate_first(st, triangles, verdicts.data(), first, end)) return true;
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
  std::vector<char> allowed(static_cast<std::size_t>(nf), 0), tried(static_cast<std::size_t>(nf), 0),
      planned(static_cast<std::size_t>(nf), 0);
  for (const std::vector<index_t>& patch : patches) {
    if (fit_patch(st, patch)) continue;
    // A patch of several surfaces: grow from local neighbourhoods. A
    // neighbourhood that fits nothing marks its triangles tried, so the
    // next seeds start elsewhere (a freeform patch would otherwise cost a
    // set of fits per triangle).
    for (index_t f : patch) allowed[f] = 1;
    // The seeds are judged in batches, in parallel: the seeds a batch holds
    // are those the loop would visit if every one before failed (the usual
    // case on a freeform patch), so their neighbourhoods are known before
    // their fits. A seed that gives a region ends the batch; the seeds
    // after it are judged again in the next.
    std::size_t pos = 0, batch = 1;
    while (pos < patch.size()) {
      std::vector<std::size_t> at;  // positions in patch of the batch's seeds
      std::vector<std::vector<index_t>> rings;  // per seed: 2-ring, 3-ring
      for (std::size_t p = pos; p < patch.size() && at.size() < batch; ++p) {
        const index_t f = patch[p];
        if (st.triangle_region[f] >= 0 || tried[f] || planned[f]) continue;
        at.push_back(p);
        rings.push_back(neighbourhood(st, f, 2, allowed));
        rings.push_back(neighbourhood(st, f, 3, allowed));
        for (index_t g : rings.back()) planned[g] = 1;
      }
      for (std::size_t k = 1; k < rings.size(); k += 2)
        for (index_t g : rings[k]) planned[g] = 0;
      if (at.empty()) break;
      // A lone seed (the first, or the next after a region) is judged as
      // fit_patch judges, in stages, so that a simple surface costs no
      // more fits than the serial order.
      if (at.size() == 1) {
        pos = at[0] + 1;
        const bool found = fit_patch(st, rings[0]) || fit_patch(st, rings[1]);
        if (!found)
          for (index_t g : rings[1]) tried[g] = 1;
        batch = found ? 1 : std::min<std::size_t>(2 * batch, kMaxBatch);
        continue;
      }
      std::vector<const std::vector<index_t>*> sets;
      for (const std::vector<index_t>& r : rings) sets.push_back(&r);
      const std::vector<Verdict> verdicts = judge_sets(st, sets);
      pos = at.back() + 1;
      bool found = false;
      for (std::size_t k = 0; k < at.size() && !found; ++k) {
        // The 3-ring is only judged when the 2-ring gives no region, which
        // leaves the state, and so the 3-ring neighbourhood, unchanged.
        if (integrate_first(st, rings[2 * k], verdicts.data() + 2 * k * kTypes) ||
            integrate_first(st, rings[2 * k + 1], verdicts.data() + (2 * k + 1) * kTypes)) {
          pos = at[k] + 1;
          found = true;
        } else {
          for (index_t g : rings[2 * k + 1]) tried[g] = 1;
        }
      }
      batch = found ? 1 : std::min<std::size_t>(2 * batch, kMaxBatch);
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
