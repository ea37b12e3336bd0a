// ODT vertex repositioning, thesis Eq. 2.31 with the barycentre rule of
// Fig. 2.33 (b) and 2.6.5.4, step size halved against inversion.
#include "improve/ball_quality.h"
#include "improve/odt_smooth_volume.h"

#include "common/parallel.h"
#include "improve/coloured_balls.h"
#include "improve/locally_delaunay.h"
#include "improve/relax_edge_lengths.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <functional>
#include <memory>

namespace femorph {

namespace {

/// Eq. 2.31: the step from v to the density-weighted mean of the centres
/// c_tau of its ball, and v's mean edge length (counted per tet); false
/// when the ball has no volume.
bool odt_centre_step(const TetMesh& mesh, const std::vector<index_t>& ball, index_t v,
                     const std::vector<std::uint8_t>& circumcentre, const OdtSmoothOptions& options, bool vertex_rho,
                     Vec3* step, double* mean_length) {
  const Vec3 x = mesh.point(v);
  Vec3 sum_c = Vec3::Zero();
  double sum_w = 0, sum_len = 0;
  int n_len = 0;
  for (const index_t t : ball) {
    const Tet& T = mesh.tet(t);
    const Vec3 &a = mesh.point(T[0]), &b = mesh.point(T[1]), &cc = mesh.point(T[2]), &d = mesh.point(T[3]);
    const Vec3 bary = (a + b + cc + d) / 4;
    const double volume = tet_signed_volume(a, b, cc, d);
    double rho = 1;
    if (options.density)
      rho = options.density(bary);
    else if (vertex_rho)
      rho = (options.vertex_density[T[0]] + options.vertex_density[T[1]] + options.vertex_density[T[2]] +
             options.vertex_density[T[3]]) / 4;
    for (const index_t w : T)
      if (w != v) {
        sum_len += (mesh.point(w) - x).norm();
        ++n_len;
      }
    // Barycentre for tets with a boundary vertex (Fig. 2.33 (b)) and
    // for tets that are not Delaunay (2.6.5.4); circumcentre otherwise.
    Vec3 centre = bary;
    if (circumcentre[t] && !tet_circumcentre(a, b, cc, d, &centre)) centre = bary;
    // Eq. 2.31 with rho = 1 (volume weights), not the equal weights
    // of Eq. 2.34: equal weights give a slightly higher mean stretch
    // but left a real part (fandisk, inner vertices jittered,
    // smoothing and flips only) below a minimum stretch of 0.2.
    const double weight = volume * rho;
    sum_c += weight * centre;
    sum_w += weight;
  }
  if (!(sum_w > 0) || n_len == 0) return false;
  *step = sum_c / sum_w - x;
  *mean_length = sum_len / n_len;
  return true;
}

/// What a sweep over the vertices did.
struct Sweep {
  double max_step = 0;
  std::size_t moved = 0, refused = 0, halvings = 0;
};

Sweep add_sweeps(Sweep a, const Sweep& b) {
  a.max_step = std::max(a.max_step, b.max_step);
  a.moved += b.moved;
  a.refused += b.refused;
  a.halvings += b.halvings;
  return a;
}

/// Per-thread buffers of a sweep.
struct BallScratch {
  std::vector<index_t> ball, neighbours;
  std::vector<double> new_stretch;
};

}  // namespace

OdtSmoothReport odt_smooth_volume(TetMesh& mesh, const OdtSmoothOptions& options) {
  OdtSmoothReport report;
  const bool vertex_rho = !options.density && !options.vertex_density.empty();
  const ColouredBalls cb = coloured_balls(mesh, options.vertex_mask);
  const std::size_t n = cb.vertices.size();
  if (n == 0) return report;
  // Active set (per entry of cb.vertices): visit in this sweep; moved far.
  std::vector<std::uint8_t> active(n, 1), moved_far(n, 0);
  std::vector<BallScratch> scratch(static_cast<std::size_t>(parallel_threads()));
  std::vector<index_t> entry(static_cast<std::size_t>(mesh.vertex_slots()), kInvalidIndex);
  for (std::size_t j = 0; j < n; ++j) entry[cb.vertices[j]] = static_cast<index_t>(j);
  // Per tet, for this sweep: 1 when its centre c_tau is the circumcentre
  // (no boundary vertex, locally Delaunay at the sweep's start), 0 for the
  // barycentre. Computed once per sweep instead of once per ball visit
  // (four times per tet), and read-only while the colours move in parallel.
  std::vector<std::uint8_t> circumcentre(static_cast<std::size_t>(mesh.tet_slots()), 0), needed(circumcentre.size(), 0);
  // With the quality guard, per tet of the active balls: its stretch, found
  // at the sweep's start and kept current as vertices move (a move writes
  // the stretches its guard found), so a ball's minimum is read, not
  // computed (the same values as computing it).
  const bool keep_stretch = options.quality_guard;
  std::vector<double> stretch_of_tet(keep_stretch ? circumcentre.size() : 0, 0.0);
  std::vector<index_t> needed_list;

  for (int sweep = 0; sweep < options.iterations; ++sweep) {
    ++report.sweeps;
    if (sweep > 0 && options.active_tolerance > 0) {
      std::fill(active.begin(), active.end(), 0);
      for (std::size_t j = 0; j < n; ++j) {
        if (!moved_far[j]) continue;
        for (std::size_t k = cb.ball_start[j]; k < cb.ball_start[j + 1]; ++k)
          for (const index_t w : mesh.tet(cb.ball_tets[k]))
            if (entry[w] >= 0) active[entry[w]] = 1;
      }
    }
    std::fill(moved_far.begin(), moved_far.end(), 0);
    needed_list.clear();
    for (std::size_t j = 0; j < n; ++j) {
      if (!active[j]) continue;
      for (std::size_t k = cb.ball_start[j]; k < cb.ball_start[j + 1]; ++k) {
        const index_t t = cb.ball_tets[k];
        if (needed[t]) continue;
        needed[t] = 1;
        needed_list.push_back(t);
      }
    }
    const long num_needed = static_cast<long>(needed_list.size());
    parallel_for(num_needed, [&](long i) {
      const index_t t = needed_list[static_cast<std::size_t>(i)];
      bool boundary = false;
      for (const index_t w : mesh.tet(t)) boundary = boundary || mesh.on_boundary(w);
      circumcentre[t] = !options.edge_density && !boundary && locally_delaunay(mesh, t);
      if (keep_stretch) {
        const Tet& T = mesh.tet(t);
        stretch_of_tet[t] = tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3]));
      }
    });
    for (const index_t t : needed_list) needed[t] = 0;

    Sweep done;
    for (std::size_t c = 0; c + 1 < cb.colour_start.size(); ++c) {
      const long first = static_cast<long>(cb.colour_start[c]), last = static_cast<long>(cb.colour_start[c + 1]);
      const auto chunk = [&](long begin, long end, int worker) {
        Sweep k;
        std::vector<index_t>& ball = scratch[static_cast<std::size_t>(worker)].ball;
        std::vector<index_t>& neighbours = scratch[static_cast<std::size_t>(worker)].neighbours;
        std::vector<double>& new_stretch = scratch[static_cast<std::size_t>(worker)].new_stretch;
        for (long j = first + begin; j < first + end; ++j) {
          if (!active[j]) continue;
          const index_t v = cb.vertices[j];
          ball.assign(cb.ball_tets.begin() + static_cast<std::ptrdiff_t>(cb.ball_start[j]),
                      cb.ball_tets.begin() + static_cast<std::ptrdiff_t>(cb.ball_start[j + 1]));
          const Vec3 x = mesh.point(v);

          Vec3 step;
          double length;
          if (options.edge_density
                  ? !spring_rest(mesh, ball, v, options.edge_density, neighbours, &step, &length)
                  : !odt_centre_step(mesh, ball, v, circumcentre, options, vertex_rho, &step, &length))
            continue;
          const double relative = step.norm() / length;
          if (!std::isfinite(relative) || relative <= options.tolerance * 1e-3) continue;  // already there

          // Fig. 2.33 step-size rule: alpha = 1, halved while the move inverts
          // a tet (or, with the guard, lowers the ball's minimum stretch).
          std::size_t h = 0;
          const auto candidate = [&](double a, Vec3* p) {
            *p = x + a * step;
            return true;
          };
          double alpha;
          if (keep_stretch) {
            double old_min = std::numeric_limits<double>::infinity();
            for (const index_t t : ball) old_min = std::min(old_min, stretch_of_tet[t]);
            if (options.guard_drop > 0)
              old_min = std::min(old_min, std::max(options.guard_keep, (1 - options.guard_drop) * old_min));
            alpha = move_with_step_halving(
                mesh, ball, v, options.max_halvings, true, options.quality_floor, old_min, candidate,
                [](const Vec3&) { return true; }, &new_stretch, &h);
            // Vertices of one colour share no tet: these tets are this vertex's.
            if (alpha > 0)
              for (std::size_t k = 0; k < ball.size(); ++k) stretch_of_tet[ball[k]] = new_stretch[k];
          } else {
            alpha = move_with_step_halving(mesh, ball, v, options.max_halvings, false, options.quality_floor,
                                           candidate, &h);
          }
          k.halvings += h;
          if (alpha > 0) {
            ++k.moved;
            k.max_step = std::max(k.max_step, alpha * relative);
            moved_far[j] = alpha * relative > options.active_tolerance;
          } else {
            ++k.refused;
          }
        }
        return k;
      };
      done = parallel_reduce(last - first, done, chunk, add_sweeps, 2048, 256);
    }
    const double max_step = done.max_step;
    const std::size_t moved = done.moved, refused = done.refused, halvings = done.halvings;
    report.moved += moved;
    report.refused += refused;
    report.halvings += halvings;
    report.last_max_step = max_step;
    if (max_step <= options.tolerance) {
      report.converged = true;
      break;
    }
    if (options.active_tolerance <= 0) std::fill(active.begin(), active.end(), 1);
  }
  return report;
}

}  // namespace femorph
