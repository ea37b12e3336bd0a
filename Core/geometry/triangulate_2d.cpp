// Constrained Delaunay triangulation: Bowyer-Watson insertion of the points
// into a large enclosing triangle, then each segment recovered by removing
// the triangles it crosses and re-triangulating the two pseudo-polygons on
// its sides (Anglada's method), all with exact orient2d / incircle.
#include "geometry/triangulate_2d.h"

#include "geometry/predicates.h"

#include <algorithm>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace femorph {

namespace {

std::uint64_t key(index_t a, index_t b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

std::uint64_t undirected(index_t a, index_t b) { return a < b ? key(a, b) : key(b, a); }

class Cdt {
 public:
  explicit Cdt(const std::vector<Vec2>& input) : p_(input) {}

  Status build(const std::vector<Segment2>& segments) {
    const index_t n = static_cast<index_t>(p_.size());
    Vec2 lo = p_[0], hi = p_[0];
    for (const Vec2& q : p_) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    const double span = std::max((hi - lo).maxCoeff(), 1e-300);
    const Vec2 c = 0.5 * (lo + hi);
    // The enclosing triangle, far enough that no input point lies on or
    // near its circumcircles' defects; its triangles are dropped at the end.
    p_.push_back(c + Vec2(-1e4 * span, -1e4 * span));
    p_.push_back(c + Vec2(1e4 * span, -1e4 * span));
    p_.push_back(c + Vec2(0, 1e4 * span));
    vertex_tri_.assign(p_.size(), kInvalidIndex);
    add(n, n + 1, n + 2);
    // Insertion in a spatial order keeps the walks short.
    std::vector<index_t> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    const double cell = span / std::max(1.0, std::sqrt(static_cast<double>(n)));
    std::sort(order.begin(), order.end(), [&](index_t a, index_t b) {
      const long ra = static_cast<long>((p_[a].y() - lo.y()) / cell), rb = static_cast<long>((p_[b].y() - lo.y()) / cell);
      if (ra != rb) return ra < rb;
      return (ra % 2 == 0) ? p_[a].x() < p_[b].x() : p_[a].x() > p_[b].x();
    });
    for (const index_t v : order) {
      const Status s = insert(v);
      if (!s) return s;
    }
    for (const Segment2& seg : segments) {
      if (seg[0] < 0 || seg[1] < 0 || seg[0] >= n || seg[1] >= n || seg[0] == seg[1]) {
        std::ostringstream msg;
        msg << "constrained_delaunay_2d: segment (" << seg[0] << ", " << seg[1] << ") has a bad vertex index";
        return Status::failure(msg.str());
      }
      const Status s = recover(seg[0], seg[1], 0);
      if (!s) return s;
    }
    return Status::success();
  }

  void collect(index_t n, std::vector<Triangle>& out, std::vector<index_t>* component) const {
    out.clear();
    std::vector<index_t> kept_id(tris_.size(), kInvalidIndex);
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      if (!alive_[t]) continue;
      const Triangle& T = tris_[t];
      if (T[0] >= n || T[1] >= n || T[2] >= n) continue;
      kept_id[t] = static_cast<index_t>(out.size());
      out.push_back(T);
    }
    if (!component) return;
    std::vector<index_t> parent(out.size());
    std::iota(parent.begin(), parent.end(), 0);
    const auto find = [&](index_t a) {
      while (parent[a] != a) a = parent[a] = parent[parent[a]];
      return a;
    };
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      if (kept_id[t] < 0) continue;
      for (int i = 0; i < 3; ++i) {
        const index_t a = tris_[t][(i + 1) % 3], b = tris_[t][(i + 2) % 3];
        if (fixed_.count(undirected(a, b))) continue;
        const auto it = edge_.find(key(b, a));
        if (it == edge_.end() || kept_id[it->second] < 0) continue;
        parent[find(kept_id[t])] = find(kept_id[it->second]);
      }
    }
    component->assign(out.size(), kInvalidIndex);
    std::unordered_map<index_t, index_t> ids;
    for (std::size_t t = 0; t < out.size(); ++t) {
      const auto it = ids.emplace(find(static_cast<index_t>(t)), static_cast<index_t>(ids.size())).first;
      (*component)[t] = it->second;
    }
  }

 private:
  index_t add(index_t a, index_t b, index_t c) {
    const index_t t = static_cast<index_t>(tris_.size());
    tris_.push_back({{a, b, c}});
    alive_.push_back(1);
    edge_[key(a, b)] = t;
    edge_[key(b, c)] = t;
    edge_[key(c, a)] = t;
    vertex_tri_[a] = vertex_tri_[b] = vertex_tri_[c] = t;
    last_ = t;
    return t;
  }

  void kill(index_t t) {
    alive_[t] = 0;
    const Triangle& T = tris_[t];
    for (int i = 0; i < 3; ++i) {
      const auto it = edge_.find(key(T[i], T[(i + 1) % 3]));
      if (it != edge_.end() && it->second == t) edge_.erase(it);
    }
  }

  index_t across(index_t a, index_t b) const {
    const auto it = edge_.find(key(b, a));
    return it == edge_.end() ? kInvalidIndex : it->second;
  }

  int orient(index_t a, index_t b, index_t c) const { return orient2d_sign(p_[a], p_[b], p_[c]); }

  Status insert(index_t v) {
    // Visibility walk to the triangle holding v.
    index_t t = last_;
    for (std::size_t guard = 0;; ++guard) {
      if (guard > 4 * tris_.size() + 16) return Status::failure("constrained_delaunay_2d: point location failed");
      const Triangle& T = tris_[t];
      bool moved = false;
      for (int i = 0; i < 3 && !moved; ++i) {
        const index_t a = T[(i + 1) % 3], b = T[(i + 2) % 3];
        if (orient(a, b, v) < 0) {
          const index_t s = across(a, b);
          if (s < 0) return Status::failure("constrained_delaunay_2d: a point lies outside the enclosing triangle");
          t = s;
          moved = true;
        }
      }
      if (!moved) break;
    }
    for (const index_t w : tris_[t])
      if (p_[w] == p_[v]) {
        std::ostringstream msg;
        msg << "constrained_delaunay_2d: points " << std::min(v, w) << " and " << std::max(v, w)
            << " coincide (" << p_[v].x() << ", " << p_[v].y() << ")";
        return Status::failure(msg.str());
      }
    // Bowyer-Watson cavity: the triangles whose circumcircle holds v.
    std::vector<index_t> cavity{t}, stack{t};
    std::unordered_set<index_t> in{t};
    while (!stack.empty()) {
      const index_t s = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        const index_t a = tris_[s][i], b = tris_[s][(i + 1) % 3];
        const index_t r = across(a, b);
        if (r < 0 || in.count(r)) continue;
        const Triangle& R = tris_[r];
        if (incircle_sign(p_[R[0]], p_[R[1]], p_[R[2]], p_[v]) > 0) {
          in.insert(r);
          cavity.push_back(r);
          stack.push_back(r);
        }
      }
    }
    std::vector<std::array<index_t, 2>> rim;
    for (const index_t s : cavity)
      for (int i = 0; i < 3; ++i) {
        const index_t a = tris_[s][i], b = tris_[s][(i + 1) % 3];
        const index_t r = across(a, b);
        if (r < 0 || !in.count(r)) rim.push_back({{a, b}});
      }
    for (const index_t s : cavity) kill(s);
    for (const auto& e : rim) add(e[0], e[1], v);
    return Status::success();
  }

  index_t triangle_at(index_t a) {
    index_t t = vertex_tri_[a];
    if (t >= 0 && alive_[t] && (tris_[t][0] == a || tris_[t][1] == a || tris_[t][2] == a)) return t;
    for (std::size_t s = 0; s < tris_.size(); ++s)
      if (alive_[s] && (tris_[s][0] == a || tris_[s][1] == a || tris_[s][2] == a)) {
        vertex_tri_[a] = static_cast<index_t>(s);
        return static_cast<index_t>(s);
      }
    return kInvalidIndex;
  }

  Status crossing(index_t a, index_t b, index_t u, index_t w) const {
    std::ostringstream msg;
    msg << "constrained_delaunay_2d: segment (" << a << ", " << b << ") crosses segment (" << u << ", " << w
        << ")";
    return Status::failure(msg.str());
  }

  // Makes (a, b) a union of edges; a point on it splits it.
  Status recover(index_t a, index_t b, int depth) {
    if (depth > 1000000) return Status::failure("constrained_delaunay_2d: segment recovery did not end");
    if (edge_.count(key(a, b)) || edge_.count(key(b, a))) {
      fixed_.insert(undirected(a, b));
      return Status::success();
    }
    // The triangle around a that the segment leaves a through.
    index_t t = triangle_at(a);
    if (t < 0) return Status::failure("constrained_delaunay_2d: a vertex has no triangle");
    index_t u = kInvalidIndex, w = kInvalidIndex;
    for (std::size_t guard = 0; guard < tris_.size() + 3; ++guard) {
      const Triangle& T = tris_[t];
      const int i = T[0] == a ? 0 : T[1] == a ? 1 : 2;
      const index_t x = T[(i + 1) % 3], y = T[(i + 2) % 3];
      const int ox = orient(a, x, b), oy = orient(a, y, b);
      const Vec2 d = p_[b] - p_[a];
      if (ox == 0 && (p_[x] - p_[a]).dot(d) > 0) {
        const Status s = recover(a, x, depth + 1);
        return s ? recover(x, b, depth + 1) : s;
      }
      if (oy == 0 && (p_[y] - p_[a]).dot(d) > 0) {
        const Status s = recover(a, y, depth + 1);
        return s ? recover(y, b, depth + 1) : s;
      }
      if (ox > 0 && oy < 0) {
        u = x;  // right of a -> b
        w = y;  // left
        break;
      }
      t = across(y, a);  // the next triangle counter-clockwise around a
      if (t < 0) return Status::failure("constrained_delaunay_2d: the triangles around a vertex are not closed");
    }
    if (u < 0) return Status::failure("constrained_delaunay_2d: no triangle around a vertex faces the segment");
    std::vector<index_t> removed{t}, right{a, u}, left{a, w};
    index_t end = b;
    for (;;) {
      if (fixed_.count(undirected(u, w))) return crossing(a, b, u, w);
      const index_t s = across(u, w);
      if (s < 0) return Status::failure("constrained_delaunay_2d: a segment leaves the triangulation");
      removed.push_back(s);
      const Triangle& S = tris_[s];
      const index_t x = S[0] != u && S[0] != w ? S[0] : S[1] != u && S[1] != w ? S[1] : S[2];
      if (x == b) break;
      const int o = orient(a, b, x);
      if (o == 0) {  // a point on the segment: stop there, go on from it
        end = x;
        break;
      }
      if (o > 0) {
        left.push_back(x);
        w = x;
      } else {
        right.push_back(x);
        u = x;
      }
    }
    right.push_back(end);
    left.push_back(end);
    for (const index_t s : removed) kill(s);
    fill(right);
    fill(left);
    fixed_.insert(undirected(a, end));
    return end == b ? Status::success() : recover(end, b, depth + 1);
  }

  // Triangulates the pseudo-polygon with base chain.front() -> chain.back()
  // and the vertices between, Delaunay with respect to each other.
  void fill(const std::vector<index_t>& chain) {
    if (chain.size() < 3) return;
    const index_t s = chain.front(), e = chain.back();
    std::size_t c = 1;
    for (std::size_t k = 2; k + 1 < chain.size(); ++k) {
      const bool ccw = orient(s, e, chain[c]) > 0;
      const Vec2& A = p_[ccw ? s : e];
      const Vec2& B = p_[ccw ? e : s];
      if (incircle_sign(A, B, p_[chain[c]], p_[chain[k]]) > 0) c = k;
    }
    if (orient(s, e, chain[c]) > 0) add(s, e, chain[c]);
    else add(e, s, chain[c]);
    fill(std::vector<index_t>(chain.begin(), chain.begin() + static_cast<long>(c) + 1));
    fill(std::vector<index_t>(chain.begin() + static_cast<long>(c), chain.end()));
  }

  std::vector<Vec2> p_;
  std::vector<Triangle> tris_;
  std::vector<char> alive_;
  std::unordered_map<std::uint64_t, index_t> edge_;  ///< directed edge -> triangle on its left
  std::unordered_set<std::uint64_t> fixed_;          ///< recovered segments' edges
  std::vector<index_t> vertex_tri_;
  index_t last_ = 0;
};

}  // namespace

Status constrained_delaunay_2d(const std::vector<Vec2>& points, const std::vector<Segment2>& segments,
                               std::vector<Triangle>& triangles, std::vector<index_t>* component) {
  triangles.clear();
  if (component) component->clear();
  for (const Vec2& q : points)
    if (!q.allFinite()) return Status::failure("constrained_delaunay_2d: a point is not finite");
  if (points.size() < 3) return Status::failure("constrained_delaunay_2d: fewer than three points");
  Cdt cdt(points);
  const Status s = cdt.build(segments);
  if (!s) return s;
  cdt.collect(static_cast<index_t>(points.size()), triangles, component);
  if (triangles.empty()) return Status::failure("constrained_delaunay_2d: all points lie on one line");
  return Status::success();
}

}  // namespace femorph
