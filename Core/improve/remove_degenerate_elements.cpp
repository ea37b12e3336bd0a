// Degenerated element removal, thesis 2.6.2 Fig. 2.38 and Steps 1-4.
#include "improve/remove_degenerate_elements.h"

#include "common/parallel.h"
#include "improve/collapse_min_stretch.h"
#include "improve/scan_live_tets.h"
#include "mesh/tet_mesh.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace femorph {

const char* to_string(DegenerateKind kind) {
  switch (kind) {
    case DegenerateKind::Sliver: return "sliver";
    case DegenerateKind::Cap: return "cap";
    case DegenerateKind::Spade: return "spade";
  }
  return "?";
}

namespace {

double face_area(const std::array<Vec3, 4>& p, int f) {
  const Vec3& a = p[kTetFace[f][0]];
  const Vec3& b = p[kTetFace[f][1]];
  const Vec3& c = p[kTetFace[f][2]];
  return 0.5 * (b - a).cross(c - a).norm();
}

/// Parameter of the projection of q onto the line (a, b).
double project_on_line(const Vec3& a, const Vec3& b, const Vec3& q) {
  const Vec3 e = b - a;
  const double l2 = e.squaredNorm();
  return l2 > 0 ? (q - a).dot(e) / l2 : 0.5;
}

/// Split collapse edges (thesis 2.6.2, Fig. 2.38 (b), (c)): the edge shared by
/// the largest and the smallest face, and the smallest face's third vertex.
/// Face f is opposite local vertex f, so the shared edge is the two vertices
/// other than f_small and f_large, and the apex is f_large itself.
void split_collapse_shape(const std::array<Vec3, 4>& p, DegenerateShape* shape) {
  double area[4];
  for (int f = 0; f < 4; ++f) area[f] = face_area(p, f);
  int fs = 0, fl = 0;
  for (int f = 1; f < 4; ++f) {
    if (area[f] < area[fs]) fs = f;
    if (area[f] > area[fl]) fl = f;
  }
  if (fs == fl) fl = (fs + 1) % 4;  // all faces equal: any other face
  int e[2], n = 0;
  for (int i = 0; i < 4; ++i)
    if (i != fs && i != fl) e[n++] = i;
  shape->v = {{e[0], e[1], fl, fs}};
  shape->s = project_on_line(p[e[0]], p[e[1]], p[fl]);
  shape->t = 0.5;
}

/// Proper crossing of 2D segments (a, b) and (c, d).
bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d) {
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& u, const Eigen::Vector2d& w) {
    return (u - o).x() * (w - o).y() - (u - o).y() * (w - o).x();
  };
  const double d1 = cross(a, b, c), d2 = cross(a, b, d), d3 = cross(c, d, a), d4 = cross(c, d, b);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

/// Parameters (s, t) of the closest points of lines (a, b) and (c, d).
void closest_line_params(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double* s, double* t) {
  const Vec3 u = b - a, v = d - c, w = a - c;
  const double uu = u.dot(u), uv = u.dot(v), vv = v.dot(v), uw = u.dot(w), vw = v.dot(w);
  const double den = uu * vv - uv * uv;
  if (den <= 1e-300 * (uu * vv + 1e-300)) {
    *s = *t = 0.5;
    return;
  }
  *s = (uv * vw - vv * uw) / den;
  *t = (uu * vw - uv * uw) / den;
}

}  // namespace

DegenerateShape classify_degenerate_tet(const std::array<Vec3, 4>& p, double spade_tolerance) {
  DegenerateShape shape;
  double lmax = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) lmax = std::max(lmax, (p[i] - p[j]).norm());
  // Spade (Fig. 2.38 (c)): three vertices near a line, i.e. a face whose
  // smallest height is tiny compared with the tet.
  double area[4];
  int fl = 0;
  bool spade = false;
  for (int f = 0; f < 4; ++f) {
    area[f] = face_area(p, f);
    if (area[f] > area[fl]) fl = f;
    double longest = 0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (p[kTetFace[f][k]] - p[kTetFace[f][(k + 1) % 3]]).norm());
    const double height = longest > 0 ? 2 * area[f] / longest : 0;
    if (height < spade_tolerance * lmax) spade = true;
  }
  if (spade) {
    split_collapse_shape(p, &shape);
    shape.kind = DegenerateKind::Spade;
    return shape;
  }
  // Sliver (Fig. 2.38 (a)): projected onto the plane of the largest face, two
  // opposite edges cross (a convex quadrangle with those diagonals).
  const Vec3& a = p[kTetFace[fl][0]];
  const Vec3 n = (p[kTetFace[fl][1]] - a).cross(p[kTetFace[fl][2]] - a).normalized();
  const Vec3 ex = (p[kTetFace[fl][1]] - a).normalized();
  const Vec3 ey = n.cross(ex);
  Eigen::Vector2d q[4];
  for (int i = 0; i < 4; ++i) q[i] = Eigen::Vector2d((p[i] - a).dot(ex), (p[i] - a).dot(ey));
  static const int pairs[3][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}};
  for (const auto& pr : pairs) {
    if (!segments_cross(q[pr[0]], q[pr[1]], q[pr[2]], q[pr[3]])) continue;
    shape.kind = DegenerateKind::Sliver;
    shape.v = {{pr[0], pr[1], pr[2], pr[3]}};
    closest_line_params(p[pr[0]], p[pr[1]], p[pr[2]], p[pr[3]], &shape.s, &shape.t);
    return shape;
  }
  // Cap (Fig. 2.38 (b)): one vertex projects inside the triangle of the others.
  split_collapse_shape(p, &shape);
  shape.kind = DegenerateKind::Cap;
  return shape;
}

namespace {

struct HeapEntry {
  double stretch;
  index_t tet;
  Tet vertices;
  bool operator>(const HeapEntry& o) const { return stretch != o.stretch ? stretch > o.stretch : tet > o.tet; }
};

class DegenerateRemover {
 public:
  DegenerateRemover(TetMesh& mesh, const DegenerateRemovalOptions& options)
      : m_(mesh), opt_(options), mask_size_(options.vertex_mask.size()) {}

  double stretch(index_t t) const {
    const Tet& T = m_.tet(t);
    return tet_stretch(m_.point(T[0]), m_.point(T[1]), m_.point(T[2]), m_.point(T[3]));
  }

  /// Below the threshold and not inverted (inverted tets are for
  /// remove_inverted_elements).
  /// *q: its stretch, or infinity for a tet with a vertex outside the mask
  /// (never a target: a local run's scans skip the rest of the mesh).
  bool is_target(index_t t, double* q) const {
    *q = std::numeric_limits<double>::infinity();
    if (!opt_.vertex_mask.empty())
      for (const index_t v : m_.tet(t))
        if (static_cast<std::size_t>(v) < mask_size_ && !opt_.vertex_mask[v]) return false;
    *q = stretch(t);
    if (!(*q < opt_.stretch_threshold)) return false;
    return m_.orientation(t) >= 0;
  }

  /// DegenerateRemovalOptions::touched.
  void mark(index_t v) const {
    if (!opt_.touched) return;
    if (static_cast<std::size_t>(v) >= opt_.touched->size()) opt_.touched->resize(static_cast<std::size_t>(v) + 1, 0);
    (*opt_.touched)[static_cast<std::size_t>(v)] = 1;
  }

  /// Edge split at p; a new boundary vertex is projected when asked.
  bool split(index_t a, index_t b, const Vec3& p, index_t* mid) {
    if (m_.split_edge(a, b, &p, mid) != OpStatus::Ok) return false;
    affected_.insert(affected_.end(), m_.touched_tets().begin(), m_.touched_tets().end());
    if (opt_.project && m_.vertex_class(*mid) != VertexClass::Inner) {
      const Vec3 q = opt_.project(*mid, p);
      if (q != p && m_.move_vertex(*mid, q) == OpStatus::Ok) {
        std::vector<index_t> ball;
        m_.vertex_ball(*mid, ball);
        affected_.insert(affected_.end(), ball.begin(), ball.end());
      }
    }
    return true;
  }

  /// Collapse of (a, b) by the rules of thesis Fig. 2.37 (2.6.1.3), the
  /// position projected onto the fitted surface when asked. Made only when
  /// every tet it leaves around the merged vertex (all the tets the split and
  /// the collapse changed) has a stretch above `worse_than`, the removed
  /// tet's: an operation that does not improve the worst tet is refused (the
  /// thesis does not say; without it flat tets can be traded back and forth).
  bool collapse(index_t a, index_t b) {
    const CollapsePlan plan = m_.plan_collapse_by_rules(a, b);
    if (plan.status != OpStatus::Ok) return false;
    Vec3 pos = plan.position;
    const VertexClass c = m_.vertex_class(plan.keep);
    if (opt_.project && c != VertexClass::Inner && c != VertexClass::Corner) pos = opt_.project(plan.keep, pos);
    if (!(collapse_min_stretch(m_, plan.keep, plan.remove, pos) > worse_than_)) return false;
    if (m_.collapse_edge(Keep{plan.keep}, Remove{plan.remove}, &pos) != OpStatus::Ok) return false;
    affected_.insert(affected_.end(), m_.touched_tets().begin(), m_.touched_tets().end());
    mark(plan.remove);  // the others are in the tets around plan.keep
    return true;
  }

  /// Takes back a split: the half-edge collapse of the new vertex onto an
  /// end of its edge restores the tets (the original points never moved).
  void undo_split(index_t mid, index_t end) { m_.half_edge_collapse(Keep{end}, Remove{mid}); }

  double clamp_fraction(double s) const {
    const double f = opt_.min_split_fraction;
    return std::min(1 - f, std::max(f, s));
  }

  /// Double split collapse [Li 2003] (Fig. 2.38 (a)): split the two crossing
  /// edges, then collapse the new short edge between the two new vertices.
  bool double_split_collapse(const Tet& ids, const DegenerateShape& sh) {
    const index_t a = ids[sh.v[0]], b = ids[sh.v[1]], c = ids[sh.v[2]], d = ids[sh.v[3]];
    const double s = clamp_fraction(sh.s), t = clamp_fraction(sh.t);
    index_t m1 = kInvalidIndex, m2 = kInvalidIndex;
    if (!split(a, b, Vec3(m_.point(a) + s * (m_.point(b) - m_.point(a))), &m1)) return false;
    if (!split(c, d, Vec3(m_.point(c) + t * (m_.point(d) - m_.point(c))), &m2)) {
      undo_split(m1, a);
      return false;
    }
    if (collapse(m1, m2)) return true;
    undo_split(m2, c);
    undo_split(m1, a);
    return false;
  }

  /// Split collapse [Li 2003] (Fig. 2.38 (b), (c)): split the edge shared by
  /// the largest and the smallest face at the apex's projection, then collapse
  /// the new short edge (new vertex, apex). When the projection is at an end
  /// of the edge, the apex is collapsed with that end directly.
  bool split_collapse(const Tet& ids, const DegenerateShape& sh) {
    const index_t x = ids[sh.v[0]], y = ids[sh.v[1]], z = ids[sh.v[2]];
    const double f = opt_.min_split_fraction;
    if (sh.s < f) return collapse(z, x);
    if (sh.s > 1 - f) return collapse(z, y);
    index_t mid = kInvalidIndex;
    if (!split(x, y, Vec3(m_.point(x) + sh.s * (m_.point(y) - m_.point(x))), &mid)) return false;
    if (collapse(mid, z)) return true;
    undo_split(mid, x);
    return false;
  }

  /// When the operation of the tet's kind is refused (by the rules of
  /// Fig. 2.37, positivity, the link condition or the quality guard), the
  /// same operations on the tet's other edges, in a fixed order: double split
  /// collapse of each pair of opposite edges, split collapse of each edge with
  /// each opposite vertex, and the collapse of each edge. Not in the thesis,
  /// which names one operation per kind.
  bool alternatives(const Tet& ids, const std::array<Vec3, 4>& p) {
    static const int pairs[3][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}};
    for (const auto& pr : pairs) {
      DegenerateShape sh;
      sh.v = {{pr[0], pr[1], pr[2], pr[3]}};
      closest_line_params(p[pr[0]], p[pr[1]], p[pr[2]], p[pr[3]], &sh.s, &sh.t);
      affected_.clear();
      if (double_split_collapse(ids, sh)) return true;
    }
    for (const auto& pr : pairs)
      for (int apex = 2; apex < 4; ++apex) {
        DegenerateShape sh;
        sh.v = {{pr[0], pr[1], pr[apex], pr[5 - apex]}};
        sh.s = project_on_line(p[pr[0]], p[pr[1]], p[pr[apex]]);
        affected_.clear();
        if (split_collapse(ids, sh)) return true;
        sh.v = {{pr[2], pr[3], pr[apex - 2], pr[3 - apex]}};
        sh.s = project_on_line(p[pr[2]], p[pr[3]], p[pr[apex - 2]]);
        affected_.clear();
        if (split_collapse(ids, sh)) return true;
      }
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        affected_.clear();
        if (collapse(ids[i], ids[j])) return true;
      }
    return false;
  }

  DegenerateRemovalStats run() {
    DegenerateRemovalStats st;
    // Step 1: tets below gamma_st on a min-heap by stretch. The stretches
    // are found in parallel (a scan of every tet, several times per Phased
    // ODT run); stretch and tet id order the heap totally, so its pops do
    // not depend on how it was filled.
    double qmin = std::numeric_limits<double>::infinity();
    std::vector<HeapEntry> targets;
    {
      struct Found {
        std::vector<HeapEntry> targets;
        double qmin = std::numeric_limits<double>::infinity();
      };
      const std::vector<Found> found = scan_live_tets(m_, Found{}, [&](index_t t, Found& f) {
        double q;
        if (is_target(t, &q)) f.targets.push_back({q, t, m_.tet(t)});
        f.qmin = std::min(f.qmin, q);
      });
      join_chunks(found, [](const Found& f) -> const std::vector<HeapEntry>& { return f.targets; }, &targets);
      for (const Found& f : found) qmin = std::min(qmin, f.qmin);
    }
    std::priority_queue<HeapEntry, std::vector<HeapEntry>, std::greater<HeapEntry>> heap(
        std::greater<HeapEntry>(), std::move(targets));
    st.min_stretch_before = qmin;
    st.initial_below = heap.size();
    const std::size_t max_ops = opt_.max_operations ? opt_.max_operations : 20 * heap.size() + 100;
    std::size_t ops = 0;
    // Step 4: repeat Steps 2-3 until the heap is empty.
    while (!heap.empty() && ops < max_ops) {
      // Step 2: pop the minimum; skip entries whose tet changed since.
      const HeapEntry e = heap.top();
      heap.pop();
      if (!m_.tet_alive(e.tet) || m_.tet(e.tet) != e.vertices) continue;
      double q;
      if (!is_target(e.tet, &q)) continue;
      std::array<Vec3, 4> p;
      for (int i = 0; i < 4; ++i) p[i] = m_.point(e.vertices[i]);
      const DegenerateShape sh = classify_degenerate_tet(p, opt_.spade_tolerance);
      // Step 3: the removal operation of its kind, then the alternatives.
      affected_.clear();
      worse_than_ = q;
      bool ok = sh.kind == DegenerateKind::Sliver ? double_split_collapse(e.vertices, sh)
                                                  : split_collapse(e.vertices, sh);
      if (!ok) ok = alternatives(e.vertices, p);
      if (!ok) {
        ++st.failed;
        continue;
      }
      ++ops;
      if (sh.kind == DegenerateKind::Sliver) ++st.removed_slivers;
      else if (sh.kind == DegenerateKind::Cap) ++st.removed_caps;
      else ++st.removed_spades;
      // Step 3: affected tets below gamma_st go (back) on the heap.
      std::sort(affected_.begin(), affected_.end());
      affected_.erase(std::unique(affected_.begin(), affected_.end()), affected_.end());
      for (index_t t : affected_) {
        if (!m_.tet_alive(t)) continue;
        for (const index_t v : m_.tet(t)) mark(v);
        double qa;
        if (is_target(t, &qa)) heap.push({qa, t, m_.tet(t)});
      }
    }
    using Scan = std::pair<double, std::size_t>;  // (minimum stretch, tets still targeted)
    const Scan scan = parallel_reduce(
        static_cast<long>(m_.tet_slots()), Scan(std::numeric_limits<double>::infinity(), 0),
        [&](long begin, long end, int) {
          Scan k(std::numeric_limits<double>::infinity(), 0);
          for (long i = begin; i < end; ++i) {
            const index_t t = static_cast<index_t>(i);
            if (!m_.tet_alive(t)) continue;
            double q;
            if (is_target(t, &q)) ++k.second;
            k.first = std::min(k.first, q);
          }
          return k;
        },
        [](Scan a, Scan b) { return Scan(std::min(a.first, b.first), a.second + b.second); });
    qmin = scan.first;
    st.remaining_below = scan.second;
    st.min_stretch_after = qmin;
    return st;
  }

 private:
  TetMesh& m_;
  const DegenerateRemovalOptions& opt_;
  std::size_t mask_size_;  // vertex slots past it were made by splits
  std::vector<index_t> affected_;
  double worse_than_ = 0;  // stretch of the tet being removed
};

}  // namespace

DegenerateRemovalStats remove_degenerate_elements(TetMesh& mesh, const DegenerateRemovalOptions& options) {
  return DegenerateRemover(mesh, options).run();
}

}  // namespace femorph
