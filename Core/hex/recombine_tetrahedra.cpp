// Tet To Hex, thesis 4.5 (Fig. 4.7): A1 (local search on the extended
// RF-graph) then A2 (greedy conversion), plus the checks of the input, the
// minimum scaled Jacobian filter, the optional removal of non-conformal
// cells, and the output cells in VTK's node orders.
#include "hex/tet_to_hex.h"
#include "common/parallel.h"

#include "geometry/predicates.h"
#include "hex/tet_to_hex_internal.h"
#include "quality/tet_quality.h"

#include <utility>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>

namespace femorph {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

Status recombine_tetrahedra(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                            const TetToHexParams& params, TetToHexResult& result) {
  using namespace tet_to_hex;
  const auto start = std::chrono::steady_clock::now();
  result = TetToHexResult();
  // Progress: the share of each step in [0, 1].
  bool stopped = false;
  auto report = [&params, &stopped](double fraction, const char* step) {
    stopped = stopped || (params.progress && !params.progress(fraction, step));
    return !stopped;
  };
  const Status aborted = Status::failure("aborted");
  if (!report(0.0, "checking the mesh")) return aborted;
  if (!(params.quad_angle_deg >= 0 && params.quad_angle_deg <= 180))
    return Status::failure("the quad angle must be in [0, 180] degrees; it is " +
                           std::to_string(params.quad_angle_deg));
  if (!(params.min_scaled_jacobian >= -1 && params.min_scaled_jacobian <= 1))
    return Status::failure("the minimum scaled Jacobian must be in [-1, 1]; it is " +
                           std::to_string(params.min_scaled_jacobian));
  if (points.size() > static_cast<std::size_t>(std::numeric_limits<index_t>::max()))
    return Status::failure("too many points (" + std::to_string(points.size()) + ")");

  // The input: finite points, a conforming mesh of positive tets.
  const std::ptrdiff_t np = static_cast<std::ptrdiff_t>(points.size());
  for (std::ptrdiff_t i = 0; i < np; ++i)
    if (!points[i].allFinite())
      return Status::failure("point " + std::to_string(i) + " has a NaN or infinite coordinate");
  std::vector<index_t> adjacency;
  Status status = build_tet_adjacency(static_cast<index_t>(points.size()), tets, adjacency);
  if (!status) return status;
  const std::ptrdiff_t nt = static_cast<std::ptrdiff_t>(tets.size());
  using Bad = std::pair<std::int64_t, std::int64_t>;  // count, first
  const Bad bad = parallel_reduce(
      static_cast<long>(nt), Bad(0, std::numeric_limits<std::int64_t>::max()),
      [&](long begin, long end, int) {
        Bad k(0, std::numeric_limits<std::int64_t>::max());
        for (long t = begin; t < end; ++t) {
          const Tet& v = tets[static_cast<std::size_t>(t)];
          if (orient3d_sign(points[v[0]], points[v[1]], points[v[2]], points[v[3]]) <= 0) {
            ++k.first;
            k.second = std::min<std::int64_t>(k.second, t);
          }
        }
        return k;
      },
      [](Bad a, Bad b) { return Bad(a.first + b.first, std::min(a.second, b.second)); });
  const std::int64_t not_positive = bad.first, first = bad.second;
  if (not_positive > 0)
    return Status::failure(std::to_string(not_positive) +
                           (not_positive == 1 ? " tetrahedron is" : " tetrahedra are") +
                           " inverted or flat (the first is " + std::to_string(first) +
                           "); Tet To Hex needs positive tetrahedra (VTK_TETRA's order)");
  TetToHexStats& stats = result.stats;
  stats.seconds_adjacency = seconds_since(start);

  // A1, then the max-heap of Eq. 4.1.
  if (!report(0.1, "searching candidates")) return aborted;
  const auto search_start = std::chrono::steady_clock::now();
  std::vector<Candidate> candidates;
  std::function<bool(double)> search_progress;
  if (params.progress)
    search_progress = [&report](double f) { return report(0.1 + 0.6 * f, "searching candidates"); };
  if (!search_candidates(points, tets, adjacency, params, candidates, stats, search_progress)) {
    result = TetToHexResult();
    return aborted;
  }
  if (!report(0.7, "sorting candidates")) {
    result = TetToHexResult();
    return aborted;
  }
  sort_candidates(candidates);
  stats.seconds_search = seconds_since(search_start);

  // A2, and the removal of non-conformal cells when asked.
  if (!report(0.75, "adopting candidates")) {
    result = TetToHexResult();
    return aborted;
  }
  const auto adopt_start = std::chrono::steady_clock::now();
  std::vector<Cell> cells;
  std::vector<index_t> cell_of_tet;
  adopt_candidates_greedy(candidates, points, tets, adjacency, cells, cell_of_tet);
  if (params.refuse_nonconformal) {
    if (!report(0.85, "dissolving non-conformal cells")) {
      result = TetToHexResult();
      return aborted;
    }
    stats.dissolved_nonconformal =
        dissolve_nonconformal_cells(candidates, points, tets, adjacency, cells, cell_of_tet);
  }
  stats.nonconformal_interfaces = count_nonconformal_interfaces(cells, cell_of_tet, tets, adjacency);
  std::vector<Candidate>().swap(candidates);
  if (!report(0.95, "writing the cells")) {
    result = TetToHexResult();
    return aborted;
  }

  // Output: hexahedra, wedges, pyramids (each by smallest source tet), then
  // the tets left, in input order.
  std::vector<index_t> order;
  for (std::size_t c = 0; c < cells.size(); ++c)
    if (cells[c].alive) order.push_back(static_cast<index_t>(c));
  auto rank = [](CellKind k) { return k == CellKind::Hexahedron ? 0 : k == CellKind::Wedge ? 1 : 2; };
  std::sort(order.begin(), order.end(), [&](index_t a, index_t b) {
    if (cells[a].kind != cells[b].kind) return rank(cells[a].kind) < rank(cells[b].kind);
    return cells[a].tets[0] < cells[b].tets[0];
  });
  MixedCells& out = result.cells;
  auto add_tet_volume = [&](CellKind kind, index_t t) {
    const Tet& v = tets[t];
    const double volume = tet_signed_volume(points[v[0]], points[v[1]], points[v[2]], points[v[3]]);
    stats.volume[static_cast<int>(kind)] += volume;
    stats.total_volume += volume;
  };
  for (index_t c : order) {
    const Cell& cell = cells[c];
    out.add(cell.kind, cell.nodes.data());
    for (int k = 0; k < cell.num_tets; ++k) {
      result.source_tets.push_back(cell.tets[k]);
      add_tet_volume(cell.kind, cell.tets[k]);
    }
    result.source_offsets.push_back(static_cast<index_t>(result.source_tets.size()));
  }
  for (index_t t = 0; t < static_cast<index_t>(nt); ++t) {
    if (cell_of_tet[t] != kInvalidIndex) continue;
    out.add(CellKind::Tetra, tets[t].data());
    result.source_tets.push_back(t);
    result.source_offsets.push_back(static_cast<index_t>(result.source_tets.size()));
    add_tet_volume(CellKind::Tetra, t);
  }
  const std::ptrdiff_t nc = out.size();
  result.min_scaled_jacobian.resize(static_cast<std::size_t>(nc));
  parallel_for_chunks(
      static_cast<long>(nc),
      [&](long begin, long end, int) {
        for (std::ptrdiff_t c = static_cast<std::ptrdiff_t>(begin); c < static_cast<std::ptrdiff_t>(end); ++c) {
          Vec3 corners[kMaxNodes];
          const index_t* nodes = out.nodes(static_cast<index_t>(c));
          for (index_t k = 0; k < out.node_count(static_cast<index_t>(c)); ++k) corners[k] = points[nodes[k]];
          result.min_scaled_jacobian[c] = min_scaled_jacobian(out.kinds[c], corners);
        }
      },
      kParallelMinItems);
  for (CellKind kind : out.kinds) ++stats.cells[static_cast<int>(kind)];
  stats.seconds_adopt = seconds_since(adopt_start);
  stats.seconds_total = seconds_since(start);
  report(1.0, "done");
  return Status::success();
}

}  // namespace femorph
