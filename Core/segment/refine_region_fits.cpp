// Levenberg-Marquardt refinement, thesis 2.4.5 (A15), Eq. 2.8: every fitted
// region gets a final least-squares fit over all its vertices.
#include "segment/segmentation_state.h"

#include <sstream>

namespace femorph {
namespace segment {

void refine_region_fits(State& st) {
  for (std::size_t r = 0; r < st.regions.size(); ++r) {
    WorkRegion& region = st.regions[r];
    if (!region.alive || region.type == SurfaceType::Unknown) continue;
    // Over the inner vertices where boundary curves are approximate.
    FitResult fit;
    if (region.type == SurfaceType::Plane || st.params.refine_fits)
      fit = refit_region(st, region.type, region.surface, region.triangles);
    // Keep the refinement only if it stays a plausible CAD surface.
    if (fit.ok && region.type != SurfaceType::Plane && !plausible_fit(st, fit.surface, region.triangles)) fit.ok = false;
    if (!fit.ok) fit = evaluate_fit(region.surface, st.positions(st.vertices_of(region.triangles)));
    else region.surface = fit.surface;
    // The reported figures are over all vertices; the warning compares the
    // border vertices with their own tolerance (fit.max_abs is scaled).
    const FitResult all = evaluate_fit(region.surface, st.positions(st.vertices_of(region.triangles)));
    region.fit_rms = all.rms;
    region.fit_max = all.max_abs;
    if (fit.max_abs > st.tolerance) {
      std::ostringstream m;
      m << to_string(region.type) << " region " << r << ": largest vertex distance " << region.fit_max
        << " exceeds the tolerance " << st.tolerance;
      if (st.curve_tolerance > st.tolerance) m << " (" << st.curve_tolerance << " on boundary curves)";
      st.warnings.push_back(m.str());
    }
  }
}

}  // namespace segment
}  // namespace femorph
