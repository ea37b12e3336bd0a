// Boundary re-estimation, thesis 2.4.4: the thesis compares, for boundary
// triangles of a torus region's neighbours, the distances to both fitted
// surfaces and gives each to the closer. Applied here to every region border,
// since growing order decides ties at G1 boundaries (a triangle along a
// tangent line lies within tolerance of both surfaces).
#include "segment/segmentation_state.h"

#include <algorithm>

namespace femorph {
namespace segment {

namespace {

/// How many of the triangle's vertices lie exactly on s (within
/// State::exact_tolerance, the mesh's own precision: a small fit that passes
/// near a face's vertices does not count as explaining them); 0 for all
/// while boundary curves are as exact as the rest (the distances alone
/// decide).
int exact_count(const State& st, const SurfacePrimitive& s, index_t f) {
  if (!(st.curve_tolerance > st.tolerance)) return 0;
  int n = 0;
  const double exact = st.exact_tolerance();
  for (index_t v : st.surface.triangles[f]) n += distance(s, st.surface.points[v]) <= exact;
  return n;
}

/// Where boundary curves are approximate: the distances of the triangle to
/// surfaces a and b over its vertices exactly on either
/// (those inside a face; a vertex on an approximate curve is off both and
/// tells nothing). Left as they are when there is no such vertex.
void exact_distances(const State& st, const SurfacePrimitive& a, const SurfacePrimitive& b, index_t f, double& da,
                     double& db) {
  const double exact = st.exact_tolerance();
  double ma = 0, mb = 0;
  bool any = false;
  for (index_t v : st.surface.triangles[f]) {
    const double ea = distance(a, st.surface.points[v]), eb = distance(b, st.surface.points[v]);
    if (std::min(ea, eb) > exact) continue;
    ma = std::max(ma, ea);
    mb = std::max(mb, eb);
    any = true;
  }
  if (!any) return;
  da = ma;
  db = mb;
}

/// One re-estimation over the current fits: border triangles move to the
/// neighbour that explains them clearly better, the border advancing one
/// triangle per round. Marks the regions that lost or gained triangles in
/// `changed`; returns whether any moved.
bool move_border_triangles(State& st, std::vector<char>& changed) {
  const SurfaceMesh& s = st.surface;
  const index_t nf = s.num_triangles();
  // Work lists of border triangles only: a move changes the border around
  // the moved triangle, so its neighbours are the next candidates. Moving a
  // border by one triangle per round, this peels a strip that a neighbouring
  // fit took off an exact surface.
  constexpr int kMaxRounds = 64;
  std::vector<index_t> candidates, next;
  std::vector<char> queued(static_cast<std::size_t>(nf), 0);
  std::vector<index_t> size(st.regions.size(), 0);
  for (index_t f = 0; f < nf; ++f) {
    const index_t r = st.triangle_region[f];
    if (r < 0) continue;
    ++size[r];
    for (int k = 0; k < 3; ++k) {
      const index_t g = s.neighbors[f][k];
      if (g >= 0 && st.triangle_region[g] != r) {
        candidates.push_back(f);
        break;
      }
    }
  }
  bool any = false;
  for (int round = 0; round < kMaxRounds && !candidates.empty(); ++round) {
    next.clear();
    for (index_t f : candidates) queued[f] = 0;
    for (index_t f : candidates) {
      const index_t own = st.triangle_region[f];
      if (own < 0) continue;
      const WorkRegion& mine = st.regions[own];
      index_t best = own;
      double d_best = 1e300;
      int exact_best = -1;
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0) continue;
        const index_t other = st.triangle_region[g];
        if (other < 0 || other == own || other == best) continue;
        const WorkRegion& o = st.regions[other];
        if (o.type == SurfaceType::Unknown || !st.triangle_near(o.surface, f)) continue;
        double d = st.triangle_distance(o.surface, f);
        double d_own = mine.type == SurfaceType::Unknown ? 1e300 : st.triangle_distance(mine.surface, f);
        if (st.curve_tolerance > st.tolerance && mine.type != SurfaceType::Unknown)
          exact_distances(st, o.surface, mine.surface, f, d, d_own);
        // Where boundary curves are approximate, a triangle's vertices on
        // them lie off both surfaces: the surface with more of its vertices
        // exactly on it (inside the face) explains it, and the
        // distances decide between equal counts.
        const int exact = exact_count(st, o.surface, f);
        const int exact_own = mine.type == SurfaceType::Unknown ? 0 : exact_count(st, mine.surface, f);
        if (exact < exact_own || exact < exact_best) continue;
        // Clearly closer: the margin keeps exact ties (both 0) where they are.
        if (exact > exact_own || (d < 0.5 * d_own && (exact > exact_best || d < d_best))) {
          best = other;
          d_best = d;
          exact_best = exact;
        }
      }
      if (best == own) continue;
      // Do not empty a fitted region (an unknown one may vanish).
      if (mine.type != SurfaceType::Unknown && size[own] <= 1) continue;
      st.triangle_region[f] = best;
      changed[own] = changed[best] = 1;
      --size[own];
      ++size[best];
      any = true;
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g >= 0 && !queued[g]) {
          queued[g] = 1;
          next.push_back(g);
        }
      }
    }
    candidates.swap(next);
  }
  if (!any) return false;
  // Rebuild the triangle lists from the assignment.
  for (WorkRegion& r : st.regions) r.triangles.clear();
  for (index_t f = 0; f < nf; ++f)
    if (st.triangle_region[f] >= 0) st.regions[st.triangle_region[f]].triangles.push_back(f);
  for (WorkRegion& r : st.regions) r.alive = r.alive && !r.triangles.empty();
  return true;
}

}  // namespace

void reestimate_region_boundaries(State& st) {
  std::vector<char> changed(st.regions.size(), 0);
  if (!(st.curve_tolerance > st.tolerance)) {
    move_border_triangles(st, changed);
    return;
  }
  // At first each region is fitted as it is (thesis 2.4.4). Where boundary
  // curves are approximate the fits of growth (of a partial region, and of a
  // narrow face over all its vertices) are not exact, and the comparison
  // counts exact vertices; a fit bent by a neighbour's triangles comes
  // exact once they have moved out: refit the changed regions and compare
  // again, a few times.
  constexpr int kMaxPasses = 3;
  changed.assign(st.regions.size(), 1);
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    for (std::size_t i = 0; i < st.regions.size(); ++i) {
      WorkRegion& r = st.regions[i];
      if (!changed[i] || !r.alive || r.type == SurfaceType::Unknown) continue;
      const FitResult fit = refit_region(st, r.type, r.surface, r.triangles);
      if (fit.ok && plausible_fit(st, fit.surface, r.triangles)) r.surface = fit.surface;
    }
    changed.assign(st.regions.size(), 0);
    if (!move_border_triangles(st, changed)) break;
  }
}

}  // namespace segment
}  // namespace femorph
