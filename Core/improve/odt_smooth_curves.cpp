// Phase (1) of Phased ODT smoothing (thesis 2.6.5.2): Eq. 2.34 over the two
// curve edges of each curve vertex, CPT smoothing on lines, central angles on
// circles (Fig. 2.42).
#include "improve/control_shape_accuracy.h"
#include "improve/ball_quality.h"
#include "improve/odt_smooth_curves.h"

#include "improve/boundary_geometry.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace femorph {

namespace {

/// The two curve neighbours of v (other ends of its curve edges); false when
/// v does not have exactly two.
bool curve_neighbours(const TetMesh& mesh, index_t v, const std::vector<index_t>& ball, index_t* w) {
  int n = 0;
  for (index_t t : ball) {
    const Tet& T = mesh.tet(t);
    for (int f = 0; f < 4; ++f) {
      if (T[f] == v || !mesh.is_boundary_face(t, f)) continue;
      for (int i = 0; i < 3; ++i) {
        const index_t u = T[kTetFace[f][i]];
        if (u == v || (n > 0 && w[0] == u) || (n > 1 && w[1] == u)) continue;
        if (!mesh.is_curve_edge(v, u, t)) continue;
        if (n == 2) return false;
        w[n++] = u;
      }
    }
  }
  return n == 2;
}

}  // namespace

OdtSmoothReport odt_smooth_curves(TetMesh& mesh, const BoundaryGeometry& geometry,
                                  const BoundarySmoothOptions& options) {
  OdtSmoothReport report;
  const index_t slots = mesh.vertex_slots();
  const bool use_mask = !options.vertex_mask.empty();
  std::vector<index_t> ball;

  for (int sweep = 0; sweep < options.iterations; ++sweep) {
    ++report.sweeps;
    double max_step = 0;
    for (index_t v = 0; v < slots; ++v) {
      if (!mesh.vertex_alive(v) || mesh.vertex_class(v) != VertexClass::Curve) continue;
      if (use_mask && (static_cast<std::size_t>(v) >= options.vertex_mask.size() || !options.vertex_mask[v])) continue;
      const VertexConstraint c = vertex_constraint(mesh, geometry, v);
      if (c.kind != VertexConstraint::Curve) continue;
      mesh.vertex_ball(v, ball);
      index_t w[2];
      if (!curve_neighbours(mesh, v, ball, w)) continue;
      const Vec3 x = mesh.point(v);
      const Vec3 &w0 = mesh.point(w[0]), &w1 = mesh.point(w[1]);
      const double len = ((w0 - x).norm() + (w1 - x).norm()) / 2;

      // Eq. 2.34 with the edge midpoints (CPT), or on the central angle.
      const bool circle = c.curve && (c.curve->type == CurveType::Circle || c.curve->type == CurveType::CircularArc);
      Vec3 centre = Vec3::Zero(), e1 = Vec3::Zero(), e2 = Vec3::Zero(), step = Vec3::Zero();
      double theta = 0;
      if (circle) {
        // Fig. 2.42: angles about the centre, measured from v (v at 0, the
        // neighbours in (-pi, pi]: no wrap-around); the midpoints of the
        // edges are at half their angles.
        const Vec3 n = c.curve->normal.normalized();
        centre = c.curve->center;
        const Vec3 r = (x - centre) - (x - centre).dot(n) * n;
        if (!(r.norm() > 0)) continue;
        e1 = r.normalized();
        e2 = n.cross(e1);
        double t[2];
        for (int i = 0; i < 2; ++i) {
          const Vec3 d = mesh.point(w[i]) - centre;
          t[i] = std::atan2(d.dot(e2), d.dot(e1));
        }
        theta = (t[0] + t[1]) / 4;  // mean of the edge mid-angles t[i] / 2
        if (!(std::abs(theta) * c.curve->radius / len > options.tolerance * 1e-3)) continue;
      } else {
        step = (w0 + w1) / 4 - x / 2;  // mean of the midpoints (x + w_i) / 2, minus x
        if (!(step.norm() / len > options.tolerance * 1e-3)) continue;
      }

      const bool accepted =
          move_with_step_halving(
              mesh, ball, v, options.max_halvings, options.quality_guard, options.quality_floor,
              [&](double alpha, Vec3* p) {
                const Vec3 q = circle ? centre + c.curve->radius *
                                                     (std::cos(alpha * theta) * e1 + std::sin(alpha * theta) * e2)
                                      : Vec3(x + alpha * step);
                return project_to_constraint(c, q, p);
              },
              [&](const Vec3& p) {
                return !options.acceptable_error ||
                       chords_within_error(mesh, geometry, *options.acceptable_error, v, p, ball);
              },
              &report.halvings) > 0;
      const Vec3& p = mesh.point(v);
      if (accepted) {
        ++report.moved;
        max_step = std::max(max_step, (p - x).norm() / len);
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
