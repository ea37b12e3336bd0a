// Thesis 3.5.4 (contact region adaptation), done by re-triangulation: the
// thesis makes the two objects' contact triangles identical by pairing
// vertices, virtual collapses and insertions, and flips. Here the union of
// both patches is triangulated once in the surface's 2D chart (3.4.2), with
// the boundary lines of both patches as constraints and their crossings
// inserted on the other object's edges (3.5.4.2); the overlap's triangles
// are then shared by the two objects by construction, the other object's
// surface keeps its geometry, and the contact area is that of the overlap
// of the two patches.
#include "adapt/contact.h"

#include "geometry/predicates.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <unordered_map>

namespace femorph {

namespace {

using Edge = std::pair<index_t, index_t>;

Edge undirected(index_t a, index_t b) { return a < b ? Edge(a, b) : Edge(b, a); }

// Boundary edges of a patch (edges of one face), in the faces' direction.
std::vector<Edge> patch_boundary(const std::vector<Tri>& faces) {
  std::map<Edge, int> count;
  for (const Tri& f : faces)
    for (int i = 0; i < 3; ++i) ++count[undirected(f[i], f[(i + 1) % 3])];
  std::vector<Edge> out;
  for (const Tri& f : faces)
    for (int i = 0; i < 3; ++i)
      if (count[undirected(f[i], f[(i + 1) % 3])] == 1) out.emplace_back(f[i], f[(i + 1) % 3]);
  return out;
}

double distance_to_segment(const Vec2& q, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double l2 = d.squaredNorm();
  const double t = l2 > 0 ? std::clamp((q - a).dot(d) / l2, 0.0, 1.0) : 0.0;
  return (a + t * d - q).norm();
}

}  // namespace

Status merge_contact_surfaces(const SurfacePrimitive& surface, const std::vector<Tri>& moving_faces,
                              const std::vector<Tri>& other_faces, const std::function<Vec3(index_t)>& point,
                              int moving_material, int other_material, int space_material, index_t first_new_id,
                              double spacing, MergedContact& out, const std::function<bool(index_t)>& movable) {
  out = MergedContact();
  if (moving_faces.empty() || other_faces.empty()) return Status::failure("merge_contact_surfaces: an empty patch");
  // The chart, centred on the other patch.
  Vec3 centre = Vec3::Zero();
  for (const Tri& f : other_faces) centre += (point(f[0]) + point(f[1]) + point(f[2])) / 3;
  centre /= static_cast<double>(other_faces.size());
  const SurfaceChart chart = make_surface_chart(surface, closest_point(surface, centre));

  // Chart coordinates of every vertex of both patches; which patch owns it.
  std::unordered_map<index_t, index_t> local;  // global id -> local
  std::vector<index_t> global;
  std::vector<Vec2> q;
  std::vector<std::uint8_t> owner;  // 1 moving, 2 other, 3 new
  std::vector<Tri> other = other_faces;
  std::set<index_t> targets;        // ids both patches use
  const auto take = [&](const std::vector<Tri>& faces, std::uint8_t who) -> Status {
    for (const Tri& f : faces) {
      for (const index_t v : f) {
        const auto it = local.emplace(v, static_cast<index_t>(global.size()));
        if (it.second) {
          global.push_back(v);
          q.push_back(chart.map(point(v)));
          owner.push_back(who);
        } else if (owner[it.first->second] != who && !(who == 1 && targets.count(v))) {
          std::ostringstream msg;
          msg << "merge_contact_surfaces: vertex " << v << " is in both patches";
          return Status::failure(msg.str());
        }
      }
      if (chart.period.x() > 0)
        for (int i = 0; i < 3; ++i)
          if (std::abs(q[local[f[i]]].x() - q[local[f[(i + 1) % 3]]].x()) > 0.5 * chart.period.x())
            return Status::failure(
                "merge_contact_surfaces: the contact patch wraps around its surface (not supported yet)");
    }
    return Status::success();
  };
  // A boundary point of the other patch next to a boundary point of the
  // moving patch that lies on its boundary line (closer than 0.3 spacing)
  // would leave a tiny edge (where a moving feature line ends on the
  // other's, e.g. a cap edge on a half tube's edge): the other's point
  // slides along its line onto the moving one, when `movable` allows.
  if (movable) {
    const std::vector<Edge> bm0 = patch_boundary(moving_faces), bc0 = patch_boundary(other_faces);
    std::map<index_t, index_t> snap;
    std::vector<std::array<Vec2, 2>> line(bc0.size());
    for (std::size_t i = 0; i < bc0.size(); ++i) {
      line[i][0] = chart.map(point(bc0[i].first));
      line[i][1] = chart.unwrap(chart.map(point(bc0[i].second)), line[i][0]);
    }
    for (const Edge& em : bm0)
      for (const index_t vm : {em.first, em.second}) {
        const Vec2 x = chart.map(point(vm));
        for (std::size_t i = 0; i < bc0.size(); ++i) {
          const Edge& ec = bc0[i];
          const Vec2& a = line[i][0];
          const Vec2& b = line[i][1];
          const Vec2 y = chart.unwrap(x, a);
          if (orient2d_sign(a, b, y) != 0) continue;
          const double t = (y - a).dot(b - a) / (b - a).squaredNorm();
          if (!(t > 0 && t < 1)) continue;
          const index_t near = t < 0.5 ? ec.first : ec.second;
          const double d = (t < 0.5 ? t : 1 - t) * (b - a).norm();
          if (d >= 0.3 * spacing || snap.count(near) || !movable(near)) continue;
          snap[near] = vm;
        }
      }
    for (Tri& f : other)
      for (index_t& v : f) {
        const auto it = snap.find(v);
        if (it != snap.end()) v = it->second;
      }
    for (const auto& [c, m] : snap) {
      out.replaced[c] = m;
      targets.insert(m);
    }
  }
  // Moving vertices on other vertices become them.
  std::unordered_map<std::uint64_t, std::vector<index_t>> grid;
  const double cell = std::max(spacing, 1e-300);
  const auto cell_key = [cell](const Vec3& p, int dx, int dy, int dz) {
    const auto c = [&](double x, int d) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x / cell)) + d) & 0x1fffff; };
    return (c(p.x(), dx) << 42) | (c(p.y(), dy) << 21) | c(p.z(), dz);
  };
  for (const Tri& f : other)
    for (const index_t v : f) {
      auto& bin = grid[cell_key(point(v), 0, 0, 0)];
      if (std::find(bin.begin(), bin.end(), v) == bin.end()) bin.push_back(v);
    }
  std::vector<Tri> moving = moving_faces;
  for (Tri& f : moving)
    for (index_t& v : f) {
      const auto done = out.replaced.find(v);
      if (done != out.replaced.end()) {
        v = done->second;
        continue;
      }
      const Vec3 p = point(v);
      index_t hit = kInvalidIndex;
      for (int dx = -1; dx <= 1 && hit < 0; ++dx)
        for (int dy = -1; dy <= 1 && hit < 0; ++dy)
          for (int dz = -1; dz <= 1 && hit < 0; ++dz) {
            const auto it = grid.find(cell_key(p, dx, dy, dz));
            if (it == grid.end()) continue;
            for (const index_t w : it->second)
              if ((point(w) - p).norm() <= 1e-9 * spacing) hit = w;
          }
      if (hit >= 0) {
        out.replaced[v] = hit;
        targets.insert(hit);
        v = hit;
      }
    }
  Status s = take(other, 2);
  if (s) s = take(moving, 1);
  if (!s) return s;
  const std::vector<Edge> bm = patch_boundary(moving), bc = patch_boundary(other);
  std::vector<std::uint8_t> on_boundary(global.size(), 0);
  for (const Edge& e : bm) on_boundary[local[e.first]] = on_boundary[local[e.second]] = 1;
  for (const Edge& e : bc) on_boundary[local[e.first]] = on_boundary[local[e.second]] = 1;

  ChartTriangles in_m(chart, spacing), in_c(chart, spacing);
  for (const Tri& f : moving) in_m.add({{q[local[f[0]]], q[local[f[1]]], q[local[f[2]]]}});
  for (const Tri& f : other) in_c.add({{q[local[f[0]]], q[local[f[1]]], q[local[f[2]]]}});

  // Crossings of the two boundary lines (3.5.4.2): new points on both.
  std::map<Edge, std::vector<std::pair<double, index_t>>> on_edge;  // local ids
  for (const Edge& em : bm) {
    const index_t a = local[em.first], b = local[em.second];
    for (const Edge& ec : bc) {
      const index_t c = local[ec.first], d = local[ec.second];
      const int o1 = orient2d_sign(q[a], q[b], q[c]), o2 = orient2d_sign(q[a], q[b], q[d]);
      const int o3 = orient2d_sign(q[c], q[d], q[a]), o4 = orient2d_sign(q[c], q[d], q[b]);
      if (o1 * o2 >= 0 || o3 * o4 >= 0) continue;
      const Vec2 r = q[b] - q[a], w = q[d] - q[c];
      const double den = r.x() * w.y() - r.y() * w.x();
      const double t = ((q[c] - q[a]).x() * w.y() - (q[c] - q[a]).y() * w.x()) / den;
      const Vec2 x = q[a] + t * r;
      const index_t id = static_cast<index_t>(global.size());
      global.push_back(first_new_id + static_cast<index_t>(out.new_points.size()));
      // On the other object's edge (its surface keeps its geometry; the
      // moving object's boundary line crosses it within the chord sag).
      const double tc_edge = std::clamp((x - q[c]).dot(q[d] - q[c]) / (q[d] - q[c]).squaredNorm(), 0.0, 1.0);
      out.new_points.push_back((1 - tc_edge) * point(ec.first) + tc_edge * point(ec.second));
      q.push_back(x);
      owner.push_back(3);
      on_boundary.push_back(1);
      const double tc = (x - q[c]).dot(w) / w.squaredNorm();
      on_edge[undirected(em.first, em.second)].push_back({em.first < em.second ? t : 1 - t, id});
      on_edge[undirected(ec.first, ec.second)].push_back({ec.first < ec.second ? tc : 1 - tc, id});
    }
  }

  // The points kept: every boundary point; the moving patch's inner points
  // outside the other patch and away from its boundary; the other patch's
  // inner points away from the moving patch's boundary.
  // Near a line and not exactly on it (a point on it splits it instead).
  const auto near_line = [&](index_t i, const std::vector<Edge>& line, double reach) {
    for (const Edge& e : line) {
      const index_t a = local[e.first], b = local[e.second];
      if (distance_to_segment(q[i], q[a], q[b]) >= reach) continue;
      if (orient2d_sign(q[a], q[b], q[i]) != 0) return true;
    }
    return false;
  };
  std::vector<index_t> cdt_id(global.size(), kInvalidIndex);
  std::vector<Vec2> pts;
  std::vector<index_t> pts_local;
  for (std::size_t i = 0; i < global.size(); ++i) {
    bool keep = on_boundary[i] != 0;
    if (!keep && owner[i] == 1) keep = !in_c.contains(q[i], spacing) && !near_line(static_cast<index_t>(i), bc, spacing);
    // The other object's points near the moving boundary make slivers; on a
    // curved surface dropping one moves the surface (a longer chord), so
    // only those very close go there.
    const double reach = surface.type == SurfaceType::Plane ? spacing : 0.3 * spacing;
    if (!keep && owner[i] == 2) keep = !near_line(static_cast<index_t>(i), bm, reach);
    if (!keep) continue;
    cdt_id[i] = static_cast<index_t>(pts.size());
    pts.push_back(q[i]);
    pts_local.push_back(static_cast<index_t>(i));
  }
  // Inner points closer than the spacing to a point kept before them go
  // (points the boundary lines of earlier steps left behind would make
  // slivers), boundary points first.
  {
    std::unordered_map<std::uint64_t, std::vector<index_t>> bins;
    const auto key2 = [&](const Vec2& x, int dx, int dy) {
      const auto c = [&](double v, int d) {
        return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / spacing)) + d) & 0xffffffff;
      };
      return (c(x.x(), dx) << 32) | c(x.y(), dy);
    };
    std::vector<index_t> order(pts_local.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<index_t>(k);
    std::stable_sort(order.begin(), order.end(),
                     [&](index_t a, index_t b) { return on_boundary[pts_local[a]] > on_boundary[pts_local[b]]; });
    std::vector<std::uint8_t> drop(pts_local.size(), 0);
    for (const index_t k : order) {
      const Vec2& x = pts[k];
      if (!on_boundary[pts_local[k]]) {
        bool close = false;
        for (int dx = -1; dx <= 1 && !close; ++dx)
          for (int dy = -1; dy <= 1 && !close; ++dy) {
            const auto it = bins.find(key2(x, dx, dy));
            if (it == bins.end()) continue;
            for (const index_t j : it->second)
              if ((pts[j] - x).norm() < spacing) close = true;
          }
        if (close) {
          drop[k] = 1;
          continue;
        }
      }
      bins[key2(x, 0, 0)].push_back(k);
    }
    std::vector<Vec2> kept_pts;
    std::vector<index_t> kept_local;
    std::fill(cdt_id.begin(), cdt_id.end(), kInvalidIndex);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (drop[k]) continue;
      cdt_id[pts_local[k]] = static_cast<index_t>(kept_pts.size());
      kept_pts.push_back(pts[k]);
      kept_local.push_back(pts_local[k]);
    }
    pts = std::move(kept_pts);
    pts_local = std::move(kept_local);
  }
  // Segments: both boundary lines, split at their crossings.
  std::vector<Segment2> segments;
  const auto add_line = [&](const std::vector<Edge>& line) {
    for (const Edge& e : line) {
      std::vector<std::pair<double, index_t>> cut;
      const auto it = on_edge.find(undirected(e.first, e.second));
      if (it != on_edge.end()) cut = it->second;
      std::sort(cut.begin(), cut.end());
      if (e.first > e.second) std::reverse(cut.begin(), cut.end());
      index_t from = cdt_id[local[e.first]];
      for (const auto& c : cut) {
        segments.push_back({{from, cdt_id[c.second]}});
        from = cdt_id[c.second];
      }
      segments.push_back({{from, cdt_id[local[e.second]]}});
    }
  };
  add_line(bm);
  add_line(bc);
  std::vector<Triangle> tris;
  s = constrained_delaunay_2d(pts, segments, tris);
  if (!s) return Status::failure("merge_contact_surfaces: " + s.message);

  // Which side is each object on: the other's outward faces point along
  // sign_c times the surface normal.
  const Tri& f0 = other[0];
  const Vec3 n0 = (point(f0[1]) - point(f0[0])).cross(point(f0[2]) - point(f0[0]));
  const double sign_c = n0.dot(surface_normal(surface, (point(f0[0]) + point(f0[1]) + point(f0[2])) / 3)) >= 0 ? 1 : -1;
  const Tri& g0 = moving[0];
  const Vec3 m0 = (point(g0[1]) - point(g0[0])).cross(point(g0[2]) - point(g0[0]));
  const double sign_m = m0.dot(surface_normal(surface, (point(g0[0]) + point(g0[1]) + point(g0[2])) / 3)) >= 0 ? 1 : -1;
  const auto position = [&](index_t l) {
    return owner[l] == 3 ? out.new_points[global[l] - first_new_id] : point(global[l]);
  };
  for (const Triangle& t : tris) {
    const Vec2 g = (pts[t[0]] + pts[t[1]] + pts[t[2]]) / 3;
    const bool m = in_m.contains(g, 0), c = in_c.contains(g, 0);
    if (!m && !c) continue;
    HoleFacet f;
    for (int i = 0; i < 3; ++i) f.v[i] = global[pts_local[t[i]]];
    const Vec3 a = position(pts_local[t[0]]), b = position(pts_local[t[1]]), d = position(pts_local[t[2]]);
    const Vec3 n = (b - a).cross(d - a);
    const double along = n.dot(surface_normal(surface, (a + b + d) / 3));
    // Orient as the owning object's outward faces; the object behind.
    const double want = c ? sign_c : sign_m;
    if (along * want < 0) std::swap(f.v[1], f.v[2]);
    f.back = c ? other_material : moving_material;
    f.front = c && m ? moving_material : space_material;
    if (c && m) out.contact_area += 0.5 * n.norm();
    out.faces.push_back(f);
  }
  // Points that landed on the two patches' boundary edges.
  const auto collect = [&](const std::vector<Edge>& line) {
    for (const Edge& e : line) {
      // Parameters from the smaller id: the crossings, and the kept points
      // exactly on the edge (the constrained triangulation split it there).
      const index_t a = local[std::min(e.first, e.second)], b = local[std::max(e.first, e.second)];
      std::vector<std::pair<double, index_t>> on;
      const auto it = on_edge.find(undirected(e.first, e.second));
      if (it != on_edge.end()) on = it->second;
      const Vec2 d = q[b] - q[a];
      for (std::size_t k = 0; k < pts.size(); ++k) {
        const index_t l = pts_local[k];
        if (l == a || l == b || owner[l] == 3 || orient2d_sign(q[a], q[b], q[l]) != 0) continue;
        const double t = (q[l] - q[a]).dot(d) / d.squaredNorm();
        if (t > 0 && t < 1) on.push_back({t, l});
      }
      if (on.empty()) continue;
      std::sort(on.begin(), on.end());
      auto& list = out.split_edges[undirected(e.first, e.second)];
      list.clear();
      for (const auto& p : on) list.push_back(global[p.second]);
    }
  };
  collect(bm);
  collect(bc);
  return Status::success();
}

}  // namespace femorph
