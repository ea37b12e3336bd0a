// ODT vertex repositioning, thesis Eq. 2.31 with the barycentre rule of
// Fig. 2.33 (b) and 2.6.5.4, step size halved against inversion.
#include "improve/ball_quality.h"
#include "improve/odt_smooth_volume.h"

#include "improve/locally_delaunay.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace femorph {

OdtSmoothReport odt_smooth_volume(TetMesh& mesh, const OdtSmoothOptions& options) {
  OdtSmoothReport report;
  const index_t slots = mesh.vertex_slots();
  const bool use_mask = !options.vertex_mask.empty();
  const bool vertex_rho = !options.density && !options.vertex_density.empty();
  std::vector<index_t> ball;
  // Active set: bit 0 = visit in this sweep, bit 1 = in the next one.
  std::vector<std::uint8_t> active(static_cast<std::size_t>(slots), 1);

  for (int sweep = 0; sweep < options.iterations; ++sweep) {
    ++report.sweeps;
    double max_step = 0;
    if (sweep > 0 && options.active_tolerance > 0)
      for (auto& a : active) a = (a & 2) ? 1 : 0;
    for (index_t v = 0; v < slots; ++v) {
      if (!(active[v] & 1) || !mesh.vertex_alive(v) || mesh.vertex_class(v) != VertexClass::Inner) continue;
      if (use_mask && (static_cast<std::size_t>(v) >= options.vertex_mask.size() || !options.vertex_mask[v])) continue;
      mesh.vertex_ball(v, ball);
      const Vec3 x = mesh.point(v);

      // Eq. 2.31: density-weighted mean of the centres c_tau.
      Vec3 sum_c = Vec3::Zero();
      double sum_w = 0, sum_len = 0;
      int n_len = 0;
      for (index_t t : ball) {
        const Tet& T = mesh.tet(t);
        const Vec3 &a = mesh.point(T[0]), &b = mesh.point(T[1]), &c = mesh.point(T[2]), &d = mesh.point(T[3]);
        const Vec3 bary = (a + b + c + d) / 4;
        const double volume = tet_signed_volume(a, b, c, d);
        double rho = 1;
        if (options.density)
          rho = options.density(bary);
        else if (vertex_rho)
          rho = (options.vertex_density[T[0]] + options.vertex_density[T[1]] + options.vertex_density[T[2]] +
                 options.vertex_density[T[3]]) / 4;
        // Barycentre for tets with a boundary vertex (Fig. 2.33 (b)) and for
        // tets that are not Delaunay (2.6.5.4); circumcentre otherwise.
        bool boundary = false;
        for (index_t w : T) {
          boundary = boundary || mesh.on_boundary(w);
          if (w != v) {
            sum_len += (mesh.point(w) - x).norm();
            ++n_len;
          }
        }
        Vec3 centre = bary;
        if (!boundary && locally_delaunay(mesh, t)) {
          if (!tet_circumcentre(a, b, c, d, &centre)) centre = bary;
        }
        const double weight = volume * rho;
        sum_c += weight * centre;
        sum_w += weight;
      }
      if (!(sum_w > 0) || n_len == 0) continue;
      const Vec3 step = sum_c / sum_w - x;
      const double length = sum_len / n_len;
      const double relative = step.norm() / length;
      if (!std::isfinite(relative) || relative <= options.tolerance * 1e-3) continue;  // already there

      // Fig. 2.33 step-size rule: alpha = 1, halved while the move inverts a
      // tet (or, with the guard, lowers the ball's minimum stretch).
      const double alpha = move_with_step_halving(
          mesh, ball, v, options.max_halvings, options.quality_guard, options.quality_floor,
          [&](double a, Vec3* p) {
            *p = x + a * step;
            return true;
          },
          &report.halvings);
      const bool accepted = alpha > 0;
      if (accepted) {
        ++report.moved;
        max_step = std::max(max_step, alpha * relative);
        if (alpha * relative > options.active_tolerance)
          for (const index_t t : ball)
            for (const index_t w : mesh.tet(t)) active[w] |= 2;
      } else {
        ++report.refused;
      }
    }
    report.last_max_step = max_step;
    if (max_step <= options.tolerance) {
      report.converged = true;
      break;
    }
  }
  return report;
}

}  // namespace femorph
