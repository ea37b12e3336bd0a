// Shared machinery of the segmentation steps: fitting a region and region
// integration by alternate growing and refitting (thesis 2.4.3.3).
#include "segment/segmentation_state.h"

#include "common/parallel.h"

#include <algorithm>
#include <cmath>

namespace femorph {
namespace segment {

State::Scratch& State::scratch() const {
  if (!in_parallel()) return scratch_;
  thread_local Scratch own;
  return own;
}

std::vector<index_t> State::vertices_of(const std::vector<index_t>& triangles) const {
  Scratch& sc = scratch();
  if (sc.vertex_slot.size() != surface.points.size()) {
    sc.vertex_marks.reset(surface.points.size());
    sc.vertex_slot.assign(surface.points.size(), kInvalidIndex);
  }
  const std::uint32_t mark = sc.vertex_marks.next(surface.points.size());
  std::vector<index_t> v;
  v.reserve(triangles.size() / 2 + 3);
  for (index_t f : triangles)
    for (index_t w : surface.triangles[f])
      if (sc.vertex_marks.stamp[w] != mark) {
        sc.vertex_marks.stamp[w] = mark;
        sc.vertex_slot[w] = static_cast<index_t>(v.size());
        v.push_back(w);
      }
  return v;
}

std::vector<char> State::inner_mask(const std::vector<index_t>& triangles,
                                    const std::vector<index_t>& vertices) const {
  Stamps<std::uint32_t>& marks = scratch().triangle_marks;
  const std::uint32_t mark = marks.next(static_cast<std::size_t>(surface.num_triangles()));
  for (index_t f : triangles) marks.stamp[f] = mark;
  std::vector<char> inner(vertices.size(), 1);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const index_t v = vertices[i];
    for (index_t k = surface.vertex_offsets[v]; k < surface.vertex_offsets[v + 1]; ++k)
      if (marks.stamp[surface.vertex_triangles[k]] != mark) {
        inner[i] = 0;
        break;
      }
  }
  return inner;
}

std::vector<index_t> State::fit_vertices(const std::vector<index_t>& triangles, std::size_t min_count) const {
  std::vector<index_t> vertices = vertices_of(triangles);
  if (!(curve_tolerance > tolerance)) return vertices;  // every vertex as exact as the others
  const std::vector<char> inner = inner_mask(triangles, vertices);
  std::vector<index_t> kept;
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (inner[i]) kept.push_back(vertices[i]);
  if (kept.size() < min_count || 4 * kept.size() < vertices.size()) return vertices;
  return kept;
}

std::vector<index_t> State::exact_vertices(const SurfacePrimitive& s, const std::vector<index_t>& triangles,
                                           std::size_t min_count) const {
  std::vector<index_t> vertices = vertices_of(triangles);
  if (!(curve_tolerance > tolerance)) return vertices;
  // Within the tight tolerance and within four times the median distance:
  // where the tight tolerance is loose (not tightened to the mesh's
  // precision), the median still tells the exact vertices, which are most.
  std::vector<double> d;
  d.reserve(vertices.size());
  for (index_t v : vertices) d.push_back(distance(s, surface.points[v]));
  std::vector<double> sorted = d;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  constexpr double kMedianFactor = 4.0;
  const double bar = std::min(tolerance, kMedianFactor * sorted[sorted.size() / 2] + 1e-12 * scale);
  std::vector<index_t> kept;
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (d[i] <= bar) kept.push_back(vertices[i]);
  if (kept.size() < min_count || 4 * kept.size() < vertices.size()) return vertices;
  return kept;
}

double State::scaled_max_distance(const SurfacePrimitive& s, const std::vector<index_t>& triangles) const {
  const std::vector<index_t> vertices = vertices_of(triangles);
  double d = 0;
  if (!(curve_tolerance > tolerance)) {
    for (index_t v : vertices) d = std::max(d, distance(s, surface.points[v]));
    return d;
  }
  const std::vector<char> inner = inner_mask(triangles, vertices);
  const double border_scale = tolerance / near_tolerance();
  for (std::size_t i = 0; i < vertices.size(); ++i)
    d = std::max(d, distance(s, surface.points[vertices[i]]) * (inner[i] ? 1.0 : border_scale));
  return d;
}

std::vector<Vec3> State::positions(const std::vector<index_t>& vertices) const {
  std::vector<Vec3> p;
  p.reserve(vertices.size());
  for (index_t v : vertices) p.push_back(surface.points[v]);
  return p;
}

bool State::absorb_if_near(index_t from, index_t into) {
  WorkRegion& source = regions[from];
  WorkRegion& target = regions[into];
  for (const index_t f : source.triangles)
    if (!triangle_near(target.surface, f)) return false;
  for (const index_t f : source.triangles) triangle_region[f] = into;
  target.triangles.insert(target.triangles.end(), source.triangles.begin(), source.triangles.end());
  source.triangles.clear();
  source.alive = false;
  return true;
}

Vec3 State::vertex_normal(index_t v) const {
  if (curvature.vertex_valid.size() > static_cast<std::size_t>(v) && curvature.vertex_valid[v])
    return curvature.vertex_normal[v];
  Vec3 n = Vec3::Zero();
  for (index_t i = surface.vertex_offsets[v]; i < surface.vertex_offsets[v + 1]; ++i) {
    const index_t f = surface.vertex_triangles[i];
    n += surface.areas[f] * surface.normals[f];
  }
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : n;
}

std::vector<Vec3> State::normals(const std::vector<index_t>& vertices) const {
  std::vector<Vec3> n;
  n.reserve(vertices.size());
  for (index_t v : vertices) n.push_back(vertex_normal(v));
  return n;
}

double State::triangle_distance(const SurfacePrimitive& s, index_t f) const {
  double d = 0;
  for (index_t v : surface.triangles[f]) d = std::max(d, distance(s, surface.points[v]));
  return d;
}

double State::triangle_distance_off(const SurfacePrimitive& s, index_t f, index_t other) const {
  if (!(curve_tolerance > tolerance)) return triangle_distance(s, f);  // border vertices as exact as the others
  double d = 0;
  bool any = false;
  for (index_t v : surface.triangles[f]) {
    bool touched = false;
    for (index_t k = surface.vertex_offsets[v]; k < surface.vertex_offsets[v + 1] && !touched; ++k)
      touched = triangle_region[surface.vertex_triangles[k]] == other;
    if (touched) continue;
    d = std::max(d, distance(s, surface.points[v]));
    any = true;
  }
  return any ? d : triangle_distance(s, f);
}

namespace {

/// A triangle lying on the surface also faces along it (a flat triangle
/// inscribed in a curved surface deviates by about half its angular span).
bool faces_along(const SurfaceMesh& surface, const SurfacePrimitive& s, index_t f) {
  const Vec3& n = surface.normals[f];
  if (n.squaredNorm() == 0) return true;  // degenerate: distances decide
  const Tri& t = surface.triangles[f];
  const Vec3 c = (surface.points[t[0]] + surface.points[t[1]] + surface.points[t[2]]) / 3.0;
  constexpr double kCos30 = 0.8660254037844387;
  return std::abs(n.dot(surface_normal(s, c))) >= kCos30;
}

}  // namespace

bool State::triangle_near(const SurfacePrimitive& s, index_t f) const {
  const double near = near_tolerance();
  if (!(near > tolerance)) return triangle_on(s, f);
  bool inside = false;
  for (index_t v : surface.triangles[f]) {
    const double d = distance(s, surface.points[v]);
    if (d > near) return false;
    inside = inside || d <= tolerance;
  }
  if (!inside)
    for (index_t v : surface.triangles[f])
      if (sharp.vertex_degree[v] == 0) return false;
  return faces_along(surface, s, f);
}

bool State::triangle_on(const SurfacePrimitive& s, index_t f) const {
  if (triangle_distance(s, f) > tolerance) return false;
  return faces_along(surface, s, f);
}

namespace {

/// Area-weighted vertex normals restricted to the given triangles: at a sharp
/// edge or a region border only the region's own side counts.
std::vector<Vec3> region_normals(const State& st, const std::vector<index_t>& triangles,
                                 const std::vector<index_t>& vertices) {
  // `vertices` comes from vertices_of(triangles): slot() maps back.
  std::vector<Vec3> n(vertices.size(), Vec3::Zero());
  for (index_t f : triangles)
    for (index_t w : st.surface.triangles[f]) n[st.slot(w)] += st.surface.areas[f] * st.surface.normals[f];
  for (Vec3& v : n) {
    const double len = v.norm();
    if (len > 0) v /= len;
  }
  return n;
}

}  // namespace

FitResult fit_region(const State& st, SurfaceType type, const std::vector<index_t>& triangles,
                     const std::vector<Vec3>* max_dirs, bool refine) {
  const std::vector<index_t> vertices = st.vertices_of(triangles);
  std::vector<Vec3> points = st.positions(vertices);
  std::vector<Vec3> normals = region_normals(st, triangles, vertices);
  std::vector<Vec3> dirs;
  if (max_dirs) dirs = *max_dirs;
  // Where boundary-curve vertices are less exact than the others, fit the
  // inner vertices when there are enough of them (fit_vertices' rule), and
  // fall back to all if that fit misses the border vertices by more than
  // their tolerance (inner vertices along one line of a narrow strip).
  std::vector<Vec3> all_points, all_normals, all_dirs;
  std::vector<char> inner;
  if (st.curve_tolerance > st.tolerance) {
    inner = st.inner_mask(triangles, vertices);
    std::size_t count = 0;
    for (char c : inner) count += c;
    if (count >= 2 * min_vertices(type) && 4 * count >= vertices.size()) {
      all_points.swap(points);
      all_normals.swap(normals);
      all_dirs = dirs;
      dirs.clear();
      for (std::size_t i = 0; i < vertices.size(); ++i)
        if (inner[i]) {
          points.push_back(all_points[i]);
          normals.push_back(all_normals[i]);
          if (max_dirs) dirs.push_back(all_dirs[i]);
        }
    }
  }
  auto misses_border = [&](const FitResult& f) {
    if (all_points.empty() || !f.ok) return false;
    for (const Vec3& p : all_points)
      if (distance(f.surface, p) > st.near_tolerance()) return true;
    return false;
  };
  RansacParams rp;
  rp.iterations = st.params.ransac_iterations;
  // RANSAC models come from three points and their normals, whose errors
  // put good models a fair part of an edge off: a tolerance as tight as the
  // growing one finds no consensus on fine meshes. LM then fits exactly.
  rp.inlier_tolerance = std::max(st.tolerance, 0.2 * st.surface.mean_edge_length);
  rp.max_cone_half_angle = degrees_to_radians(st.params.max_cone_half_angle_deg);
  rp.seed = st.params.random_seed;
  auto fit_points = [&]() {
  FitResult fit;
  switch (type) {
    case SurfaceType::Plane: return fit_plane(points, &normals);
    case SurfaceType::Cylinder: fit = fit_cylinder(points, normals); break;
    case SurfaceType::Cone: fit = ransac_cone(points, normals, rp); break;
    case SurfaceType::Sphere: {
      fit = fit_sphere(points);
      if (!fit.ok || fit.max_abs > st.tolerance) {
        const FitResult r = ransac_sphere(points, normals, rp);
        if (r.ok && (!fit.ok || r.rms < fit.rms)) fit = r;
      }
      break;
    }
    case SurfaceType::Torus:
      // max_dirs are per vertex of the region when given.
      fit = ransac_torus(points, normals, max_dirs ? &dirs : nullptr, rp);
      break;
    default: return fit;
  }
  if (!fit.ok || !refine) return fit;
  const FitResult refined = refine_fit_lm(fit.surface, points);
  if (refined.ok && refined.rms <= fit.rms) return refined;
  return fit;
  };
  // The largest distance over all vertices, the border ones in units of the
  // curve tolerance (as scaled_max_distance), so that callers compare it
  // with the tight tolerance.
  auto scaled = [&](FitResult f) {
    if (inner.empty() || !f.ok) return f;
    const double border_scale = st.tolerance / st.near_tolerance();
    f.max_abs = 0;
    for (std::size_t i = 0; i < vertices.size(); ++i)
      f.max_abs = std::max(f.max_abs, distance(f.surface, st.surface.points[vertices[i]]) *
                                          (inner[i] ? 1.0 : border_scale));
    return f;
  };
  const FitResult fit = fit_points();
  if (!misses_border(fit)) return scaled(fit);
  points.swap(all_points);
  normals.swap(all_normals);
  dirs.swap(all_dirs);
  return scaled(fit_points());
}

FitResult refit_region(const State& st, SurfaceType type, const SurfacePrimitive& start,
                       const std::vector<index_t>& triangles) {
  auto fit = [&](const std::vector<Vec3>& points) {
    FitResult r = type == SurfaceType::Plane ? fit_plane(points, nullptr) : refine_fit_lm(start, points);
    if (type == SurfaceType::Plane && r.ok && r.surface.axis.dot(start.axis) < 0) r.surface.axis = -r.surface.axis;
    return r;
  };
  const std::vector<index_t> chosen = st.fit_vertices(triangles, 2 * min_vertices(type));
  FitResult r = fit(st.positions(chosen));
  if (!(st.curve_tolerance > st.tolerance)) return r;
  const std::vector<index_t> all = st.vertices_of(triangles);
  if (r.ok && chosen.size() < all.size()) {
    bool misses = false;
    for (index_t v : all) misses = misses || distance(r.surface, st.surface.points[v]) > st.near_tolerance();
    if (misses) r = fit(st.positions(all));
  }
  // Then over the vertices that fit exactly (within the tight tolerance):
  // border vertices counted as inner where the region overreaches its face
  // by a triangle, and all vertices of a narrow strip, would tilt it.
  for (int pass = 0; pass < 3 && r.ok; ++pass) {
    const std::vector<index_t> exact = st.exact_vertices(r.surface, triangles, 2 * min_vertices(type));
    if (exact.size() == all.size()) break;
    const FitResult e = fit(st.positions(exact));
    if (!e.ok) break;
    r = e;
  }
  if (r.ok) r.max_abs = st.scaled_max_distance(r.surface, triangles);
  return r;
}

WorkRegion integrate_region(const State& st, SurfaceType type, const std::vector<index_t>& seed,
                            const FitResult& initial) {
  WorkRegion region;
  region.type = type;
  if (!initial.ok || seed.empty()) {
    region.alive = false;
    return region;
  }
  region.surface = initial.surface;
  const SurfaceMesh& s = st.surface;
  std::vector<char> in_region(static_cast<std::size_t>(s.num_triangles()), 0);
  // Keep only the seed triangles that lie on the initial fit.
  for (index_t f : seed)
    if (st.triangle_region[f] < 0 && st.triangle_near(region.surface, f)) {
      region.triangles.push_back(f);
      in_region[f] = 1;
    }
  if (region.triangles.empty()) {
    region.alive = false;
    return region;
  }
  constexpr int kMaxRounds = 8;
  std::vector<index_t> frontier;
  for (int round = 0; round < kMaxRounds; ++round) {
    // Region growing by distance: breadth-first over unassigned neighbours
    // lying on the current fit.
    const std::size_t before = region.triangles.size();
    frontier = region.triangles;
    while (!frontier.empty()) {
      const index_t f = frontier.back();
      frontier.pop_back();
      for (int k = 0; k < 3; ++k) {
        const index_t g = s.neighbors[f][k];
        if (g < 0 || in_region[g] || st.triangle_region[g] >= 0) continue;
        if (!st.triangle_near(region.surface, g)) continue;
        in_region[g] = 1;
        region.triangles.push_back(g);
        frontier.push_back(g);
      }
    }
    // Refit on the grown region: exact least squares for planes, LM from the
    // current surface for the others. A growth of under 2% cannot move the
    // fit enough to matter: keep it (large regions would pay an LM each).
    const std::size_t added = region.triangles.size() - before;
    if (round > 0 && added * 50 < region.triangles.size()) {
      if (added == 0) break;
      continue;
    }
    const FitResult refit = refit_region(st, type, region.surface, region.triangles);
    if (refit.ok) {
      region.surface = refit.surface;
      region.fit_rms = refit.rms;
      region.fit_max = refit.max_abs;
    } else {
      const FitResult e = evaluate_fit(region.surface, st.positions(st.vertices_of(region.triangles)));
      region.fit_rms = e.rms;
      region.fit_max = e.max_abs;
    }
    if (region.triangles.size() == before && round > 0) break;
  }
  // Where boundary curves are approximate, the fits during growth took the
  // inner vertices of a partial region (or all vertices when too few were
  // inner): a last fit over the whole region's inner vertices makes it exact.
  if (st.curve_tolerance > st.tolerance) {
    const FitResult refit = refit_region(st, type, region.surface, region.triangles);
    if (refit.ok) {
      region.surface = refit.surface;
      region.fit_rms = refit.rms;
      region.fit_max = refit.max_abs;
    }
  }
  // Drop triangles the final fit no longer accepts (rare: the seed was wider
  // than the surface).
  std::vector<index_t> kept;
  for (index_t f : region.triangles)
    if (st.triangle_near(region.surface, f)) kept.push_back(f);
  region.triangles.swap(kept);
  region.alive = st.vertices_of(region.triangles).size() >= min_vertices(type) &&
                 plausible_fit(st, region.surface, region.triangles) &&
                 !simpler_type_fits(st, type, region.triangles, region.fit_max);
  return region;
}

std::size_t min_vertices(SurfaceType type) {
  switch (type) {
    case SurfaceType::Plane: return 4;
    case SurfaceType::Sphere: return 6;
    case SurfaceType::Cylinder: return 7;
    case SurfaceType::Cone: return 8;
    default: return 9;
  }
}

namespace {

/// Whether every triangle lies near s (State::triangle_near) but a few, at
/// most a tenth, each on the border of the set (sharing an edge with a
/// triangle outside it).
bool near_but_border(const State& st, const SurfacePrimitive& s, const std::vector<index_t>& triangles) {
  constexpr std::size_t kFewDivisor = 10;
  std::vector<index_t> far;
  for (index_t f : triangles)
    if (!st.triangle_near(s, f)) {
      far.push_back(f);
      if (far.size() * kFewDivisor > triangles.size()) return false;
    }
  if (far.empty()) return true;
  std::vector<index_t> sorted = triangles;
  std::sort(sorted.begin(), sorted.end());
  for (index_t f : far) {
    bool border = false;
    for (int k = 0; k < 3 && !border; ++k) {
      const index_t g = st.surface.neighbors[f][k];
      border = g < 0 || !std::binary_search(sorted.begin(), sorted.end(), g);
    }
    if (!border) return false;
  }
  return true;
}

}  // namespace

bool simpler_type_fits(const State& st, SurfaceType type, const std::vector<index_t>& triangles, double max_abs) {
  // Where boundary curves are approximate, max_abs is set by their noise
  // (scaled_max_distance), which any smooth surface near the region shares:
  // "nearly as well" is then closer.
  constexpr double kNearly = 3.0, kNearlyCurves = 1.5;
  const double bar =
      std::max(st.tolerance, (st.curve_tolerance > st.tolerance ? kNearlyCurves : kNearly) * max_abs);
  std::vector<SurfaceType> simpler;
  switch (type) {
    case SurfaceType::Cylinder:
    case SurfaceType::Sphere: simpler = {SurfaceType::Plane}; break;
    case SurfaceType::Cone:
    case SurfaceType::Torus: simpler = {SurfaceType::Plane, SurfaceType::Cylinder, SurfaceType::Sphere}; break;
    default: return false;
  }
  const std::size_t nv = st.vertices_of(triangles).size();
  for (SurfaceType s : simpler) {
    if (nv < min_vertices(s)) continue;
    // The direct fit decides when it is clearly in or out; LM only near the bar.
    const FitResult quick = fit_region(st, s, triangles, nullptr, false);
    if (!quick.ok) continue;
    if (quick.max_abs <= bar) return true;
    if (quick.max_abs > 10 * bar) continue;
    const FitResult fit = fit_region(st, s, triangles);
    if (fit.ok && fit.max_abs <= bar) return true;
    // Where boundary curves are approximate, max_abs came from a refit over
    // the exact vertices (refit_region): the simpler type gets the same, and
    // it is judged by triangles, not by the single worst vertex: a region
    // that grew a few triangles into a tangent neighbour (at a G1 junction)
    // bends a fit with more parameters towards them.
    if (!fit.ok || !(st.curve_tolerance > st.tolerance)) continue;
    const FitResult exact = refit_region(st, s, fit.surface, triangles);
    if (exact.ok && (exact.max_abs <= bar || near_but_border(st, exact.surface, triangles))) return true;
  }
  return false;
}

bool plausible_fit(const State& st, const SurfacePrimitive& s, const std::vector<index_t>& triangles) {
  if (s.type == SurfaceType::Plane) return true;
  if (s.type == SurfaceType::Unknown || triangles.empty()) return false;
  Eigen::AlignedBox3d box;
  for (index_t f : triangles)
    for (index_t v : st.surface.triangles[f]) box.extend(st.surface.points[v]);
  const double extent = box.diagonal().norm();
  const Vec3 centre = box.center();
  constexpr double kFar = 1000.0;  // times the region's extent
  double rho = 0;                  // smallest radius of curvature over the region
  switch (s.type) {
    case SurfaceType::Cylinder:
    case SurfaceType::Sphere: rho = s.radius; break;
    case SurfaceType::Torus:
      // Ring, horn (r = R) and spindle (r > R: a rounded boss end reaching
      // its axis) tori; R near 0 is a sphere, which simpler_type_fits prefers.
      if (!(s.radius > 0) || !(s.minor_radius > 0)) return false;
      // A fillet torus goes around its axis: its major radius is of the order
      // of the region; a huge one imitates a cylinder.
      if (s.radius > 10.0 * extent) return false;
      rho = s.minor_radius;
      break;
    case SurfaceType::Cone: {
      const double max_angle = degrees_to_radians(st.params.max_cone_half_angle_deg);
      if (s.half_angle < degrees_to_radians(1.0) || s.half_angle > max_angle) return false;
      if ((centre - s.point).norm() > kFar * extent) return false;
      const Vec3 d = centre - s.point;
      const double to_axis = (d - d.dot(s.axis) * s.axis).norm();
      rho = to_axis / std::cos(s.half_angle);
      break;
    }
    default: return false;
  }
  if (!(rho > 0) || rho > kFar * extent) return false;
  return extent * extent / (8.0 * rho) > st.tolerance;
}

index_t add_region(State& st, WorkRegion region) {
  const index_t id = static_cast<index_t>(st.regions.size());
  for (index_t f : region.triangles) st.triangle_region[f] = id;
  st.regions.push_back(std::move(region));
  return id;
}

}  // namespace segment
}  // namespace femorph
