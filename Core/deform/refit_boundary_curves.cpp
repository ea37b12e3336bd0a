// The curves between moved or deformed regions change with them (2.5.4.5
// updates "the boundary edge information" before the vertices move): their
// fits are taken again from their vertices' new positions.
#include "deform/deform.h"

#include "mesh/tet_mesh.h"

#include <cmath>

namespace femorph {

void refit_boundary_curves(const TetMesh& mesh, const std::vector<SurfacePrimitive>& surfaces, const DeformPlan& plan,
                           std::vector<BoundaryCurve>& curves) {
  const auto fixed = [&](index_t r) {
    return r < 0 || r >= static_cast<index_t>(plan.roles.size()) || plan.roles[r] == RegionRole::Fixed;
  };
  const SurfacePrimitive none;
  const auto surface = [&](index_t r) {
    return r >= 0 && r < static_cast<index_t>(surfaces.size()) ? surfaces[r] : none;
  };
  for (BoundaryCurve& c : curves) {
    if (fixed(c.region_a) && fixed(c.region_b)) continue;
    std::vector<Vec3> points;
    std::vector<index_t> alive;
    for (const index_t v : c.vertices) {
      if (mesh.vertex_alive(v) && mesh.vertex_class(v) != VertexClass::Inner) {
        points.push_back(mesh.point(v));
        alive.push_back(v);
      }
    }
    const CurveFit fit = classify_boundary_curve(points, c.closed, 1e-6 * plan.part_size, surface(c.region_a),
                                                 surface(c.region_b));
    c.vertices = alive;
    if (fit.ok && (fit.curve.type == CurveType::Line || fit.curve.type == CurveType::Circle ||
                   fit.curve.type == CurveType::CircularArc)) {
      c.curve = fit.curve;
      c.type = fit.curve.type;
      // A circle in a coordinate plane whose points all share that
      // coordinate: its normal and centre exactly so (no rounding noise off
      // the plane when Improve projects onto it).
      if (c.type != CurveType::Line) {
        for (int k = 0; k < 3; ++k) {
          if (std::abs(std::abs(c.curve.normal[k]) - 1) >= 1e-9) continue;
          bool same = !points.empty();
          for (const Vec3& p : points) same = same && p[k] == points.front()[k];
          if (!same) continue;
          const double sign = c.curve.normal[k] > 0 ? 1.0 : -1.0;
          c.curve.normal = Vec3::Zero();
          c.curve.normal[k] = sign;
          c.curve.center[k] = c.curve.start[k] = c.curve.end[k] = points.front()[k];
        }
      }
    } else {
      c.curve = CurvePrimitive();
      c.type = CurveType::Unclassified;
    }
  }
}

}  // namespace femorph
