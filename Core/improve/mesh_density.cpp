// Thesis 2.6.3 Eq. 2.32, Eq. 2.33 and 2.7.4 Eq. 2.35; see mesh_density.h.
#include "improve/mesh_density.h"

#include "common/parallel.h"
#include "mesh/tet_mesh.h"
#include "mesh/unique_edges.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>

namespace femorph {

namespace {

double signed_volume6(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a));
}

/// Fills the entries of `values` with known[i] == 0 layer by layer: an
/// unknown entry next to known ones (6-neighbourhood of a grid with
/// dims[0] x dims[1] x dims[2] entries) takes the mean of their values. A
/// layer's values come from the entries known before it and its members are
/// all the unqueued neighbours of the layer before, so neither depends on
/// the order in which the threads find them.
void fill_from_neighbours(const std::array<int, 3>& dims, std::vector<double>& values,
                          std::vector<char>& known) {
  const long total = static_cast<long>(dims[0]) * dims[1] * dims[2];
  const bool parallel = total >= kParallelMinItems;
  // The entries next to q across -x, +x, -y, +y, -z, +z (this order: the
  // sums below add in it), each passed to f; q split into (i, j, k) once.
  const long sy = dims[0], sz = static_cast<long>(dims[0]) * dims[1];
  const auto for_each_neighbour = [&](long q, auto&& f) {
    const long k = q / sz, rest = q - k * sz, j = rest / sy, i = rest - j * sy;
    if (i > 0) f(q - 1);
    if (i + 1 < dims[0]) f(q + 1);
    if (j > 0) f(q - sy);
    if (j + 1 < dims[1]) f(q + sy);
    if (k > 0) f(q - sz);
    if (k + 1 < dims[2]) f(q + sz);
  };
  std::vector<char> queued(known);
  std::vector<long> layer;
  // Layer 0: the unknown entries next to a known one.
  layer = parallel_reduce(
      total, std::vector<long>(),
      [&](long begin, long end, int) {
        std::vector<long> out;
        for (long q = begin; q < end; ++q) {
          if (known[static_cast<std::size_t>(q)]) continue;
          bool next_to_known = false;
          for_each_neighbour(q, [&](long r) { next_to_known = next_to_known || known[static_cast<std::size_t>(r)]; });
          if (next_to_known) out.push_back(q);
        }
        return out;
      },
      append<long>, parallel_when(parallel));
  for (const long q : layer) queued[static_cast<std::size_t>(q)] = 1;
  std::vector<double> layer_values;
  while (!layer.empty()) {
    const long layer_size = static_cast<long>(layer.size());
    const bool parallel_layer = layer_size >= kParallelMinItems;
    layer_values.assign(layer.size(), 0.0);
    parallel_for(
        layer_size,
        [&](long n) {
          double sum = 0;
          int count = 0;
          for_each_neighbour(layer[static_cast<std::size_t>(n)], [&](long r) {
            if (known[static_cast<std::size_t>(r)]) {
              sum += values[static_cast<std::size_t>(r)];
              ++count;
            }
          });
          layer_values[static_cast<std::size_t>(n)] = count ? sum / count : 0.0;
        },
        parallel_when(parallel_layer));
    parallel_for(
        layer_size,
        [&](long n) {
          const std::size_t q = static_cast<std::size_t>(layer[static_cast<std::size_t>(n)]);
          values[q] = layer_values[static_cast<std::size_t>(n)];
          known[q] = 1;
        },
        parallel_when(parallel_layer));
    // The next layer: the unqueued neighbours, each taken by one thread.
    layer = parallel_reduce(
        layer_size, std::vector<long>(),
        [&](long begin, long end, int) {
          std::vector<long> out;
          for (long n = begin; n < end; ++n)
            for_each_neighbour(layer[static_cast<std::size_t>(n)], [&](long r) {
              if (!__atomic_load_n(&queued[static_cast<std::size_t>(r)], __ATOMIC_RELAXED) &&
                  !__atomic_exchange_n(&queued[static_cast<std::size_t>(r)], char(1), __ATOMIC_RELAXED))
                out.push_back(r);
            });
          return out;
        },
        append<long>, parallel_when(parallel_layer));
  }
}

DensityError density_error_of(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                              const DensityGrid& grid, DensityLookup lookup) {
  DensityError out;
  if (grid.empty()) return out;
  const std::vector<Edge> edges = unique_edges(tets, static_cast<index_t>(points.size()));
  // Sums per fixed chunk of edges, added in chunk order: the mean does not
  // depend on the number of threads.
  constexpr long kChunk = 8192;
  const long n = static_cast<long>(edges.size()), chunks = (n + kChunk - 1) / kChunk;
  std::vector<double> chunk_sum(static_cast<std::size_t>(chunks), 0.0), chunk_max(chunk_sum.size(), 0.0);
  std::vector<std::size_t> chunk_count(chunk_sum.size(), 0);
  parallel_for_chunks(
      n,
      [&](long begin, long end, int) {
        const std::size_t i = static_cast<std::size_t>(begin / kChunk);
        for (long k = begin; k < end; ++k) {
          const Edge& e = edges[static_cast<std::size_t>(k)];
          const Vec3& a = points[e.first];
          const Vec3& b = points[e.second];
          const double length = (b - a).norm();
          const double rho = grid.density_at(0.5 * (a + b), lookup);
          if (!(length > 0) || !(rho > 0)) continue;
          const double eps = std::abs(1.0 / length - rho) / rho;  // Eq. 2.35
          chunk_sum[i] += eps;
          chunk_max[i] = std::max(chunk_max[i], eps);
          ++chunk_count[i];
        }
      },
      kParallelMinItems, kChunk);
  double sum = 0;
  for (std::size_t i = 0; i < chunk_sum.size(); ++i) {
    sum += chunk_sum[i];
    out.max = std::max(out.max, chunk_max[i]);
    out.edges += chunk_count[i];
  }
  out.mean = out.edges ? sum / static_cast<double>(out.edges) : 0.0;
  return out;
}

}  // namespace

std::vector<double> vertex_density(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                                   double* mean_length) {
  // Eq. 2.32: average of the reciprocals of the incident edge lengths.
  std::vector<double> sum(points.size(), 0.0);
  std::vector<int> count(points.size(), 0);
  const std::vector<Edge> edges = unique_edges(tets, static_cast<index_t>(points.size()));
  double length_sum = 0;
  for (const Edge& e : edges) {
    const index_t a = e.first, b = e.second;
    const double length = (points[b] - points[a]).norm();
    length_sum += length;
    if (!(length > 0)) continue;
    sum[a] += 1.0 / length;
    sum[b] += 1.0 / length;
    ++count[a];
    ++count[b];
  }
  for (std::size_t i = 0; i < points.size(); ++i) sum[i] = count[i] ? sum[i] / count[i] : 0.0;
  if (mean_length) *mean_length = edges.empty() ? 0.0 : length_sum / static_cast<double>(edges.size());
  return sum;
}

std::vector<double> vertex_density(const TetMesh& mesh) {
  return vertex_density(mesh.points(), live_tet_list(mesh));
}

double mean_edge_length(const std::vector<Vec3>& points, const std::vector<Tet>& tets) {
  const std::vector<Edge> edges = unique_edges(tets, static_cast<index_t>(points.size()));
  double sum = 0;
  for (const Edge& e : edges) sum += (points[e.second] - points[e.first]).norm();
  return edges.empty() ? 0.0 : sum / static_cast<double>(edges.size());
}

bool DensityGrid::build(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                        const std::vector<double>& densities, double cell_size, std::size_t max_points,
                        bool with_trilinear) {
  *this = DensityGrid();
  if (tets.empty() || densities.size() != points.size()) return false;
  if (!(cell_size > 0)) cell_size = 0.5 * mean_edge_length(points, tets);
  if (!(cell_size > 0) || !std::isfinite(cell_size)) return false;

  // A regular grid covering the deformed mesh (Fig. 2.40 (b)).
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  for (const Tet& t : tets)
    for (const index_t v : t) {
      lo = lo.cwiseMin(points[v]);
      hi = hi.cwiseMax(points[v]);
    }
  std::array<int, 3> n{{1, 1, 1}};
  std::size_t total = 1;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::ceil((hi[a] - lo[a]) / cell_size - 1e-9);
    if (!(cells < 1e7)) return false;
    n[a] = std::max(1, static_cast<int>(cells));
    total *= static_cast<std::size_t>(n[a]) + 1;
    if (total > max_points) return false;
  }
  origin_ = lo;
  h_ = cell_size;
  n_ = n;
  raw_points_.assign(total, 0.0);
  std::vector<char> known(total, 0);

  // Eq. 2.33: each grid point g in tet tau_g takes
  // sum_i V(tau_g^i) rho_i / V(tau_g), tau_g^i being tau_g with vertex i
  // replaced by g (barycentric interpolation). A grid point on a face
  // shared by two tets takes the value from the tet listed first: the tets
  // are scanned in parallel for the first one that gives each grid point a
  // value, then each grid point is evaluated in that tet.
  constexpr double kTol = 1e-9;
  // The value tet t gives grid point (i, j, k): > 0, or 0 when it gives none.
  const auto value_in = [&](const Tet& t, int i, int j, int k) {
    const Vec3 p[4] = {points[t[0]], points[t[1]], points[t[2]], points[t[3]]};
    const double volume = signed_volume6(p[0], p[1], p[2], p[3]);
    const Vec3 x = origin_ + h_ * Vec3(i, j, k);
    double lambda[4];
    for (int q = 0; q < 4; ++q) {
      Vec3 r[4] = {p[0], p[1], p[2], p[3]};
      r[q] = x;
      lambda[q] = signed_volume6(r[0], r[1], r[2], r[3]) / volume;
      if (!(lambda[q] >= -kTol)) return 0.0;
    }
    double value = 0, weight = 0;
    for (int q = 0; q < 4; ++q)
      if (densities[t[q]] > 0) {
        value += lambda[q] * densities[t[q]];
        weight += lambda[q];
      }
    if (!(weight > 0)) return 0.0;
    return std::max(value / weight, 0.0);
  };
  const long ntets = static_cast<long>(tets.size());
  std::vector<std::atomic<index_t>> owner(total);
  const long ntotal = static_cast<long>(total);
  parallel_for(ntotal,
               [&](long g) { owner[static_cast<std::size_t>(g)].store(kInvalidIndex, std::memory_order_relaxed); });
  parallel_for(
      ntets,
      [&](long ti) {
        const Tet& t = tets[static_cast<std::size_t>(ti)];
        const Vec3 p[4] = {points[t[0]], points[t[1]], points[t[2]], points[t[3]]};
        const double volume = signed_volume6(p[0], p[1], p[2], p[3]);
        if (volume == 0 || !std::isfinite(volume)) return;
        Vec3 tlo = p[0], thi = p[0];
        for (int q = 1; q < 4; ++q) {
          tlo = tlo.cwiseMin(p[q]);
          thi = thi.cwiseMax(p[q]);
        }
        int i0[3], i1[3];
        for (int a = 0; a < 3; ++a) {
          i0[a] = std::max(0, static_cast<int>(std::ceil((tlo[a] - origin_[a]) / h_ - kTol)));
          i1[a] = std::min(n_[a], static_cast<int>(std::floor((thi[a] - origin_[a]) / h_ + kTol)));
        }
        // Barycentric coordinates as an affine function of the grid point: a
        // cheap first test that skips most of the box (a tet fills a sixth of
        // it or less). Its tolerance is loose and it is left out for flat tets
        // (6V / L^3 < 1e-4), so value_in alone decides which points are inside.
        Eigen::Matrix3d edges;
        edges << p[1] - p[0], p[2] - p[0], p[3] - p[0];
        const double longest = std::max({edges.col(0).norm(), edges.col(1).norm(), edges.col(2).norm(),
                                         (p[2] - p[1]).norm(), (p[3] - p[1]).norm(), (p[3] - p[2]).norm()});
        const bool prefilter = std::abs(volume) > 1e-4 * longest * longest * longest;
        const Eigen::Matrix3d to_bary = prefilter ? Eigen::Matrix3d(edges.inverse()) : Eigen::Matrix3d::Zero();
        constexpr double kLoose = 1e-6;
        for (int k = i0[2]; k <= i1[2]; ++k)
          for (int j = i0[1]; j <= i1[1]; ++j)
            for (int i = i0[0]; i <= i1[0]; ++i) {
              if (prefilter) {
                const Vec3 l = to_bary * (origin_ + h_ * Vec3(i, j, k) - p[0]);
                if (!(l.minCoeff() >= -kLoose && l.sum() <= 1 + kLoose)) continue;
              }
              std::atomic<index_t>& o = owner[point_id(i, j, k)];
              index_t current = o.load(std::memory_order_relaxed);
              if (current != kInvalidIndex && current < ti) continue;
              if (!(value_in(t, i, j, k) > 0)) continue;
              while ((current == kInvalidIndex || current > ti) &&
                     !o.compare_exchange_weak(current, static_cast<index_t>(ti), std::memory_order_relaxed)) {
              }
            }
      },
      kParallelMinItems, 1024);
  const int row = n_[0] + 1, rows = (n_[1] + 1) * (n_[2] + 1);
  parallel_for(
      rows,
      [&](long rl) {
        const int r = static_cast<int>(rl);
        for (int i = 0; i < row; ++i) {
          const int j = r % (n_[1] + 1), k = r / (n_[1] + 1);
          const std::size_t g = point_id(i, j, k);
          const index_t t = owner[g].load(std::memory_order_relaxed);
          if (t == kInvalidIndex) continue;
          raw_points_[g] = value_in(tets[static_cast<std::size_t>(t)], i, j, k);
          known[g] = 1;
        }
      },
      parallel_when(ntotal >= kParallelMinItems));
  if (std::find(known.begin(), known.end(), 1) == known.end()) {
    *this = DensityGrid();
    return false;
  }

  // Trilinear lookup: grid points outside the mesh take their neighbours'.
  if (with_trilinear) {
    filled_points_ = raw_points_;
    std::vector<char> filled_known = known;
    fill_from_neighbours({{n_[0] + 1, n_[1] + 1, n_[2] + 1}}, filled_points_, filled_known);
  }

  // rho_GC: the average of the nonzero densities of the cell's corners;
  // cells without any take their neighbour cells' values.
  cell_values_.assign(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2], 0.0);
  std::vector<char> cell_known(cell_values_.size(), 0);
  const int cell_rows = n_[1] * n_[2];
  parallel_for(
      cell_rows,
      [&](long rl) {
        const int r = static_cast<int>(rl);
        for (int i = 0; i < n_[0]; ++i) {
          const int j = r % n_[1], k = r / n_[1];
          double sum = 0;
          int count = 0;
          for (int c = 0; c < 8; ++c) {
            const double v = raw_points_[point_id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))];
            if (v > 0) {
              sum += v;
              ++count;
            }
          }
          if (count) {
            cell_values_[cell_id(i, j, k)] = sum / count;
            cell_known[cell_id(i, j, k)] = 1;
          }
        }
      },
      parallel_when(static_cast<long>(cell_values_.size()) >= kParallelMinItems));
  fill_from_neighbours(n_, cell_values_, cell_known);
  return true;
}

double DensityGrid::density_at(const Vec3& p, DensityLookup lookup) const {
  if (empty()) return 0.0;
  int c[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    double t = (p[a] - origin_[a]) / h_;
    if (!(t > 0)) t = 0;  // also NaN
    if (t > n_[a]) t = n_[a];
    c[a] = std::min(static_cast<int>(std::floor(t)), n_[a] - 1);
    f[a] = t - c[a];
  }
  if (lookup == DensityLookup::Cell || filled_points_.empty()) return cell_values_[cell_id(c[0], c[1], c[2])];
  double value = 0;
  for (int q = 0; q < 8; ++q) {
    const int dx = q & 1, dy = (q >> 1) & 1, dz = (q >> 2) & 1;
    const double w = (dx ? f[0] : 1 - f[0]) * (dy ? f[1] : 1 - f[1]) * (dz ? f[2] : 1 - f[2]);
    value += w * filled_points_[point_id(c[0] + dx, c[1] + dy, c[2] + dz)];
  }
  return value;
}

DensityError mean_density_error(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                                const DensityGrid& grid, DensityLookup lookup) {
  return density_error_of(points, tets, grid, lookup);
}

DensityError mean_density_error(const TetMesh& mesh, const DensityGrid& grid, DensityLookup lookup) {
  return density_error_of(mesh.points(), live_tet_list(mesh), grid, lookup);
}

}  // namespace femorph
