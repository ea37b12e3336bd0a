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
    const std::vector<Vec3> points = st.positions(st.vertices_of(region.triangles));
    FitResult fit;
    if (region.type == SurfaceType::Plane) {
      fit = fit_plane(points, nullptr);
      if (fit.ok && fit.surface.axis.dot(region.surface.axis) < 0) fit.surface.axis = -fit.surface.axis;
    } else if (st.params.refine_fits) {
      fit = refine_fit_lm(region.surface, points);
    }
    // Keep the refinement only if it stays a plausible CAD surface.
    if (fit.ok && region.type != SurfaceType::Plane && !plausible_fit(st, fit.surface, region.triangles)) fit.ok = false;
    if (!fit.ok) fit = evaluate_fit(region.surface, points);
    else region.surface = fit.surface;
    region.fit_rms = fit.rms;
    region.fit_max = fit.max_abs;
    if (region.fit_max > st.tolerance) {
      std::ostringstream m;
      m << to_string(region.type) << " region " << r << ": largest vertex distance " << region.fit_max
        << " exceeds the tolerance " << st.tolerance;
      st.warnings.push_back(m.str());
    }
  }
}

}  // namespace segment
}  // namespace femorph
