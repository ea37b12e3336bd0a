#include "segment/normal_tensor_curvature.h"

namespace femorph {

// Thesis Eq. 2.6: sigma^2 = sum |v_eta - v_bar|^2 / |N|, v_bar the normalised
// sum of the v_eta. A zero sum leaves v_bar = 0 (variance = mean |v|^2).
double vector_variance(const Vec3* vectors, int count, bool unsigned_directions) {
  if (count <= 0) return 0.0;
  const Vec3& first = vectors[0];
  auto aligned = [&](int k) -> Vec3 {
    const Vec3& v = vectors[k];
    return unsigned_directions && v.dot(first) < 0 ? Vec3(-v) : v;
  };
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < count; ++k) sum += aligned(k);
  const double norm = sum.norm();
  const Vec3 mean = norm > 0 ? Vec3(sum / norm) : Vec3::Zero();
  double total = 0;
  for (int k = 0; k < count; ++k) total += (aligned(k) - mean).squaredNorm();
  return total / count;
}

}  // namespace femorph
