// Phase (2) of Phased ODT smoothing (thesis 2.6.5.3): Eq. 2.34 over the
// surface triangles around each surface vertex, in the 2D parameter plane of
// its fitted region (Fig. 2.43, 2.44 steps 1-3).
#include "improve/control_shape_accuracy.h"
#include "improve/ball_quality.h"
#include "improve/odt_smooth_surface.h"
#include "improve/relax_edge_lengths.h"

#include "common/parallel.h"
#include "improve/boundary_geometry.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

namespace femorph {

namespace {

using Vec2 = Eigen::Vector2d;

/// A unit vector perpendicular to the unit vector n (deterministic).
Vec3 perpendicular(const Vec3& n) {
  const Vec3 t = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : (std::abs(n.y()) < 0.6 ? Vec3::UnitY() : Vec3::UnitZ());
  return (t - t.dot(n) * n).normalized();
}

/// The 2D parameter plane of a fitted surface around a point x on it
/// (Fig. 2.43); angles are measured from x, so the 1-ring of x never meets
/// the seam at +-pi. map() is isometric at x.
class Chart {
 public:
  bool init(const SurfacePrimitive& s, const Vec3& x) {
    s_ = &s;
    switch (s.type) {
      case SurfaceType::Plane:
        o_ = x;
        a_ = s.axis.normalized();
        e1_ = perpendicular(a_);
        break;
      case SurfaceType::Cylinder:
      case SurfaceType::Cone:
      case SurfaceType::Torus: {
        o_ = s.point;
        a_ = s.axis.normalized();
        const Vec3 d = x - o_;
        h0_ = d.dot(a_);
        const Vec3 radial = d - h0_ * a_;
        const double rho = radial.norm();
        if (!(rho > 1e-12 * (d.norm() + s.radius))) return false;  // on the axis
        e1_ = radial / rho;
        if (s.type == SurfaceType::Cone) sin_half_ = std::sin(s.half_angle), cos_half_ = std::cos(s.half_angle);
        if (s.type == SurfaceType::Torus) {
          phi0_ = std::atan2(h0_, rho - s.radius);
          ring_ = s.radius + s.minor_radius * std::cos(phi0_);
          if (!(ring_ > 0) || !(s.minor_radius > 0)) return false;
        }
        if (s.type == SurfaceType::Cylinder && !(s.radius > 0)) return false;
        if (s.type == SurfaceType::Cone && !(sin_half_ > 0)) return false;
        break;
      }
      case SurfaceType::Sphere: {
        o_ = s.point;
        const Vec3 d = x - o_;
        if (!(d.norm() > 0) || !(s.radius > 0)) return false;
        e1_ = d.normalized();
        a_ = perpendicular(e1_);  // v on the equator: the pole is perpendicular to it
        break;
      }
      default:
        return false;
    }
    e2_ = a_.cross(e1_);
    return true;
  }

  Vec2 map(const Vec3& p) const {
    const Vec3 d = p - o_;
    const double u = d.dot(e1_), w = d.dot(e2_);
    switch (s_->type) {
      case SurfaceType::Plane:
        return Vec2(u, w);
      case SurfaceType::Cylinder:  // development: arc length, height
        return Vec2(s_->radius * std::atan2(w, u), d.dot(a_) - h0_);
      case SurfaceType::Cone: {  // development about the apex
        const double psi = std::atan2(w, u) * sin_half_;
        const double s = d.norm();
        return Vec2(s * std::cos(psi), s * std::sin(psi));
      }
      case SurfaceType::Sphere: {  // (azimuth, latitude) with v on the equator
        const double z = d.dot(a_);
        return s_->radius * Vec2(std::atan2(w, u), std::atan2(z, std::hypot(u, w)));
      }
      case SurfaceType::Torus: {  // (toroidal, poloidal) angles relative to v
        const double z = d.dot(a_);
        const double phi = std::atan2(z, std::hypot(u, w) - s_->radius);
        return Vec2(ring_ * std::atan2(w, u), s_->minor_radius * std::remainder(phi - phi0_, 2 * kPi));
      }
      default:
        return Vec2(u, w);
    }
  }

  Vec3 unmap(const Vec2& q) const {
    switch (s_->type) {
      case SurfaceType::Plane:
        return o_ + q.x() * e1_ + q.y() * e2_;
      case SurfaceType::Cylinder: {
        const double t = q.x() / s_->radius;
        return o_ + (h0_ + q.y()) * a_ + s_->radius * (std::cos(t) * e1_ + std::sin(t) * e2_);
      }
      case SurfaceType::Cone: {
        const double s = q.norm(), t = std::atan2(q.y(), q.x()) / sin_half_;
        return o_ + s * (cos_half_ * a_ + sin_half_ * (std::cos(t) * e1_ + std::sin(t) * e2_));
      }
      case SurfaceType::Sphere: {
        const double t = q.x() / s_->radius, lat = q.y() / s_->radius;
        return o_ + s_->radius * (std::cos(lat) * (std::cos(t) * e1_ + std::sin(t) * e2_) + std::sin(lat) * a_);
      }
      case SurfaceType::Torus: {
        const double t = q.x() / ring_, phi = phi0_ + q.y() / s_->minor_radius;
        const double rho = s_->radius + s_->minor_radius * std::cos(phi);
        return o_ + rho * (std::cos(t) * e1_ + std::sin(t) * e2_) + s_->minor_radius * std::sin(phi) * a_;
      }
      default:
        return o_ + q.x() * e1_ + q.y() * e2_;
    }
  }

 private:
  const SurfacePrimitive* s_ = nullptr;
  Vec3 o_ = Vec3::Zero(), a_ = Vec3::Zero(), e1_ = Vec3::Zero(), e2_ = Vec3::Zero();
  double h0_ = 0, sin_half_ = 0, cos_half_ = 0, phi0_ = 0, ring_ = 0;
};

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Circumcentre and squared radius of a 2D triangle; false when it is
/// (nearly) degenerate.
bool circumcircle(const Vec2& p0, const Vec2& p1, const Vec2& p2, Vec2* centre, double* r2) {
  const Vec2 b = p1 - p0, c = p2 - p0;
  const double d = 2 * cross2(b, c);
  if (!(std::abs(d) > 1e-12 * b.squaredNorm() + 1e-12 * c.squaredNorm())) return false;
  const Vec2 u((c.y() * b.squaredNorm() - b.y() * c.squaredNorm()) / d,
               (b.x() * c.squaredNorm() - c.x() * b.squaredNorm()) / d);
  *centre = p0 + u;
  *r2 = u.squaredNorm();
  return std::isfinite(*r2);
}

int sign(double x) { return (x > 0) - (x < 0); }

/// The third vertex of the other boundary face on edge (p, q) than the one
/// with apex v, when that face lies in `region`; -1 otherwise. t: a tet on
/// the edge (so nothing walks the mesh's shared marks). ring, others: scratch.
index_t opposite_vertex(const TetMesh& mesh, index_t p, index_t q, index_t v, index_t region, index_t t,
                        std::vector<index_t>& ring, std::vector<index_t>& others) {
  bool on_boundary = false;
  if (!mesh.edge_ring_with_vertices(p, q, ring, others, &on_boundary, t) || !on_boundary) return kInvalidIndex;
  for (const index_t r : {ring.front(), ring.back()}) {
    const Tet& T = mesh.tet(r);
    for (int f = 0; f < 4; ++f) {
      if (T[f] == p || T[f] == q || !mesh.is_boundary_face(r, f) || mesh.face_region(r, f) != region) continue;
      for (int i = 0; i < 3; ++i) {
        const index_t u = T[kTetFace[f][i]];
        if (u != p && u != q && u != v) return u;
      }
    }
  }
  return kInvalidIndex;
}


/// What smoothing a surface vertex needs from the topology, which smoothing
/// does not change: gathered once per call instead of once per sweep (the
/// ball and edge-ring walks are a large share of a sweep's time).
struct SurfaceStencils {
  std::vector<index_t> vertex;
  std::vector<VertexConstraint> constraint;
  // CSR per vertex: its ball; its boundary triangles (v, p, q) as
  // (p, q, tet); their vertices p, q without repeats (the link); per
  // triangle, p's and q's places in the link and the vertex across (p, q)
  // in the same region (-1: none).
  std::vector<std::size_t> ball_start, ring_start, link_start;
  std::vector<index_t> ball, link, opposite;
  std::vector<std::array<index_t, 3>> ring;
  std::vector<std::array<int, 2>> ring_local;
};

SurfaceStencils surface_stencils(const TetMesh& mesh, const BoundaryGeometry& geometry,
                                 const BoundarySmoothOptions& options) {
  const bool use_mask = !options.vertex_mask.empty();
  std::vector<index_t> candidates;
  for (index_t v = 0; v < mesh.vertex_slots(); ++v) {
    if (!mesh.vertex_alive(v) || mesh.vertex_class(v) != VertexClass::Surface) continue;
    if (use_mask && (static_cast<std::size_t>(v) >= options.vertex_mask.size() || !options.vertex_mask[v])) continue;
    candidates.push_back(v);
  }
  // In parallel over fixed chunks of the candidates, each into its own
  // part, joined in order: the same stencils whatever the number of threads.
  constexpr std::size_t kChunk = 256;
  const long chunks = static_cast<long>((candidates.size() + kChunk - 1) / kChunk);
  std::vector<SurfaceStencils> parts(static_cast<std::size_t>(chunks));
  std::vector<TetMesh::WalkMarks> marks(static_cast<std::size_t>(parallel_threads()));
  parallel_for_chunks(
      static_cast<long>(candidates.size()),
      [&](long begin, long end, int worker) {
        std::vector<index_t> ball, link, edge_tets, edge_others;
        std::vector<std::array<index_t, 3>> ring;
        TetMesh::WalkMarks& my_marks = marks[static_cast<std::size_t>(worker)];
        SurfaceStencils& out = parts[static_cast<std::size_t>(begin) / kChunk];
        out.ball_start.push_back(0);
        out.ring_start.push_back(0);
        out.link_start.push_back(0);
        for (std::size_t k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k) {
          const index_t v = candidates[k];
          mesh.vertex_ball(v, ball, my_marks);
          const VertexConstraint c = vertex_constraint(mesh, geometry, v, ball);
          if (c.kind != VertexConstraint::Surface && c.kind != VertexConstraint::Discrete) continue;
          // The 1-ring of boundary triangles: boundary faces of the ball.
          ring.clear();
          link.clear();
          for (index_t t : ball) {
            const Tet& T = mesh.tet(t);
            for (int f = 0; f < 4; ++f) {
              if (T[f] == v || !mesh.is_boundary_face(t, f)) continue;
              std::array<index_t, 3> face{T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]};
              while (face[0] != v) std::rotate(face.begin(), face.begin() + 1, face.end());
              ring.push_back({face[1], face[2], t});
              for (int i = 1; i < 3; ++i)
                if (std::find(link.begin(), link.end(), face[i]) == link.end()) link.push_back(face[i]);
            }
          }
          if (ring.size() < 3) continue;
          out.vertex.push_back(v);
          out.constraint.push_back(c);
          out.ball.insert(out.ball.end(), ball.begin(), ball.end());
          out.ball_start.push_back(out.ball.size());
          out.link.insert(out.link.end(), link.begin(), link.end());
          out.link_start.push_back(out.link.size());
          for (const auto& r : ring) {
            out.ring.push_back(r);
            std::array<int, 2> local{};
            for (int i = 0; i < 2; ++i)
              local[i] = static_cast<int>(std::find(link.begin(), link.end(), r[i]) - link.begin());
            out.ring_local.push_back(local);
            out.opposite.push_back(opposite_vertex(mesh, r[0], r[1], v, c.region_a, r[2], edge_tets, edge_others));
          }
          out.ring_start.push_back(out.ring.size());
        }
      },
      static_cast<long>(2 * kChunk), static_cast<long>(kChunk));
  SurfaceStencils out;
  out.ball_start.push_back(0);
  out.ring_start.push_back(0);
  out.link_start.push_back(0);
  for (const SurfaceStencils& part : parts) {
    const std::size_t ball0 = out.ball.size(), ring0 = out.ring.size(), link0 = out.link.size();
    out.vertex.insert(out.vertex.end(), part.vertex.begin(), part.vertex.end());
    out.constraint.insert(out.constraint.end(), part.constraint.begin(), part.constraint.end());
    out.ball.insert(out.ball.end(), part.ball.begin(), part.ball.end());
    out.link.insert(out.link.end(), part.link.begin(), part.link.end());
    out.opposite.insert(out.opposite.end(), part.opposite.begin(), part.opposite.end());
    out.ring.insert(out.ring.end(), part.ring.begin(), part.ring.end());
    out.ring_local.insert(out.ring_local.end(), part.ring_local.begin(), part.ring_local.end());
    for (std::size_t i = 1; i < part.ball_start.size(); ++i) out.ball_start.push_back(ball0 + part.ball_start[i]);
    for (std::size_t i = 1; i < part.ring_start.size(); ++i) out.ring_start.push_back(ring0 + part.ring_start[i]);
    for (std::size_t i = 1; i < part.link_start.size(); ++i) out.link_start.push_back(link0 + part.link_start[i]);
  }
  return out;
}

/// The order of a sweep: the stencil vertices grouped by colour, no two of
/// one colour reading each other's position (a vertex reads the positions
/// of its ball's vertices and of its opposite vertices), so that a colour
/// moves in parallel. Greedy in stencil order, so the same whatever the
/// number of threads. colour_start[c] .. colour_start[c + 1]: colour c.
std::vector<std::size_t> colour_order(const TetMesh& mesh, const SurfaceStencils& st,
                                      std::vector<std::size_t>& colour_start) {
  const std::size_t n = st.vertex.size();
  std::vector<index_t> entry(static_cast<std::size_t>(mesh.vertex_slots()), kInvalidIndex);
  for (std::size_t i = 0; i < n; ++i) entry[st.vertex[i]] = static_cast<index_t>(i);
  // Who reads i through an opposite vertex (not symmetric, unlike the balls).
  std::vector<std::size_t> read_start(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = st.ring_start[i]; k < st.ring_start[i + 1]; ++k)
      if (st.opposite[k] >= 0 && entry[st.opposite[k]] >= 0) ++read_start[entry[st.opposite[k]] + 1];
  for (std::size_t i = 0; i < n; ++i) read_start[i + 1] += read_start[i];
  std::vector<index_t> readers(read_start[n]);
  {
    std::vector<std::size_t> fill(read_start.begin(), read_start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = st.ring_start[i]; k < st.ring_start[i + 1]; ++k)
        if (st.opposite[k] >= 0 && entry[st.opposite[k]] >= 0)
          readers[fill[entry[st.opposite[k]]]++] = static_cast<index_t>(i);
  }
  std::vector<int> colour(n, -1);
  std::vector<char> used;
  int colours = 0;
  for (std::size_t i = 0; i < n; ++i) {
    used.assign(static_cast<std::size_t>(colours) + 1, 0);
    const auto mark = [&](index_t w) {
      if (w >= 0 && entry[w] >= 0 && colour[entry[w]] >= 0) used[colour[entry[w]]] = 1;
    };
    for (std::size_t k = st.ball_start[i]; k < st.ball_start[i + 1]; ++k)
      for (const index_t w : mesh.tet(st.ball[k])) mark(w);
    for (std::size_t k = st.ring_start[i]; k < st.ring_start[i + 1]; ++k) mark(st.opposite[k]);
    for (std::size_t k = read_start[i]; k < read_start[i + 1]; ++k) mark(st.vertex[readers[k]]);
    int c = 0;
    while (used[c]) ++c;
    colour[i] = c;
    colours = std::max(colours, c + 1);
  }
  colour_start.assign(static_cast<std::size_t>(colours) + 1, 0);
  for (const int c : colour) ++colour_start[c + 1];
  for (int c = 0; c < colours; ++c) colour_start[c + 1] += colour_start[c];
  std::vector<std::size_t> order(n), slot(colour_start.begin(), colour_start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order[slot[colour[i]]++] = i;
  return order;
}

/// One thread's scratch for smoothing a surface vertex.
struct SurfaceScratch {
  std::vector<index_t> ball, link;
  std::vector<std::array<index_t, 3>> ring;
  std::vector<std::array<int, 2>> ring_local;
  std::vector<Vec2> link2;      // the link mapped to the parameter plane
  std::vector<Vec2> opposite2;  // the vertex across each ring triangle's outer edge, mapped
  std::vector<std::uint8_t> has_opposite;
  std::vector<int> old_sign;
  std::vector<double> new_stretch;  // the ball's stretches after a move
  std::vector<index_t> neighbours;  // the ball's vertices but v (edge_density)
  Chart chart;
  SurfacePrimitive tangent_plane;
};

}  // namespace

namespace {

/// What a sweep over the boundary vertices did.
struct SweepCounts {
  double max_step = 0;
  std::size_t moved = 0, refused = 0, halvings = 0;
};

}  // namespace

OdtSmoothReport odt_smooth_surface(TetMesh& mesh, const BoundaryGeometry& geometry,
                                   const BoundarySmoothOptions& options) {
  OdtSmoothReport report;
  const SurfaceStencils st = surface_stencils(mesh, geometry, options);
  std::vector<std::size_t> colour_start;
  const std::vector<std::size_t> order = colour_order(mesh, st, colour_start);
  std::vector<SurfaceScratch> scratch(static_cast<std::size_t>(parallel_threads()));
  // The quality guard reads each ball's minimum stretch: the stretch of
  // every tet of the balls is found once, in parallel, and kept as the
  // moves change it (vertices of one colour share no tet), instead of once
  // per vertex and sweep (as in odt_smooth_volume).
  std::vector<double> stretch_of_tet;
  std::atomic<std::size_t> cache_checked{0}, cache_disagreements{0};
  if (options.quality_guard) {
    const long slots = mesh.tet_slots();
    std::vector<std::uint8_t> in_ball(static_cast<std::size_t>(slots), 0);
    for (const index_t t : st.ball) in_ball[static_cast<std::size_t>(t)] = 1;
    stretch_of_tet.assign(static_cast<std::size_t>(slots), 0.0);
    parallel_for(slots, [&](long t) {
      if (in_ball[static_cast<std::size_t>(t)]) {
        const Tet& T = mesh.tet(static_cast<index_t>(t));
        stretch_of_tet[static_cast<std::size_t>(t)] =
            tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3]));
      }
    });
  }

  // One vertex: 1 moved (*step: its move over its mean edge length), 0
  // refused, -1 left (already there, or no chart).
  const auto smooth_vertex = [&](std::size_t i, SurfaceScratch& sc, double* step_out, std::size_t* halvings) -> int {
      std::vector<index_t>& ball = sc.ball;
      std::vector<index_t>& link = sc.link;
      std::vector<std::array<index_t, 3>>& ring = sc.ring;
      std::vector<std::array<int, 2>>& ring_local = sc.ring_local;
      std::vector<Vec2>& link2 = sc.link2;
      std::vector<Vec2>& opposite2 = sc.opposite2;
      std::vector<std::uint8_t>& has_opposite = sc.has_opposite;
      std::vector<int>& old_sign = sc.old_sign;
      Chart& chart = sc.chart;
      SurfacePrimitive& tangent_plane = sc.tangent_plane;
      const index_t v = st.vertex[i];
      const VertexConstraint& c = st.constraint[i];
      const Vec3 x = mesh.point(v);
      if (c.kind == VertexConstraint::Surface && !chart.init(*c.surface, x)) return -1;
      ball.assign(st.ball.begin() + static_cast<std::ptrdiff_t>(st.ball_start[i]),
                  st.ball.begin() + static_cast<std::ptrdiff_t>(st.ball_start[i + 1]));
      const auto r0 = static_cast<std::ptrdiff_t>(st.ring_start[i]),
                 r1 = static_cast<std::ptrdiff_t>(st.ring_start[i + 1]);
      ring.assign(st.ring.begin() + r0, st.ring.begin() + r1);
      ring_local.assign(st.ring_local.begin() + r0, st.ring_local.begin() + r1);
      link.assign(st.link.begin() + static_cast<std::ptrdiff_t>(st.link_start[i]),
                  st.link.begin() + static_cast<std::ptrdiff_t>(st.link_start[i + 1]));
      // A region without a fit (kept triangles): the plane through x normal
      // to its ring, the moves projected back onto the kept triangles.
      if (c.kind == VertexConstraint::Discrete) {
        Vec3 normal = Vec3::Zero();
        for (const auto& r : ring) normal += (mesh.point(r[0]) - x).cross(mesh.point(r[1]) - x);
        if (!(normal.norm() > 0)) return -1;
        tangent_plane.type = SurfaceType::Plane;
        tangent_plane.point = x;
        tangent_plane.axis = normal.normalized();
        if (!chart.init(tangent_plane, x)) return -1;
      }
      // Step 1 (Fig. 2.44): map v and its ring to the parameter plane.
      const Vec2 x2 = chart.map(x);
      link2.resize(link.size());
      double len = 0;
      for (std::size_t l = 0; l < link.size(); ++l) {
        link2[l] = chart.map(mesh.point(link[l]));
        len += (mesh.point(link[l]) - x).norm();
      }
      len /= static_cast<double>(link.size());
      old_sign.resize(ring.size());
      opposite2.resize(ring.size());
      has_opposite.assign(ring.size(), 0);
      for (std::size_t k = 0; k < ring.size(); ++k) {
        // The vertex across the outer edge (p, q), when in the same region.
        const index_t o = st.opposite[static_cast<std::size_t>(r0) + k];
        if (o >= 0) {
          opposite2[k] = chart.map(mesh.point(o));
          has_opposite[k] = 1;
        }
      }

      // Step 2: Eq. 2.34, the unweighted mean of the centres c_tau (or the
      // springs' rest position, edge_density).
      Vec2 sum = Vec2::Zero();
      double ring_area = 0;
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const Vec2 &p = link2[ring_local[k][0]], &q = link2[ring_local[k][1]];
        old_sign[k] = sign(cross2(p - x2, q - x2));
        ring_area += cross2(p - x2, q - x2);
        if (options.edge_density) continue;
        Vec2 centre = (x2 + p + q) / 3;
        const bool region_boundary = mesh.vertex_class(ring[k][0]) != VertexClass::Surface ||
                                     mesh.vertex_class(ring[k][1]) != VertexClass::Surface;
        Vec2 cc;
        double r2 = 0;
        if (!region_boundary && circumcircle(x2, p, q, &cc, &r2)) {
          // Delaunay: no other ring vertex, nor the one across (p, q), inside.
          bool delaunay = true;
          for (std::size_t l = 0; l < link.size() && delaunay; ++l)
            if (static_cast<int>(l) != ring_local[k][0] && static_cast<int>(l) != ring_local[k][1])
              delaunay = (link2[l] - cc).squaredNorm() >= r2 * (1 - 1e-12);
          if (delaunay && has_opposite[k]) delaunay = (opposite2[k] - cc).squaredNorm() >= r2 * (1 - 1e-12);
          if (delaunay) centre = cc;
        }
        sum += centre;
      }
      // The ring's orientation in the chart; a triangle already folded there
      // (a sliver the chart's distortion turned over) is not held to it.
      const int orientation = sign(ring_area);
      for (int& s : old_sign) s = s == orientation ? s : 0;
      Vec2 step = sum / static_cast<double>(ring.size()) - x2;
      if (options.edge_density) {
        Vec3 rest;
        if (!spring_rest(mesh, ball, v, options.edge_density, sc.neighbours, &rest)) return -1;
        step = chart.map(x + rest) - x2;  // the step's part along the surface
      }
      const double relative = step.norm() / len;
      if (!std::isfinite(relative) || relative <= options.tolerance * 1e-3) return -1;  // already there

      // Step 3: map back, project onto the surface; alpha halved while the
      // move inverts a tet, folds a ring triangle or lowers the ball's quality.
      double old_min = 0;
      if (options.quality_guard) {
        old_min = std::numeric_limits<double>::infinity();
        for (const index_t t : ball) old_min = std::min(old_min, stretch_of_tet[static_cast<std::size_t>(t)]);
        if (options.check_stretch_cache) {
          ++cache_checked;
          if (old_min != ball_min_stretch(mesh, ball, v, x)) ++cache_disagreements;
        }
        if (options.guard_drop > 0)
          old_min = std::min(old_min, std::max(options.guard_keep, (1 - options.guard_drop) * old_min));
      }
      const bool accepted =
          move_with_step_halving(
              mesh, ball, v, options.max_halvings, options.quality_guard, options.quality_floor, old_min,
              [&](double alpha, Vec3* p) {
                const Vec2 q2 = x2 + alpha * step;
                if (!project_to_constraint(c, chart.unmap(q2), p)) return false;
                for (std::size_t k = 0; k < ring.size(); ++k)
                  if (old_sign[k] != 0 &&
                      sign(cross2(link2[ring_local[k][0]] - q2, link2[ring_local[k][1]] - q2)) != old_sign[k])
                    return false;  // a ring triangle folds over
                return true;
              },
              [&](const Vec3& p) {
                return !options.acceptable_error ||
                       chords_within_error(mesh, geometry, *options.acceptable_error, v, p, ball);
              },
              options.quality_guard ? &sc.new_stretch : nullptr, halvings) > 0;
      if (!accepted) return 0;
      if (options.quality_guard)
        for (std::size_t k = 0; k < ball.size(); ++k) stretch_of_tet[static_cast<std::size_t>(ball[k])] = sc.new_stretch[k];
      *step_out = (mesh.point(v) - x).norm() / len;
      return 1;
  };

  for (int sweep = 0; sweep < options.iterations; ++sweep) {
    ++report.sweeps;
    SweepCounts counts;
    for (std::size_t c = 0; c + 1 < colour_start.size(); ++c) {
      const long first = static_cast<long>(colour_start[c]), last = static_cast<long>(colour_start[c + 1]);
      const auto chunk = [&](long begin, long end, int worker) {
        SweepCounts k;
        for (long j = first + begin; j < first + end; ++j) {
          double step = 0;
          const int r = smooth_vertex(order[static_cast<std::size_t>(j)], scratch[static_cast<std::size_t>(worker)],
                                      &step, &k.halvings);
          k.moved += r == 1;
          k.refused += r == 0;
          if (r == 1) k.max_step = std::max(k.max_step, step);
        }
        return k;
      };
      counts = parallel_reduce(
          last - first, counts, chunk,
          [](SweepCounts a, const SweepCounts& b) {
            a.max_step = std::max(a.max_step, b.max_step);
            a.moved += b.moved;
            a.refused += b.refused;
            a.halvings += b.halvings;
            return a;
          },
          128, 64);
    }
    const double max_step = counts.max_step;
    const std::size_t moved = counts.moved, refused = counts.refused, halvings = counts.halvings;
    report.moved += moved;
    report.refused += refused;
    report.halvings += halvings;
    report.last_max_step = max_step;
    report.cache_checked = cache_checked;
    report.cache_disagreements = cache_disagreements;
    if (max_step <= options.tolerance) {
      report.converged = true;
      break;
    }
  }
  return report;
}

}  // namespace femorph
