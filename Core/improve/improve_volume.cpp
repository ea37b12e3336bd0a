// Phase (3) of Phased ODT smoothing (thesis 2.6.5.4, Fig. 2.34): ODT
// smoothing of the inner vertices alternated with quality-raising flips.
#include "improve/improve_volume.h"

#include "improve/scan_live_tets.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <vector>

namespace femorph {

void live_stretch_range(const TetMesh& mesh, double* min_stretch, double* mean_stretch) {
  // Combined in chunk order: the mean does not depend on the number of
  // threads.
  struct Range {
    double lo = std::numeric_limits<double>::infinity(), sum = 0;
    std::size_t n = 0;
  };
  const std::vector<Range> ranges = scan_live_tets(mesh, Range{}, [&](index_t t, Range& r) {
    const Tet& T = mesh.tet(t);
    const double q = tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3]));
    r.lo = std::min(r.lo, q);
    r.sum += q;
    ++r.n;
  });
  double lo = std::numeric_limits<double>::infinity(), sum = 0;
  std::size_t n = 0;
  for (const Range& r : ranges) {
    lo = std::min(lo, r.lo);
    sum += r.sum;
    n += r.n;
  }
  if (min_stretch) *min_stretch = n ? lo : 0;
  if (mean_stretch) *mean_stretch = n ? sum / static_cast<double>(n) : 0;
}

ImproveVolumeStats improve_volume(TetMesh& mesh, const ImproveVolumeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ImproveVolumeStats stats;
  live_stretch_range(mesh, &stats.min_stretch_before, &stats.mean_stretch_before);
  FlipImproveOptions flip_options = options.flips;
  flip_options.vertex_mask = options.smooth.vertex_mask;
  for (int round = 0; round < options.rounds; ++round) {
    ++stats.rounds;
    const OdtSmoothReport smooth = odt_smooth_volume(mesh, options.smooth);
    const FlipImproveReport flips = improve_tets_by_flips(mesh, flip_options);
    stats.moved += smooth.moved;
    stats.refused += smooth.refused;
    stats.flips_23 += flips.flips_23;
    stats.flips_32 += flips.flips_32;
    stats.flips_44 += flips.flips_44;
    if (options.stop_when_converged && flips.total() == 0 && smooth.sweeps == 1 && smooth.converged) break;
  }
  live_stretch_range(mesh, &stats.min_stretch_after, &stats.mean_stretch_after);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace femorph
