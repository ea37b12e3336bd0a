// The space-and-object meshes of thesis 3.7.2, built at run time for the
// Adapt tests and benchmark: a grid of cubes, a vertex at each cube's
// centre, each cube cut into 12 tets (two triangles per square face, joined
// to the centre), inner vertices jittered; material 1 on a block of cubes.
// And the contact case of thesis 3.7.3 (make_cylinder_half_tube): a cylinder
// and a half tube meshed by TetGen from exact surface triangulations, in a
// space mesh made by mesh_space_around.
#pragma once

#include "adapt/adapt.h"
#include "adapt/tetgen_plc.h"
#include "improve/mesh_density.h"
#include "geometry/discrete_surface.h"
#include "common/types.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace femorph {
namespace testing {

struct MaterialMesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  std::vector<int> material;
  Vec3 object_lo = Vec3::Zero(), object_hi = Vec3::Zero();  ///< the block at step 0
};

/// `cells` cubes of edge `edge` from the origin; the object is the `object`
/// cubes from cube `offset`, per axis (< 0: centred in the grid, rounded
/// down). Square faces are split along
/// the diagonal through their lowest-id corner, so neighbouring cubes match.
/// Vertices off the outer boundary move by up to `jitter` x edge (a move that
/// would flatten a tet is skipped), then `smooth_sweeps` half-Laplacian sweeps.
inline MaterialMesh make_block_in_box(std::array<int, 3> cells, std::array<int, 3> object, double edge,
                                      double jitter, std::uint64_t seed, std::array<int, 3> offset = {{-1, -1, -1}},
                                      int smooth_sweeps = 0) {
  MaterialMesh m;
  const int nx = cells[0], ny = cells[1], nz = cells[2];
  const auto corner = [&](int i, int j, int k) { return static_cast<index_t>((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.points.emplace_back(i * edge, j * edge, k * edge);
  std::array<int, 3> o0;
  for (int a = 0; a < 3; ++a) o0[a] = offset[a] >= 0 ? offset[a] : (cells[a] - object[a]) / 2;
  m.object_lo = Vec3(o0[0], o0[1], o0[2]) * edge;
  m.object_hi = Vec3(o0[0] + object[0], o0[1] + object[1], o0[2] + object[2]) * edge;
  const auto volume = [&](const Tet& t) {
    const Vec3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]], &d = m.points[t[3]];
    return (b - a).dot((c - a).cross(d - a));
  };
  // The 6 faces of a cube as corner offsets in cyclic order.
  static const int kFace[6][4][3] = {
      {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}},
      {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const index_t c = static_cast<index_t>(m.points.size());
        m.points.emplace_back((i + 0.5) * edge, (j + 0.5) * edge, (k + 0.5) * edge);
        const bool in_object = i >= o0[0] && i < o0[0] + object[0] && j >= o0[1] && j < o0[1] + object[1] &&
                               k >= o0[2] && k < o0[2] + object[2];
        for (const auto& face : kFace) {
          index_t q[4];
          for (int r = 0; r < 4; ++r) q[r] = corner(i + face[r][0], j + face[r][1], k + face[r][2]);
          const int low = static_cast<int>(std::min_element(q, q + 4) - q);
          const index_t a = q[low], b = q[(low + 1) % 4], cc = q[(low + 2) % 4], d = q[(low + 3) % 4];
          for (const Tet& t0 : {Tet{{a, b, cc, c}}, Tet{{a, cc, d, c}}}) {
            Tet t = t0;
            if (volume(t) < 0) std::swap(t[0], t[1]);
            m.tets.push_back(t);
            m.material.push_back(in_object ? 1 : 0);
          }
        }
      }
  // Jitter: vertices strictly inside the box, one at a time, kept when no
  // tet around falls below a fifth of its volume.
  std::vector<std::vector<index_t>> ball(m.points.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (const index_t v : m.tets[t]) ball[v].push_back(static_cast<index_t>(t));
  const Vec3 hi(nx * edge, ny * edge, nz * edge);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const double tol = 1e-9 * edge;
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    const Vec3 p = m.points[v];
    const Vec3 move(u(rng), u(rng), u(rng));
    if ((p.array() < tol).any() || (p.array() > hi.array() - tol).any()) continue;
    std::vector<double> before;
    for (const index_t t : ball[v]) before.push_back(volume(m.tets[t]));
    m.points[v] = p + jitter * edge * move;
    for (std::size_t r = 0; r < ball[v].size(); ++r)
      if (volume(m.tets[ball[v][r]]) < 0.2 * before[r]) {
        m.points[v] = p;
        break;
      }
  }
  // Smoothing (the thesis smooths its jittered input): each sweep moves
  // every inner vertex halfway to the mean of its neighbours, when no tet
  // around falls below a fifth of its volume.
  std::vector<std::vector<index_t>> neighbours(m.points.size());
  for (const Tet& t : m.tets)
    for (const index_t a : t)
      for (const index_t b : t)
        if (a != b) neighbours[a].push_back(b);
  for (auto& n : neighbours) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  for (int sweep = 0; sweep < smooth_sweeps; ++sweep)
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      const Vec3 p = m.points[v];
      if ((p.array() < tol).any() || (p.array() > hi.array() - tol).any()) continue;
      Vec3 mean = Vec3::Zero();
      for (const index_t w : neighbours[v]) mean += m.points[w];
      mean /= static_cast<double>(neighbours[v].size());
      std::vector<double> before;
      for (const index_t t : ball[v]) before.push_back(volume(m.tets[t]));
      m.points[v] = 0.5 * (p + mean);
      for (std::size_t r = 0; r < ball[v].size(); ++r)
        if (volume(m.tets[ball[v][r]]) < 0.2 * before[r]) {
          m.points[v] = p;
          break;
        }
    }
  return m;
}

/// Thesis 3.7.3 (Fig. 3.22): a cylinder (material 1, the moving object)
/// translated along its axis z into a half tube of the same radius (material
/// 2, fixed), in a box of space (material 0). Lengths in the units of the
/// motion (thesis: 1 per step, 45 steps).
struct CylinderHalfTube {
  double r = 1.0;    ///< the cylinder's radius = the half tube's inner radius
  double R = 1.6;    ///< the half tube's outer radius (> r)
  double Lc = 3.0;   ///< the cylinder's length: z in [-Lc - gap, -gap] at step 0
  double Lt = 4.0;   ///< the half tube's length: z in [0, Lt], y <= 0
  double gap = 0.5;  ///< between the cylinder's front cap and the tube at step 0 (> 0: no contact)
  /// Segments of the full circle (even, >= 4): theta = 0 and pi, the half
  /// tube's inner edges (y = 0), are segment boundaries, and the tube's
  /// inner half polygon is the cylinder's lower half polygon.
  int n_theta = 12;
  double margin = 1.5;  ///< space between the objects (over the travel) and the box
  /// The cylinder's planned travel along +z; the box holds the cylinder
  /// over it (< 0: Lt + gap, the front cap reaching the tube's far end).
  double travel = -1;
  double space_edge = 0;  ///< the box faces' edge (<= 0: mesh_space_around's default)
  /// Each material's mesh improved with its boundary fixed
  /// (improve_material_mesh) before use: TetGen's radius-edge bound leaves
  /// slivers, and 3.6 improves only the region of a step.
  bool improve = true;

  int n_half() const { return n_theta / 2; }
  /// The surface triangulations' edge: the chord of one of n_theta segments
  /// (the z spacing is the nearest to it that divides the lengths).
  double edge() const { return 2 * r * std::sin(kPi / n_theta); }
  /// Segments of the tube's outer half circle (its chord close to edge()).
  int n_outer_half() const { return std::max(n_half(), static_cast<int>(std::lround(n_half() * R / r))); }
  double planned_travel() const { return travel < 0 ? Lt + gap : travel; }

  /// The sizes of the 3.7.3 benchmark (about the thesis' 160k tets):
  /// 163k tets, 27k points (thesis: 160,791 and 31,530), surface edge 0.49.
  static CylinderHalfTube benchmark() {
    CylinderHalfTube g;
    g.r = 5;
    g.R = 8;
    g.Lc = 20;
    g.Lt = 45;
    g.gap = 0.5;
    g.n_theta = 64;
    g.margin = 4;
    g.travel = 45;
    return g;
  }

  /// The volumes of the meshed polyhedra: the cylinder's n_theta-gon prism,
  /// the half tube's prism between its outer and inner half polygons.
  double cylinder_volume() const { return 0.5 * n_theta * r * r * std::sin(2 * kPi / n_theta) * Lc; }
  double half_tube_volume() const {
    const int no = n_outer_half(), ni = n_half();
    return (0.5 * no * R * R * std::sin(kPi / no) - 0.5 * ni * r * r * std::sin(kPi / ni)) * Lt;
  }
};

/// The contact of 3.7.3 after a translation s along +z (s = step at 1 per
/// step): the cylinder's side over the tube's inner surface. overlap: the
/// length of [front - Lc, front] and [0, Lt] in common, front = s - gap the
/// cylinder's front cap; exact = pi r overlap (the analytic half cylinders);
/// discrete = n_half chords 2 r sin(pi / (2 n_half)) x overlap (the area
/// of the tube's inner half polygon over that length, which is the
/// cylinder's lower half polygon). The 1% check of 3.7.3 uses `discrete`:
/// both meshes are polygons, and discrete < exact by 1 - sinc(pi/n_theta)
/// (1.1% for n_theta = 12, 0.16% for 32), so the exact area would fail a
/// correct coarse mesh; tests report both.
struct ContactArea {
  double overlap = 0, exact = 0, discrete = 0;
};
inline ContactArea cylinder_half_tube_contact_area(const CylinderHalfTube& g, double s) {
  ContactArea a;
  const double front = s - g.gap;
  a.overlap = std::max(0.0, std::min(front, g.Lt) - std::max(front - g.Lc, 0.0));
  a.exact = kPi * g.r * a.overlap;
  const int n = g.n_half();
  a.discrete = n * 2 * g.r * std::sin(kPi / (2 * n)) * a.overlap;
  return a;
}

namespace detail {

/// A closed triangulated surface being built: points merged by position.
struct SurfaceBuilder {
  std::vector<Vec3> points;
  std::vector<std::array<index_t, 3>> triangles;
  std::map<std::array<long long, 3>, index_t> ids;
  double quantum = 1e-9;

  index_t point(const Vec3& p) {
    const std::array<long long, 3> key{
        {std::llround(p.x() / quantum), std::llround(p.y() / quantum), std::llround(p.z() / quantum)}};
    const auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const index_t id = static_cast<index_t>(points.size());
    points.push_back(p);
    ids.emplace(key, id);
    return id;
  }
  void triangle(index_t a, index_t b, index_t c) {
    if (a != b && b != c && a != c) triangles.push_back({{a, b, c}});
  }
  /// A quad (a b c d in cyclic order) as two triangles; `flip`
  /// chooses the diagonal.
  void quad(index_t a, index_t b, index_t c, index_t d, bool flip) {
    if (flip) {
      triangle(a, b, d);
      triangle(b, c, d);
    } else {
      triangle(a, b, c);
      triangle(a, c, d);
    }
  }
  /// Triangles between two polylines of one plane running the same way
  /// (parameters t in [0, 1], both from 0 to 1; a single point is a
  /// polyline of one): advances on the one whose next point comes first.
  void stitch(const std::vector<index_t>& a, const std::vector<double>& ta, const std::vector<index_t>& b,
              const std::vector<double>& tb) {
    std::size_t i = 0, j = 0;
    while (i + 1 < a.size() || j + 1 < b.size()) {
      const bool advance_a = j + 1 == b.size() || (i + 1 < a.size() && ta[i + 1] <= tb[j + 1]);
      if (advance_a) {
        triangle(a[i], a[i + 1], b[j]);
        ++i;
      } else {
        triangle(a[i], b[j + 1], b[j]);
        ++j;
      }
    }
  }
};

/// The point at radius rho and angle 2 pi k / n about the z axis at height
/// z, exact at quarter turns (y = 0 exactly on theta = 0, pi).
inline Vec3 polar(double rho, long k, long n, double z) {
  k = ((k % n) + n) % n;
  double c = std::cos(2 * kPi * static_cast<double>(k) / static_cast<double>(n));
  double s = std::sin(2 * kPi * static_cast<double>(k) / static_cast<double>(n));
  if ((4 * k) % n == 0) {
    const long q = 4 * k / n;
    c = q == 0 ? 1 : q == 2 ? -1 : 0;
    s = q == 1 ? 1 : q == 3 ? -1 : 0;
  }
  return Vec3(rho * c, rho * s, z);
}

/// A tet mesh of the inside of a closed triangulated surface by TetGen,
/// -pYq: a PLC whose triangles TetGen may not split (no Steiner point on
/// the surface), radius-edge ratio bounded inside. The surface points come
/// first, in order.
inline Status tetrahedralize_surface(const SurfaceBuilder& s, std::vector<Vec3>& points, std::vector<Tet>& tets) {
  const Status st = internal::tetgen_plc(s.points, s.triangles, {}, "pYq1.4Q", points, tets);
  if (!st) return Status::failure("make_cylinder_half_tube: TetGen failed on an object surface: " + st.message);
  return Status::success();
}

/// Divisions of a length into segments near `edge` long.
inline int divisions(double length, double edge) {
  return std::max(1, static_cast<int>(std::lround(length / edge)));
}

/// A disk cap at height z (radius r, n segments on its rim): rings of
/// radius r j / m, about `edge` apart, each cut into segments near `edge`,
/// stitched ring to ring from the centre.
inline void disk(SurfaceBuilder& s, double r, int n, double z, double edge) {
  const int m = divisions(r, edge);
  std::vector<index_t> inner{s.point(Vec3(0, 0, z))};
  std::vector<double> t_inner{0.0};
  for (int j = 1; j <= m; ++j) {
    const int nj = j == m ? n : std::max(3, static_cast<int>(std::lround(static_cast<double>(n) * j / m)));
    std::vector<index_t> ring;
    std::vector<double> t;
    for (int k = 0; k <= nj; ++k) {
      ring.push_back(s.point(polar(r * j / m, k, nj, z)));
      t.push_back(static_cast<double>(k) / nj);
    }
    s.stitch(inner, t_inner, ring, t);
    inner = ring;
    t_inner = t;
  }
}

/// A half annulus at height z: y <= 0, radii r to R, n_in and n_out
/// segments on its inner and outer half circles.
inline void half_annulus(SurfaceBuilder& s, double r, double R, int n_in, int n_out, double z, double edge) {
  const int m = divisions(R - r, edge);
  std::vector<index_t> inner;
  std::vector<double> t_inner;
  for (int j = 0; j <= m; ++j) {
    const double rho = j == m ? R : r + (R - r) * j / m;
    const int nj = j == 0 ? n_in : j == m ? n_out : std::max(1, static_cast<int>(std::lround(n_in * rho / r)));
    std::vector<index_t> ring;
    std::vector<double> t;
    for (int k = 0; k <= nj; ++k) {
      ring.push_back(s.point(polar(rho, nj + k, 2 * nj, z)));  // theta = pi + pi k / nj
      t.push_back(static_cast<double>(k) / nj);
    }
    if (j > 0) s.stitch(inner, t_inner, ring, t);
    inner = ring;
    t_inner = t;
  }
}

/// A closed cylinder about the z axis: radius r, n segments of the circle,
/// z in [z0, z1]; the side in n x n_z quads, two disk caps.
inline void cylinder_surface(SurfaceBuilder& cyl, double r, int n, double z0, double z1, double h) {
  const int nzc = divisions(z1 - z0, h);
  const auto zc = [&](int l) { return l == nzc ? z1 : z0 + (z1 - z0) * l / nzc; };
  for (int l = 0; l < nzc; ++l)
    for (int k = 0; k < n; ++k)
      cyl.quad(cyl.point(polar(r, k, n, zc(l))), cyl.point(polar(r, k + 1, n, zc(l))),
               cyl.point(polar(r, k + 1, n, zc(l + 1))), cyl.point(polar(r, k, n, zc(l + 1))), (k + l) % 2);
  disk(cyl, r, n, z0, h);
  disk(cyl, r, n, z1, h);
}

/// A closed half tube (y <= 0) about the z axis, z in [z0, z1]: inner and
/// outer half cylinders (radii r < R, nh and no segments of the half
/// circles), the two flat cut faces at y = 0, the two half-annulus ends.
inline void half_tube_surface(SurfaceBuilder& tube, double r, double R, int nh, int no, double z0, double z1,
                              double h) {
  const int n = 2 * nh;
  const int nzt = divisions(z1 - z0, h);
  const auto zt = [&](int l) { return l == nzt ? z1 : z0 + (z1 - z0) * l / nzt; };
  for (int l = 0; l < nzt; ++l) {
    for (int k = 0; k < nh; ++k)  // theta = pi + pi k / nh
      tube.quad(tube.point(polar(r, nh + k, n, zt(l))), tube.point(polar(r, nh + k + 1, n, zt(l))),
                tube.point(polar(r, nh + k + 1, n, zt(l + 1))), tube.point(polar(r, nh + k, n, zt(l + 1))),
                (k + l) % 2);
    for (int k = 0; k < no; ++k)
      tube.quad(tube.point(polar(R, no + k, 2 * no, zt(l))), tube.point(polar(R, no + k + 1, 2 * no, zt(l))),
                tube.point(polar(R, no + k + 1, 2 * no, zt(l + 1))), tube.point(polar(R, no + k, 2 * no, zt(l + 1))),
                (k + l) % 2);
    const int mr = divisions(R - r, h);
    for (int side = 0; side < 2; ++side)  // x < 0 (theta = pi), x > 0 (theta = 2 pi)
      for (int j = 0; j < mr; ++j) {
        const double sign = side ? 1 : -1;
        const double a = sign * (r + (R - r) * j / mr), b = sign * (j + 1 == mr ? R : r + (R - r) * (j + 1) / mr);
        tube.quad(tube.point(Vec3(a, 0, zt(l))), tube.point(Vec3(b, 0, zt(l))), tube.point(Vec3(b, 0, zt(l + 1))),
                  tube.point(Vec3(a, 0, zt(l + 1))), (j + l) % 2);
      }
  }
  half_annulus(tube, r, R, nh, no, z0, h);
  half_annulus(tube, r, R, nh, no, z1, h);
}

}  // namespace detail

/// Improve's Phased ODT on each material's tets in turn (thesis 3.6's
/// improvement, as Adapt runs it on a region), every boundary and interface
/// vertex fixed: the surfaces stay exact and the materials conformal, only
/// inner vertices move, and flips and degenerate-element removal repair the
/// slivers TetGen's -q (a radius-edge bound) lets through. Vertices a
/// material's improvement removed are dropped, new ones appended.
/// `density`: with the mesh's own density as the target (edges split and
/// collapsed toward it); without, smoothing and flips only.
inline Status improve_material_mesh(MaterialMesh& m, bool density = false, double quality_floor = 0.3) {
  std::vector<int> materials(m.material);
  std::sort(materials.begin(), materials.end());
  materials.erase(std::unique(materials.begin(), materials.end()), materials.end());
  DensityGrid grid;
  if (density) {
    double edge = 0;
    const std::vector<double> rho = vertex_density(m.points, m.tets, &edge);
    if (!grid.build(m.points, m.tets, rho, 0.5 * edge, std::size_t(1) << 24, false))
      return Status::failure("improve_material_mesh: no density grid");
  }
  for (const int material : materials) {
    TetMesh mesh;
    Status s = mesh.build(m.points, m.tets);
    if (!s) return Status::failure("improve_material_mesh: " + s.message);
    std::vector<index_t> part;
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      if (m.material[t] == material) part.push_back(static_cast<index_t>(t));
    RegionMesh rm;
    s = make_region_mesh(mesh, part, rm);
    if (!s) return Status::failure("improve_material_mesh: material " + std::to_string(material) + ": " + s.message);
    s = improve_deformed_region(rm, density ? &grid : nullptr, 1.0, quality_floor);
    if (!s) return Status::failure("improve_material_mesh: material " + std::to_string(material) + ": " + s.message);
    // The part's vertices by their ids in m (new ones appended), the other
    // materials' tets as they were.
    const TetMesh& p = rm.mesh;
    const index_t built = static_cast<index_t>(rm.global_vertex.size());
    std::vector<index_t> id(static_cast<std::size_t>(p.vertex_slots()), kInvalidIndex);
    std::vector<Vec3> points = m.points;
    for (index_t v = 0; v < p.vertex_slots(); ++v) {
      if (!p.vertex_alive(v)) continue;
      if (v < built) {
        id[v] = rm.global_vertex[v];
        points[id[v]] = p.point(v);
      } else {
        id[v] = static_cast<index_t>(points.size());
        points.push_back(p.point(v));
      }
    }
    std::vector<Tet> tets;
    std::vector<int> material_of;
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      if (m.material[t] != material) {
        tets.push_back(m.tets[t]);
        material_of.push_back(m.material[t]);
      }
    for (index_t t = 0; t < p.tet_slots(); ++t) {
      if (!p.tet_alive(t)) continue;
      Tet T = p.tet(t);
      for (index_t& v : T) v = id[v];
      tets.push_back(T);
      material_of.push_back(material);
    }
    // Drop the points no tet uses any more (collapsed inner vertices).
    std::vector<index_t> used(points.size(), kInvalidIndex);
    for (const Tet& T : tets)
      for (const index_t v : T) used[v] = 0;
    m.points.clear();
    for (std::size_t v = 0; v < points.size(); ++v)
      if (used[v] == 0) {
        used[v] = static_cast<index_t>(m.points.size());
        m.points.push_back(points[v]);
      }
    for (Tet& T : tets)
      for (index_t& v : T) v = used[v];
    m.tets = std::move(tets);
    m.material = std::move(material_of);
  }
  return Status::success();
}

/// The 3.7.3 case as one conformal tet mesh: material 1 the cylinder, 2 the
/// half tube (each meshed by TetGen -pYq from its exact surface
/// triangulation, the curved surfaces' points on the analytic cylinders;
/// the two share no vertex), 0 the space around them in the box (by
/// mesh_space_around). object_lo/hi: the cylinder's box at step 0. On
/// failure: an empty mesh and the reason in *status.
inline MaterialMesh make_cylinder_half_tube(const CylinderHalfTube& g = {}, Status* status = nullptr) {
  using detail::divisions;
  using detail::polar;
  MaterialMesh m;
  const auto fail = [&](const std::string& why) {
    if (status) *status = Status::failure(why);
    return MaterialMesh{};
  };
  if (g.n_theta < 4 || g.n_theta % 2 || !(g.r > 0) || !(g.R > g.r) || !(g.Lc > 0) || !(g.Lt > 0) ||
      !(g.gap > 0) || !(g.margin > 0))
    return fail("make_cylinder_half_tube: need n_theta even >= 4, 0 < r < R, Lc, Lt, gap, margin > 0");
  const double h = g.edge();
  const int n = g.n_theta, nh = g.n_half(), no = g.n_outer_half();

  detail::SurfaceBuilder cyl;
  cyl.quantum = 1e-9 * h;
  const double z0 = -g.Lc - g.gap, z1 = -g.gap;
  detail::cylinder_surface(cyl, g.r, n, z0, z1, h);
  detail::SurfaceBuilder tube;
  tube.quantum = cyl.quantum;
  detail::half_tube_surface(tube, g.r, g.R, nh, no, 0.0, g.Lt, h);

  std::vector<Vec3> cp, tp;
  std::vector<Tet> ct, tt;
  Status s = detail::tetrahedralize_surface(cyl, cp, ct);
  if (!s) return fail(s.message + " (cylinder)");
  s = detail::tetrahedralize_surface(tube, tp, tt);
  if (!s) return fail(s.message + " (half tube)");
  std::vector<Vec3> points = cp;
  points.insert(points.end(), tp.begin(), tp.end());
  std::vector<Tet> tets = ct;
  std::vector<int> material(ct.size(), 1);
  const index_t offset = static_cast<index_t>(cp.size());
  for (Tet t : tt) {
    for (index_t& v : t) v += offset;
    tets.push_back(t);
    material.push_back(2);
  }
  const double w = g.R + g.margin;
  const Vec3 lo(-w, -w, z0 - g.margin), hi(w, w, std::max(g.Lt, z1 + g.planned_travel()) + g.margin);
  s = mesh_space_around(points, tets, material, lo, hi, g.space_edge, m.points, m.tets, m.material);
  if (!s) return fail(s.message);
  if (g.improve) {
    s = improve_material_mesh(m);
    if (!s) return fail(s.message);
  }
  m.object_lo = Vec3(-g.r, -g.r, z0);
  m.object_hi = Vec3(g.r, g.r, z1);
  if (status) *status = Status::success();
  return m;
}

/// Thesis 3.7.4's kind of input: an assembly of two parts meshed
/// separately, no space mesh. A crank shaft (material 1: a cylinder of
/// radius r about the z axis, z in [-Lc/2, Lc/2], n_crank segments, its
/// polygon turned by half a segment) lies in the bore of a bearing (material
/// 2: a half tube, y <= 0, radii r to R, z in [-Lb/2, Lb/2], n_bearing
/// segments of the full circle). Both are meshed by TetGen -pYq from exact
/// surface triangulations of their own spacing: the touching surfaces (the
/// crank's lower half, the bore) are non-conforming; they share no vertex.
/// The crank turns about its axis (the z axis).
struct CrankAssembly {
  double r = 1.0;       ///< the crank's radius = the bore's
  double R = 1.8;       ///< the bearing's outer radius
  double Lc = 6.0;      ///< the crank's length (> Lb: it passes through)
  double Lb = 3.0;      ///< the bearing's length
  int n_crank = 28;     ///< segments of the crank's circle
  int n_bearing = 20;   ///< segments of the bore's full circle (even)

  double crank_edge() const { return 2 * r * std::sin(kPi / n_crank); }
  double bearing_edge() const { return 2 * r * std::sin(kPi / n_bearing); }
  /// The faces between the parts once conformal: the bore's half polygon
  /// (n_bearing / 2 chords) over Lb.
  double contact_area() const { return n_bearing / 2 * bearing_edge() * Lb; }
  /// About thesis 3.7.4's size (6,694 vertices, 25,320 tets): 6,579
  /// vertices, 24,490 tets.
  static CrankAssembly benchmark() {
    CrankAssembly g;
    g.Lc = 5;
    g.n_crank = 60;
    g.n_bearing = 40;
    return g;
  }
};

inline MaterialMesh make_crank_assembly(const CrankAssembly& g = {}, Status* status = nullptr) {
  const auto fail = [&](const std::string& why) {
    if (status) *status = Status::failure(why);
    return MaterialMesh{};
  };
  if (g.n_crank < 6 || g.n_bearing < 4 || g.n_bearing % 2 || !(g.r > 0) || !(g.R > g.r) || !(g.Lc > g.Lb) ||
      !(g.Lb > 0))
    return fail("make_crank_assembly: need n_crank >= 6, n_bearing even >= 4, 0 < r < R, Lc > Lb > 0");
  detail::SurfaceBuilder crank, bearing;
  const double hc = g.crank_edge(), hb = g.bearing_edge();
  crank.quantum = bearing.quantum = 1e-9 * std::min(hc, hb);
  detail::cylinder_surface(crank, g.r, g.n_crank, -0.5 * g.Lc, 0.5 * g.Lc, hc);
  const int nh = g.n_bearing / 2, no = std::max(nh, static_cast<int>(std::lround(nh * g.R / g.r)));
  detail::half_tube_surface(bearing, g.r, g.R, nh, no, -0.5 * g.Lb, 0.5 * g.Lb, hb);
  std::vector<Vec3> cp, bp;
  std::vector<Tet> ct, bt;
  Status s = detail::tetrahedralize_surface(crank, cp, ct);
  if (!s) return fail(s.message + " (crank)");
  s = detail::tetrahedralize_surface(bearing, bp, bt);
  if (!s) return fail(s.message + " (bearing)");
  // The crank's polygon turned by half a segment: no vertex of it on the
  // bore's edges (y = 0).
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(kPi / g.n_crank, Vec3::UnitZ()).toRotationMatrix();
  MaterialMesh m;
  for (const Vec3& p : cp) m.points.push_back(turn * p);
  m.tets = ct;
  m.material.assign(ct.size(), 1);
  const index_t offset = static_cast<index_t>(cp.size());
  m.points.insert(m.points.end(), bp.begin(), bp.end());
  for (Tet t : bt) {
    for (index_t& v : t) v += offset;
    m.tets.push_back(t);
    m.material.push_back(2);
  }
  m.object_lo = Vec3(-g.r, -g.r, -0.5 * g.Lc);
  m.object_hi = Vec3(g.r, g.r, 0.5 * g.Lc);
  if (status) *status = Status::success();
  return m;
}

using FaceKey = std::array<index_t, 3>;

inline FaceKey sorted_face(const Tet& t, int f) {
  FaceKey k{{t[kTetFace[f][0]], t[kTetFace[f][1]], t[kTetFace[f][2]]}};
  std::sort(k.begin(), k.end());
  return k;
}

struct AssemblyConformity {
  std::size_t shared = 0;      ///< faces of one tet of each part
  double shared_area = 0;
  std::size_t coincident = 0;  ///< boundary faces of part 1 lying on a boundary face of part 2
};

/// The contact of an assembly output (materials 1 and 2, an independent
/// check for 3.7.4): faces between the parts by vertex ids; and boundary faces of part 1 (near
/// the bore: within `reach` of radius r, y <= reach) whose centroid lies on a
/// boundary face of part 2 (within `tol`): a contact left non-conforming.
inline AssemblyConformity assembly_conformity(const AdaptOutput& out, double r, double reach, double tol) {
  AssemblyConformity c;
  std::map<FaceKey, std::vector<std::pair<std::size_t, int>>> faces;
  for (std::size_t t = 0; t < out.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) faces[sorted_face(out.tets[t], f)].push_back({t, f});
  std::vector<std::array<Vec3, 3>> crank, bearing;
  for (const auto& [k, users] : faces) {
    const Vec3 &a = out.points[k[0]], &b = out.points[k[1]], &d = out.points[k[2]];
    if (users.size() == 2) {
      const int m0 = out.material[users[0].first], m1 = out.material[users[1].first];
      if (std::min(m0, m1) == 1 && std::max(m0, m1) == 2) {
        ++c.shared;
        c.shared_area += 0.5 * (b - a).cross(d - a).norm();
      }
      continue;
    }
    const Vec3 g = (a + b + d) / 3;
    if (std::abs(std::hypot(g.x(), g.y()) - r) > reach || g.y() > reach) continue;
    (out.material[users[0].first] == 1 ? crank : bearing).push_back({{a, b, d}});
  }
  for (const auto& f : crank) {
    const Vec3 g = (f[0] + f[1] + f[2]) / 3;
    for (const auto& h : bearing)
      if ((closest_point_on_triangle(g, h[0], h[1], h[2]) - g).norm() < tol) {
        ++c.coincident;
        break;
      }
  }
  return c;
}

}  // namespace testing
}  // namespace femorph
