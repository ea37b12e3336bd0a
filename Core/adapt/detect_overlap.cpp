// Penetration check of the assembly mode (thesis 3.7.4: parts meshed
// separately, no space mesh). Beyond the thesis, which assumes a valid
// motion: detect_penetration walks through space, which an assembly has
// none of; here each point is located in the other parts' tets (a uniform
// grid), and one found inside a part farther than the tolerance from that
// part's boundary is an overlap. Coincident surfaces (contact, each part's
// chords on the same curved surface) stay within the tolerance.
#include "adapt/adapt.h"

#include "geometry/discrete_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace femorph {

namespace {

struct BoxGrid {
  Vec3 origin = Vec3::Zero();
  double h = 1;
  std::array<int, 3> n{{1, 1, 1}};
  std::vector<std::vector<index_t>> cells;

  std::array<int, 3> cell(const Vec3& p) const {
    std::array<int, 3> c;
    for (int a = 0; a < 3; ++a)
      c[a] = std::clamp(static_cast<int>(std::floor((p[a] - origin[a]) / h)), 0, n[a] - 1);
    return c;
  }
  std::size_t id(int i, int j, int k) const { return (static_cast<std::size_t>(k) * n[1] + j) * n[0] + i; }
  void add(const Vec3& lo, const Vec3& hi, index_t item) {
    const auto a = cell(lo), b = cell(hi);
    for (int k = a[2]; k <= b[2]; ++k)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int i = a[0]; i <= b[0]; ++i) cells[id(i, j, k)].push_back(item);
  }
  bool inside(const Vec3& p) const {
    for (int a = 0; a < 3; ++a)
      if (p[a] < origin[a] || p[a] > origin[a] + h * n[a]) return false;
    return true;
  }
};

}  // namespace

Status detect_overlap(const TetMesh& mesh, const std::vector<int>& material_by_origin, int material,
                      const std::vector<Vec3>& points, double tolerance) {
  std::vector<index_t> tets;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double volume = 0;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const int m = material_by_origin[mesh.tet_origin(t)];
    if (m <= 0 || m == material) continue;
    tets.push_back(t);
    const Tet& T = mesh.tet(t);
    for (const index_t v : T) {
      lo = lo.cwiseMin(mesh.point(v));
      hi = hi.cwiseMax(mesh.point(v));
    }
    const Vec3 &a = mesh.point(T[0]), &b = mesh.point(T[1]), &c = mesh.point(T[2]), &d = mesh.point(T[3]);
    volume += std::abs((b - a).dot((c - a).cross(d - a))) / 6;
  }
  if (tets.empty() || points.empty()) return Status::success();
  // Cells of about 8 tets' volume, at most about 1M of them.
  BoxGrid grid;
  const Vec3 extent = hi - lo;
  grid.h = std::max({std::cbrt(8 * volume / static_cast<double>(tets.size())),
                     std::cbrt(extent.x() * extent.y() * extent.z() / 1e6), 1e-12 * extent.norm()});
  grid.origin = lo - Vec3::Constant(tolerance);
  for (int a = 0; a < 3; ++a) grid.n[a] = std::max(1, static_cast<int>(std::ceil((extent[a] + 2 * tolerance) / grid.h)));
  grid.cells.assign(static_cast<std::size_t>(grid.n[0]) * grid.n[1] * grid.n[2], {});
  BoxGrid faces = grid;  // the parts' boundary faces, codes 4 t + f
  for (const index_t t : tets) {
    const Tet& T = mesh.tet(t);
    Vec3 a = mesh.point(T[0]), b = a;
    for (const index_t v : T) {
      a = a.cwiseMin(mesh.point(v));
      b = b.cwiseMax(mesh.point(v));
    }
    grid.add(a, b, t);
    const int m = material_by_origin[mesh.tet_origin(t)];
    for (int f = 0; f < 4; ++f) {
      const index_t code = mesh.adjacency(t, f);
      if (code >= 0 && material_by_origin[mesh.tet_origin(code >> 2)] == m) continue;
      Vec3 fa = mesh.point(T[kTetFace[f][0]]), fb = fa;
      for (int k = 1; k < 3; ++k) {
        fa = fa.cwiseMin(mesh.point(T[kTetFace[f][k]]));
        fb = fb.cwiseMax(mesh.point(T[kTetFace[f][k]]));
      }
      faces.add(fa - Vec3::Constant(tolerance), fb + Vec3::Constant(tolerance), 4 * t + f);
    }
  }
  for (const Vec3& p : points) {
    if (!grid.inside(p)) continue;
    const auto c = grid.cell(p);
    int owner = 0;
    for (const index_t t : grid.cells[grid.id(c[0], c[1], c[2])]) {
      const Tet& T = mesh.tet(t);
      const Vec3 &a = mesh.point(T[0]), &b = mesh.point(T[1]), &d = mesh.point(T[2]), &e = mesh.point(T[3]);
      Eigen::Matrix3d M;
      M.col(0) = b - a;
      M.col(1) = d - a;
      M.col(2) = e - a;
      const Vec3 x = M.partialPivLu().solve(p - a);
      if (x.minCoeff() >= 0 && x.sum() <= 1) {
        owner = material_by_origin[mesh.tet_origin(t)];
        break;
      }
    }
    if (owner == 0) continue;
    bool near_surface = false;
    for (const index_t code : faces.cells[faces.id(c[0], c[1], c[2])]) {
      const index_t t = code >> 2;
      if (material_by_origin[mesh.tet_origin(t)] != owner) continue;
      const Tet& T = mesh.tet(t);
      const int f = static_cast<int>(code & 3);
      const Vec3 q = closest_point_on_triangle(p, mesh.point(T[kTetFace[f][0]]), mesh.point(T[kTetFace[f][1]]),
                                               mesh.point(T[kTetFace[f][2]]));
      if ((q - p).norm() <= tolerance) {
        near_surface = true;
        break;
      }
    }
    if (near_surface) continue;
    std::ostringstream os;
    os << "object " << material << " would overlap object " << owner << ": its surface point (" << p.x() << ", "
       << p.y() << ", " << p.z() << ") lies inside object " << owner << ", farther than " << tolerance
       << " from its surface";
    return Status::failure(os.str());
  }
  return Status::success();
}

}  // namespace femorph
