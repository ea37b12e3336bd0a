// build_surface_mesh: the closed triangulated surface the segmentation works
// on (thesis 2.4), with edge adjacency found through vertex stars in O(#F).
#include "mesh/surface_mesh.h"
#include "common/parallel.h"

#include <functional>
#include <array>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <string>

namespace femorph {
namespace {

// A triangle whose doubled area is below this times its longest squared edge
// has no usable normal (a needle or a cap flattened to rounding noise).
constexpr double kDegenerateRatio = 1e-12;

}  // namespace

Status build_surface_mesh(std::vector<Vec3> points, std::vector<Tri> triangles, SurfaceMesh& out,
                          bool allow_open, SurfaceReport* report) {
  out = SurfaceMesh();
  if (report) *report = SurfaceReport();
  const index_t np = static_cast<index_t>(points.size());
  const index_t nf = static_cast<index_t>(triangles.size());
  if (points.size() > static_cast<std::size_t>(INT32_MAX) || triangles.size() > static_cast<std::size_t>(INT32_MAX / 3))
    return Status::failure("surface too large for 32-bit ids");

  // Input checks: indices in range, three distinct vertices, finite points.
  for (index_t f = 0; f < nf; ++f) {
    const Tri& t = triangles[f];
    for (int k = 0; k < 3; ++k)
      if (t[k] < 0 || t[k] >= np)
        return Status::failure("triangle " + std::to_string(f) + " refers to vertex " + std::to_string(t[k]) +
                               " of " + std::to_string(np));
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      return Status::failure("triangle " + std::to_string(f) + " repeats a vertex");
  }
  for (index_t v = 0; v < np; ++v)
    if (!points[v].allFinite()) return Status::failure("vertex " + std::to_string(v) + " is not finite");

  out.points = std::move(points);
  out.triangles = std::move(triangles);
  const std::vector<Vec3>& p = out.points;
  const std::vector<Tri>& tris = out.triangles;

  // Normals and areas.
  out.normals.resize(nf);
  out.areas.resize(nf);
  const std::size_t degenerate = parallel_reduce(
      static_cast<long>(nf), std::size_t(0),
      [&](long begin, long end, int) {
        std::size_t count = 0;
        for (index_t f = static_cast<index_t>(begin); f < static_cast<index_t>(end); ++f) {
          const Vec3& a = p[tris[f][0]];
          const Vec3 e1 = p[tris[f][1]] - a, e2 = p[tris[f][2]] - a;
          const Vec3 c = e1.cross(e2);
          const double twice_area = c.norm();
          const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (e2 - e1).squaredNorm()});
          out.areas[f] = 0.5 * twice_area;
          if (twice_area > kDegenerateRatio * longest2 && twice_area > 0) {
            out.normals[f] = c / twice_area;
          } else {
            out.normals[f].setZero();
            ++count;
          }
        }
        return count;
      },
      std::plus<std::size_t>());

  // Vertex -> triangle incidence (CSR, triangles in ascending order).
  out.vertex_offsets.assign(static_cast<std::size_t>(np) + 1, 0);
  for (const Tri& t : tris)
    for (int k = 0; k < 3; ++k) ++out.vertex_offsets[t[k] + 1];
  for (index_t v = 0; v < np; ++v) out.vertex_offsets[v + 1] += out.vertex_offsets[v];
  out.vertex_triangles.resize(static_cast<std::size_t>(nf) * 3);
  {
    std::vector<index_t> fill(out.vertex_offsets.begin(), out.vertex_offsets.end() - 1);
    for (index_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) out.vertex_triangles[fill[tris[f][k]]++] = f;
  }

  // Edge adjacency: the triangles sharing edge (a, b) are found in the star of
  // a. Each edge is counted once: by its lowest triangle.
  out.neighbors.resize(nf);
  using EdgeCounts = std::array<std::size_t, 3>;  // open, nonmanifold, misoriented
  const EdgeCounts counts = parallel_reduce(
      static_cast<long>(nf), EdgeCounts{},
      [&](long begin, long end, int) {
        std::size_t open = 0, nonmanifold = 0, misoriented = 0;
        for (index_t f = static_cast<index_t>(begin); f < static_cast<index_t>(end); ++f) {
          for (int k = 0; k < 3; ++k) {
            const index_t a = tris[f][k], b = tris[f][(k + 1) % 3];
            index_t other = kInvalidIndex, lowest = f;
            int count = 0;
            bool same_direction = false;
            for (index_t s = out.vertex_offsets[a]; s < out.vertex_offsets[a + 1]; ++s) {
              const index_t g = out.vertex_triangles[s];
              if (g == f) continue;
              const Tri& t = tris[g];
              const int ia = t[0] == a ? 0 : (t[1] == a ? 1 : 2);
              if (t[(ia + 1) % 3] == b) {
                same_direction = true;  // g also runs a -> b
              } else if (t[(ia + 2) % 3] != b) {
                continue;
              }
              ++count;
              other = g;
              lowest = std::min(lowest, g);
            }
            if (count == 1) {
              out.neighbors[f][k] = other;
              if (f < other) misoriented += same_direction;
            } else {
              out.neighbors[f][k] = kInvalidIndex;
              if (count == 0) {
                ++open;
              } else if (lowest == f) {
                ++nonmanifold;
              }
            }
          }
        }
        return EdgeCounts{open, nonmanifold, misoriented};
      },
      [](EdgeCounts a, const EdgeCounts& b) {
        return EdgeCounts{a[0] + b[0], a[1] + b[1], a[2] + b[2]};
      });
  const std::size_t open = counts[0], nonmanifold = counts[1], misoriented = counts[2];
  // Mean edge length, each edge once, summed in a fixed order so that it does
  // not depend on the number of threads (thresholds downstream scale by it).
  double length_sum = 0;
  std::size_t edge_count = 0;
  for (index_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const index_t g = out.neighbors[f][k];
      if (g >= 0 && g < f) continue;
      length_sum += (p[tris[f][(k + 1) % 3]] - p[tris[f][k]]).norm();
      ++edge_count;
    }
  out.mean_edge_length = edge_count ? length_sum / static_cast<double>(edge_count) : 0.0;

  if (report) {
    report->open_edges = open;
    report->nonmanifold_edges = nonmanifold;
    report->misoriented_edges = misoriented;
    report->degenerate_triangles = degenerate;
  }
  std::string problems;
  auto add = [&problems](std::size_t n, const char* what) {
    if (!n) return;
    if (!problems.empty()) problems += ", ";
    problems += std::to_string(n) + " " + what;
  };
  add(nonmanifold, "non-manifold edges (more than two triangles)");
  if (!allow_open) add(open, "open edges (one triangle)");
  add(misoriented, "edges whose two triangles are oriented inconsistently");
  if (!problems.empty()) {
    out = SurfaceMesh();
    return Status::failure("surface is not a " + std::string(allow_open ? "" : "closed ") +
                           "consistently oriented manifold: " + problems);
  }
  return Status::success();
}

}  // namespace femorph
