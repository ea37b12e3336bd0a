// Phase (3) of Phased ODT smoothing (thesis 2.6.5.4, Fig. 2.34): ODT
// smoothing of the inner vertices alternated with quality-raising flips.
#include "improve/improve_volume.h"

#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <vector>

namespace femorph {

void live_stretch_range(const TetMesh& mesh, double* min_stretch, double* mean_stretch) {
  // Per fixed chunk of tet slots, combined in chunk order: the mean does not
  // depend on the number of threads.
  constexpr long kChunk = 8192;
  const long slots = mesh.tet_slots(), chunks = (slots + kChunk - 1) / kChunk;
  std::vector<double> chunk_min(static_cast<std::size_t>(chunks), std::numeric_limits<double>::infinity()),
      chunk_sum(chunk_min.size(), 0.0);
  std::vector<std::size_t> chunk_count(chunk_min.size(), 0);
#pragma omp parallel for schedule(static) if (slots >= kParallelMinItems)
  for (long c = 0; c < chunks; ++c) {
    const std::size_t i = static_cast<std::size_t>(c);
    for (long k = c * kChunk; k < std::min(slots, (c + 1) * kChunk); ++k) {
      const index_t t = static_cast<index_t>(k);
      if (!mesh.tet_alive(t)) continue;
      const Tet& T = mesh.tet(t);
      const double q = tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3]));
      chunk_min[i] = std::min(chunk_min[i], q);
      chunk_sum[i] += q;
      ++chunk_count[i];
    }
  }
  double lo = std::numeric_limits<double>::infinity(), sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < chunk_min.size(); ++i) {
    lo = std::min(lo, chunk_min[i]);
    sum += chunk_sum[i];
    n += chunk_count[i];
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
