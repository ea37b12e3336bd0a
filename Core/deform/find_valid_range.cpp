// The valid range of the dimension (thesis 2.5.3: the largest and smallest
// value that degenerates no neighbouring region and makes no
// self-intersection), found by repositioning the boundary for trial values:
// a value is valid when its surfaces exist and no boundary triangle of a
// moved or deformed region folds over on its surface. One parameterisation
// of the boundary gives the range of one step; beyond it, the boundary is
// marched in steps, parameterised again after each (extend_valid_range).
#include "deform/deform.h"

#include "mesh/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace femorph {

namespace {

/// The boundary faces (4 t + f) of the moved and deformed regions: the
/// only ones a change can fold.
std::vector<index_t> changing_faces(const TetMesh& mesh, const DeformPlan& plan) {
  std::vector<index_t> faces;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    for (int f = 0; f < 4; ++f) {
      const index_t r = mesh.face_region(t, f);
      if (r >= 0 && r < static_cast<index_t>(plan.roles.size()) && plan.roles[r] != RegionRole::Fixed) {
        faces.push_back(4 * t + f);
      }
    }
  }
  return faces;
}

/// The tets with a vertex on a moved or deformed region: the boundary the
/// trial values move lies in them, so the parameterisation of the boundary
/// (inner vertices fixed) needs no more of the mesh.
std::vector<std::uint8_t> changing_tets(const TetMesh& mesh, const std::vector<index_t>& faces) {
  std::vector<std::uint8_t> on(mesh.vertex_slots(), 0), tets(mesh.tet_slots(), 0);
  for (const index_t code : faces) {
    const Tet& T = mesh.tet(code / 4);
    for (int k = 0; k < 3; ++k) on[T[kTetFace[code % 4][k]]] = 1;
  }
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const Tet& T = mesh.tet(t);
    tets[t] = on[T[0]] || on[T[1]] || on[T[2]] || on[T[3]];
  }
  return tets;
}

bool faces_unfolded(const TetMesh& mesh, const DeformRegions& regions, const DeformPlan& plan,
                    const SurfaceUpdate& update, const std::vector<Vec3>& points, const std::vector<index_t>& faces,
                    std::string* why) {
  for (const index_t code : faces) {
    const index_t t = code / 4;
    const int f = code % 4;
    const index_t r = mesh.face_region(t, f);
    const Tet& T = mesh.tet(t);
    const index_t a = T[kTetFace[f][0]], b = T[kTetFace[f][1]], c = T[kTetFace[f][2]];
    const Vec3 n0 = (mesh.point(b) - mesh.point(a)).cross(mesh.point(c) - mesh.point(a));
    const Vec3 n1 = (points[b] - points[a]).cross(points[c] - points[a]);
    bool ok;
    const SurfacePrimitive& s0 = regions.surfaces[r];
    const SurfacePrimitive& s1 = update.surfaces[r];
    if (s0.type == SurfaceType::Unknown || s1.type == SurfaceType::Unknown) {
      ok = n1.dot(n0) > 1e-6 * n0.squaredNorm();
    } else {
      const Vec3 c0 = (mesh.point(a) + mesh.point(b) + mesh.point(c)) / 3;
      const Vec3 c1 = (points[a] + points[b] + points[c]) / 3;
      const double side0 = n0.dot(surface_normal(s0, c0)), side1 = n1.dot(surface_normal(s1, c1));
      ok = (side0 > 0) == (side1 > 0) && std::abs(side1) > 1e-6 * n0.norm();
    }
    if (!ok) {
      if (why) {
        const Vec3 c1 = (points[a] + points[b] + points[c]) / 3;
        std::ostringstream os;
        os << "a boundary triangle of region " << r << " (" << to_string(plan.roles[r]) << ") near (" << c1.x()
           << ", " << c1.y() << ", " << c1.z() << ") folds over";
        *why = os.str();
      }
      return false;
    }
  }
  return true;
}

}  // namespace

bool boundary_unfolded(const TetMesh& mesh, const DeformRegions& regions, const DeformPlan& plan,
                       const SurfaceUpdate& update, const std::vector<Vec3>& points, std::string* why) {
  return faces_unfolded(mesh, regions, plan, update, points, changing_faces(mesh, plan), why);
}

void find_valid_range(const TetMesh& mesh, const DeformRegions& regions, DeformPlan& plan) {
  const std::vector<index_t> faces = changing_faces(mesh, plan);
  VertexParameterization param;
  if (!parameterize_vertices(mesh, plan, changing_tets(mesh, faces), param, false)) {
    plan.valid_min = plan.valid_max = plan.current;
    return;
  }
  std::vector<Vec3> points;
  std::string why;
  // The trial values of a linear dimension superpose earlier solves.
  RepositionHistory history;
  const auto valid = [&](double value) {
    const SurfaceUpdate update = update_region_surfaces(plan, regions, value);
    if (!update.error.empty()) {
      why = update.error;
      return false;
    }
    reposition_vertices(mesh, regions, param, update, points, &history);
    return faces_unfolded(mesh, regions, plan, update, points, faces, &why);
  };
  const bool angle = plan.options.type == DeformationType::ChamferAngle;
  const double c = plan.current;
  const double first = angle ? 0.5 : 0.01 * plan.part_size;
  const double cap = angle ? 180.0 : 10 * plan.part_size;
  const auto search = [&](double sign, std::string& limit) {
    limit.clear();
    double good = c, step = first;
    double bad = std::numeric_limits<double>::quiet_NaN();
    while (step <= cap) {
      const double v = c + sign * step;
      if (!valid(v)) {
        bad = v;
        break;
      }
      good = v;
      step *= 2;
    }
    if (std::isnan(bad)) return good;
    valid(bad);
    limit = why;
    for (int i = 0; i < 40 && std::abs(bad - good) > 1e-9 * std::max(1.0, std::abs(c)); ++i) {
      const double mid = 0.5 * (good + bad);
      if (valid(mid)) {
        good = mid;
      } else {
        bad = mid;
        limit = why;
      }
    }
    return good;
  };
  plan.valid_max = search(+1, plan.limit_max);
  plan.valid_min = search(-1, plan.limit_min);
}

bool extend_valid_range(const TetMesh& mesh, const DeformRegions& regions, DeformPlan& plan, double target) {
  const bool up = target > plan.valid_max;
  if (!up && !(target < plan.valid_min)) return true;
  const double bound = up ? plan.valid_max : plan.valid_min;
  TetMesh work = mesh;
  DeformRegions surfaces = regions;
  DeformPlan step_plan = plan;
  const RegionGraph graph = region_adjacency(mesh, regions.size());
  double value = plan.current;
  // Steps of half the one-step range, smaller where one folds.
  double step = std::max(0.5 * std::abs(bound - plan.current), 1e-6 * std::max(1.0, std::abs(target)));
  const double smallest = 1e-4 * std::abs(target - plan.current);
  std::vector<Vec3> points;
  std::string why;
  for (int iteration = 0; iteration < 200 && std::abs(target - value) > 1e-12 * std::max(1.0, std::abs(target));
       ++iteration) {
    const double next = std::abs(target - value) <= step ? target : value + (up ? step : -step);
    const SurfaceUpdate update = update_region_surfaces(step_plan, surfaces, next);
    VertexParameterization param;
    bool ok = update.error.empty() &&
              parameterize_vertices(work, step_plan, changing_tets(work, changing_faces(work, step_plan)), param, false);
    if (ok) {
      reposition_vertices(work, surfaces, param, update, points);
      ok = boundary_unfolded(work, surfaces, step_plan, update, points, &why);
    } else {
      why = update.error;
    }
    if (!ok) {
      step *= 0.25;
      if (step < smallest) break;
      continue;
    }
    for (index_t v = 0; v < work.vertex_slots(); ++v) {
      if (work.vertex_alive(v)) work.set_point(v, points[v]);
    }
    surfaces.surfaces = update.surfaces;
    value = next;
    (up ? plan.valid_max : plan.valid_min) = value;
    const double moved = value;
    if (!classify_surface_regions(work, surfaces, graph, plan.options, step_plan)) break;
    if (plan.options.type == DeformationType::Position) step_plan.current = moved;
    step *= 2;
  }
  if (std::abs(target - value) > 1e-12 * std::max(1.0, std::abs(target))) {
    (up ? plan.limit_max : plan.limit_min) = why;
    return false;
  }
  return true;
}

}  // namespace femorph
