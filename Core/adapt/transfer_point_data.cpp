// Field transfer between steps (beyond the thesis): the point data
// of step n at a space vertex is the data of step n - 1 interpolated at the
// vertex's new position (linear in the tet of the old mesh that holds it),
// so a solver continuing on the new mesh sees the same field in space. The
// object's vertices carry their data with them (their provenance is kept).
// A space vertex that moved into the volume the object left takes the data
// of the object's tets there (the previous field is defined on the whole
// mesh).
#include "adapt/adapt.h"

#include "mesh/vertex_stencil.h"

namespace femorph {

namespace {

/// Barycentric coordinates of p in tet (a, b, c, d).
Eigen::Vector4d barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& p) {
  Eigen::Matrix3d m;
  m.col(0) = b - a;
  m.col(1) = c - a;
  m.col(2) = d - a;
  const Vec3 x = m.partialPivLu().solve(p - a);
  return Eigen::Vector4d(1 - x.sum(), x.x(), x.y(), x.z());
}

}  // namespace

std::vector<VertexStencil> transfer_point_data(const TetMesh& before, const TetMesh& now,
                                               const std::vector<VertexStencil>& origin,
                                               const TransferBeyond& beyond) {
  const index_t built = before.vertex_slots();
  std::vector<VertexStencil> out(static_cast<std::size_t>(now.vertex_slots()));
  std::vector<index_t> ball;
  for (index_t v = 0; v < now.vertex_slots(); ++v) {
    if (!now.vertex_alive(v)) continue;
    // The build-time vertex to start from: itself, or the first of the
    // vertices a new one was made from.
    const index_t start = v < built ? v : now.vertex_origin(v).ids[0];
    if (start < 0 || start >= built) continue;
    out[v] = origin[start];
    const Vec3& p = now.point(v);
    if (v < built && p == before.point(v)) continue;
    before.vertex_ball(start, ball);
    if (ball.empty()) continue;
    index_t t = ball[0];
    // A walk through the old mesh toward p: leave by the face with the most
    // negative barycentric coordinate.
    for (int steps = 0; steps < 1000; ++steps) {
      const Tet& T = before.tet(t);
      const Eigen::Vector4d w =
          barycentric(before.point(T[0]), before.point(T[1]), before.point(T[2]), before.point(T[3]), p);
      int worst = 0;
      for (int k = 1; k < 4; ++k)
        if (w[k] < w[worst]) worst = k;
      if (w[worst] >= -1e-12) {
        const VertexStencil* stencils[4] = {&origin[T[0]], &origin[T[1]], &origin[T[2]], &origin[T[3]]};
        double weights[4];
        for (int k = 0; k < 4; ++k) weights[k] = std::max(0.0, w[k]);
        const double sum = weights[0] + weights[1] + weights[2] + weights[3];
        for (double& x : weights) x /= sum;
        out[v] = combine_stencils(stencils, weights, 4);
        break;
      }
      const index_t code = before.adjacency(t, worst);
      if (code < 0) {
        if (beyond) beyond(p, {T[kTetFace[worst][0]], T[kTetFace[worst][1]], T[kTetFace[worst][2]]}, out[v]);
        break;
      }
      t = code >> 2;
    }
  }
  return out;
}

}  // namespace femorph
