#include "geometry/fit_primitives.h"

#include <algorithm>
#include <cmath>

namespace femorph {

FitResult evaluate_fit(const SurfacePrimitive& surface, const std::vector<Vec3>& points) {
  FitResult result;
  result.surface = surface;
  if (surface.type == SurfaceType::Unknown || points.empty()) return result;
  double sum = 0, largest = 0;
  for (const Vec3& p : points) {
    const double d = signed_distance(surface, p);
    sum += d * d;
    largest = std::max(largest, std::abs(d));
  }
  result.rms = std::sqrt(sum / static_cast<double>(points.size()));
  result.max_abs = largest;
  result.inlier_count = static_cast<int>(points.size());
  result.ok = std::isfinite(result.rms);
  return result;
}

}  // namespace femorph
