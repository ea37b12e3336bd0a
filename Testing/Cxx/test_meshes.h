// Meshes built at run time for tests and benchmarks.
#pragma once

#include "common/types.h"

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace femorph {
namespace testing {

struct TestMesh {
  std::vector<Vec3> points;
  std::vector<Tet> tets;
  std::vector<Tet> face_regions;  // per tet face: region id on the boundary, -1 inside
};

/// The unit cube [0, 1]^3 cut into n^3 cells of 6 tets each (Kuhn's
/// subdivision: every cell split along its main diagonal, so neighbouring
/// cells match). Vertices are jittered by up to `jitter` times the cell size,
/// interior ones in 3D, boundary ones within their face or edge only, corners
/// not at all, so the cube's shape and volume stay exact. Boundary faces get
/// regions 0..5 for the planes x=0, x=1, y=0, y=1, z=0, z=1. All tets are
/// positively oriented when jitter < 0.15 or so.
inline TestMesh make_cube_mesh(int n, double jitter, std::uint64_t seed) {
  TestMesh m;
  const int n1 = n + 1;
  const double h = 1.0 / n;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto id = [n1](int i, int j, int k) { return static_cast<index_t>((k * n1 + j) * n1 + i); };
  m.points.resize(static_cast<std::size_t>(n1) * n1 * n1);
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        Vec3 p(i * h, j * h, k * h);
        const int idx[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          const double d = u(rng) * jitter * h;  // drawn always: same stream for any n
          if (idx[a] != 0 && idx[a] != n) p[a] += d;
        }
        m.points[id(i, j, k)] = p;
      }
  // Kuhn subdivision: one tet per permutation of the axes, walking from the
  // cell's (0,0,0) corner to its (1,1,1) corner.
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& perm : perms) {
          int c[3] = {i, j, k};
          Tet t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[perm[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          // Odd permutations give negative tets: swap two vertices.
          const Vec3& p0 = m.points[t[0]];
          if ((m.points[t[1]] - p0).dot((m.points[t[2]] - p0).cross(m.points[t[3]] - p0)) < 0) std::swap(t[1], t[2]);
          m.tets.push_back(t);
        }
  // Regions: a face is on plane x=0 when its three vertices have i == 0, etc.
  static const int face_local[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  m.face_regions.assign(m.tets.size(), Tet{{-1, -1, -1, -1}});
  auto grid = [n1](index_t v, int axis) {
    const int i = v % n1, j = (v / n1) % n1, k = v / (n1 * n1);
    return axis == 0 ? i : (axis == 1 ? j : k);
  };
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int f = 0; f < 4; ++f)
      for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
          const int target = side ? n : 0;
          bool all = true;
          for (int q = 0; q < 3; ++q) all = all && grid(m.tets[t][face_local[f][q]], axis) == target;
          if (all) m.face_regions[t][f] = 2 * axis + side;
        }
  return m;
}

/// The box [0, 1] x [0, 1] x [0, depth] on the body-centred cubic lattice of
/// spacing 1/n (n cells across, n * depth along z): the cells' corners and
/// centres; every face between two cells gives the octahedron of its square
/// and the two centres (4 tets around the centre-to-centre edge), every face
/// on the boundary the pyramid of its square and its cell's centre (2 tets).
/// Inside, edges are h (corner-corner, centre-centre) or 0.87 h (centre to
/// corner): a mesh as uniform as a mesh generator's best, like the thesis'
/// Netgen mesh of Fig. 2.53. Boundary faces get regions 0..5 as in
/// make_cube_mesh (planes x=0, x=1, y=0, y=1, z=0, z=depth).
inline TestMesh make_bcc_box_mesh(int n, int depth) {
  TestMesh m;
  const int nx = n, ny = n, nz = n * depth;
  const double h = 1.0 / n;
  const auto corner = [&](int i, int j, int k) { return static_cast<index_t>((k * (ny + 1) + j) * (nx + 1) + i); };
  const index_t corners = corner(nx, ny, nz) + 1;
  const auto centre = [&](int i, int j, int k) { return corners + static_cast<index_t>((k * ny + j) * nx + i); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.points.emplace_back(i * h, j * h, k * h);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) m.points.emplace_back((i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h);
  const auto add = [&m](Tet t, int region) {
    const Vec3& p0 = m.points[t[0]];
    if ((m.points[t[1]] - p0).dot((m.points[t[2]] - p0).cross(m.points[t[3]] - p0)) < 0) std::swap(t[1], t[2]);
    m.tets.push_back(t);
    Tet regions{{-1, -1, -1, -1}};
    // The boundary face is the one opposite the cell centre (local 0 or,
    // after the swap, still the first vertex: the centre is passed first).
    regions[0] = region;
    m.face_regions.push_back(regions);
  };
  const int size[3] = {nx, ny, nz};
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    // Square faces normal to `axis` at layer l, spanned by cells (a, b) in (u, w).
    for (int l = 0; l <= size[axis]; ++l)
      for (int a = 0; a < size[u]; ++a)
        for (int b = 0; b < size[w]; ++b) {
          index_t q[4];  // the square's corners in order around it
          static const int du[4] = {0, 1, 1, 0}, dw[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            int x[3];
            x[axis] = l;
            x[u] = a + du[c];
            x[w] = b + dw[c];
            q[c] = corner(x[0], x[1], x[2]);
          }
          const auto cell_centre = [&](int layer) {
            int x[3];
            x[axis] = layer;
            x[u] = a;
            x[w] = b;
            return centre(x[0], x[1], x[2]);
          };
          if (l > 0 && l < size[axis]) {
            const index_t c0 = cell_centre(l - 1), c1 = cell_centre(l);
            for (int c = 0; c < 4; ++c) add(Tet{{c0, c1, q[c], q[(c + 1) % 4]}}, -1);
          } else {
            const index_t c0 = cell_centre(l == 0 ? 0 : l - 1);
            const int region = 2 * axis + (l == 0 ? 0 : 1);
            const int d = (a + b) % 2;  // alternate diagonals
            add(Tet{{c0, q[d], q[d + 1], q[(d + 2) % 4]}}, region);
            add(Tet{{c0, q[d], q[(d + 2) % 4], q[(d + 3) % 4]}}, region);
          }
        }
  }
  return m;
}

/// Sum of signed tet volumes.
inline double total_volume(const std::vector<Vec3>& p, const std::vector<Tet>& tets) {
  double v = 0;
  for (const Tet& t : tets) v += (p[t[1]] - p[t[0]]).dot((p[t[2]] - p[t[0]]).cross(p[t[3]] - p[t[0]])) / 6.0;
  return v;
}

}  // namespace testing
}  // namespace femorph
