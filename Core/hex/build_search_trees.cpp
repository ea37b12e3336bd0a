// The search trees of thesis Fig. 4.10, generated from the decomposition
// tables instead of written by hand. The thesis walks six trees (one per
// extended RF-graph of Fig. 4.9, types A-F) plus those of the prism
// (Fig. 4.11) and the pyramid (Fig. 4.8), trying every neighbour at each
// LINK and backtracking. Here every tet of the tree is tied to labels (the
// reference cell's nodes), so a tree is a fixed sequence of LINK steps: the
// tet across a known face, whose fourth vertex must be the label's vertex or
// a new one. The "+" and "-" variants of Fig. 4.5 are kept when they are not
// rotations of each other (mesh tets are positive, so only
// orientation-preserving maps can match). A candidate is found from its
// smallest tet: one tree per class of tets under the triangulation's
// rotations (rooted there), and the maps of the root onto it taken up to the
// rotations fixing the root, so that each candidate is walked exactly once.
#include "hex/tet_to_hex_internal.h"

#include <algorithm>
#include <stdexcept>

namespace femorph {
namespace tet_to_hex {
namespace {

using Labels = std::array<std::int8_t, kMaxNodes>;  // a permutation of a cell's nodes
using Tets = std::vector<LocalTet>;

const std::array<std::array<std::int8_t, 4>, 1> kPyramidBase = { { { 0, 3, 2, 1 } } };

struct Shape {
  CellKind kind;
  int num_nodes;
  std::vector<std::array<int, 2>> edges;
  std::array<Vec3, kMaxNodes> ref;  // reference node positions (hex_decomposition_types.h)
};

Shape make_shape(CellKind kind) {
  Shape s{ kind, cell_node_count(kind), {}, {} };
  const std::array<std::int8_t, 4>* quads = nullptr;
  const int nq = cell_quads(kind, quads);
  auto add = [&s](int a, int b) {
    const std::array<int, 2> e = { std::min(a, b), std::max(a, b) };
    if (std::find(s.edges.begin(), s.edges.end(), e) == s.edges.end()) s.edges.push_back(e);
  };
  for (int q = 0; q < nq; ++q)
    for (int k = 0; k < 4; ++k) add(quads[q][k], quads[q][(k + 1) % 4]);
  switch (kind) {
    case CellKind::Hexahedron:
      s.ref = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1) };
      break;
    case CellKind::Wedge:
      s.ref = { Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 1, 1), Vec3(1, 0, 1),
                Vec3::Zero(), Vec3::Zero() };
      break;
    case CellKind::Pyramid:
      s.ref = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0.5, 0.5, 1),
                Vec3::Zero(), Vec3::Zero(), Vec3::Zero() };
      for (int k = 0; k < 4; ++k) add(k, 4);
      break;
    case CellKind::Tetra: break;
  }
  return s;
}

double volume(const Shape& s, int a, int b, int c, int d) {
  return tet_signed_volume(s.ref[a], s.ref[b], s.ref[c], s.ref[d]);
}

/// The rotations of the cell as node permutations: automorphisms of its
/// edge graph that keep the orientation of a corner.
std::vector<Labels> rotations(const Shape& s) {
  const int n = s.num_nodes;
  // Corner 0 and its three neighbours.
  std::array<int, 3> nb{};
  int count = 0;
  for (const auto& e : s.edges)
    if (e[0] == 0) nb[count++] = e[1];
  const double sign0 = volume(s, 0, nb[0], nb[1], nb[2]);
  std::vector<Labels> out;
  Labels p{};
  for (int i = 0; i < n; ++i) p[i] = static_cast<std::int8_t>(i);
  do {
    bool ok = true;
    for (const auto& e : s.edges) {
      const std::array<int, 2> m = { std::min(p[e[0]], p[e[1]]), std::max(p[e[0]], p[e[1]]) };
      if (std::find(s.edges.begin(), s.edges.end(), m) == s.edges.end()) {
        ok = false;
        break;
      }
    }
    if (ok && volume(s, p[0], p[nb[0]], p[nb[1]], p[nb[2]]) * sign0 > 0) out.push_back(p);
  } while (std::next_permutation(p.begin(), p.begin() + n));
  return out;
}

LocalTet sorted(LocalTet t) {
  std::sort(t.begin(), t.end());
  return t;
}

Tets canonical(const Tets& tets) {
  Tets c;
  for (const LocalTet& t : tets) c.push_back(sorted(t));
  std::sort(c.begin(), c.end());
  return c;
}

Tets apply(const Labels& p, const Tets& tets) {
  Tets out;
  for (LocalTet t : tets) {
    for (auto& v : t) v = p[v];
    out.push_back(t);
  }
  return out;
}

int shared_count(const LocalTet& a, const LocalTet& b) {
  int n = 0;
  for (auto x : a)
    for (auto y : b) n += x == y;
  return n;
}

bool has(const LocalTet& t, int label) { return std::find(t.begin(), t.end(), label) != t.end(); }

int tet_with(const Tets& tets, int a, int b, int c) {
  for (std::size_t i = 0; i < tets.size(); ++i)
    if (has(tets[i], a) && has(tets[i], b) && has(tets[i], c)) return static_cast<int>(i);
  throw std::logic_error("Tet To Hex search trees: a quad triangle in no tet");
}

struct Template {
  Tets tets;
  int decomposition = -1;
  bool mirrored = false;
};

/// The tree of template `t` rooted at its tet r.
SearchTree make_tree(const Shape& shape, const Template& t, int r,
                     const std::vector<Labels>& stabilizer) {
  SearchTree tree;
  tree.kind = shape.kind;
  tree.decomposition = t.decomposition;
  tree.mirrored = t.mirrored;
  tree.num_tets = static_cast<int>(t.tets.size());
  tree.num_nodes = shape.num_nodes;
  const std::array<std::int8_t, 4>* quads = nullptr;
  tree.num_quads = cell_quads(shape.kind, quads);

  // Quads: diagonal and the tets holding their two triangles.
  std::vector<std::array<int, 2>> quad_tets(tree.num_quads);
  for (int q = 0; q < tree.num_quads; ++q) {
    const auto& v = quads[q];
    tree.quads[q] = v;
    bool d0 = false;
    for (const LocalTet& x : t.tets) d0 = d0 || (has(x, v[0]) && has(x, v[2]));
    tree.quad_diagonal[q] = d0 ? 0 : 1;
    quad_tets[q] = d0 ? std::array<int, 2>{ tet_with(t.tets, v[0], v[1], v[2]), tet_with(t.tets, v[0], v[2], v[3]) }
                      : std::array<int, 2>{ tet_with(t.tets, v[1], v[2], v[3]), tet_with(t.tets, v[1], v[3], v[0]) };
  }

  // Walk order: from the root, next the tet next to a placed one that
  // completes the most quads (QUAD as early as possible), then one whose
  // fourth label is known (a stronger LINK check), then the smallest.
  const int n = tree.num_tets;
  std::vector<int> order = { r }, step_of(n, -1);
  step_of[r] = 0;
  while (static_cast<int>(order.size()) < n) {
    int best = -1, best_parent = -1, best_score = -1;
    for (int i = 0; i < n; ++i) {
      if (step_of[i] >= 0) continue;
      int parent = -1;
      for (int j : order)
        if (shared_count(t.tets[i], t.tets[j]) == 3) {
          parent = j;
          break;
        }
      if (parent < 0) continue;
      int completes = 0;
      for (const auto& qt : quad_tets)
        completes += (qt[0] == i && step_of[qt[1]] >= 0) || (qt[1] == i && step_of[qt[0]] >= 0);
      int apex = 0;
      for (auto v : t.tets[i])
        if (!has(t.tets[parent], v)) apex = v;
      bool known = false;
      for (int j : order) known = known || has(t.tets[j], apex);
      const int score = 2 * completes + (known ? 1 : 0);
      if (score > best_score) {
        best = i;
        best_parent = parent;
        best_score = score;
      }
    }
    if (best < 0) throw std::logic_error("Tet To Hex search trees: a triangulation not face-connected");
    const int s = static_cast<int>(order.size());
    step_of[best] = s;
    order.push_back(best);
    tree.parent[s] = static_cast<std::int8_t>(step_of[best_parent]);
    for (auto v : t.tets[best_parent])
      if (!has(t.tets[best], v)) tree.opposite[s] = v;
    for (auto v : t.tets[best])
      if (!has(t.tets[best_parent], v)) tree.apex[s] = v;
  }
  for (int s = 0; s < n; ++s) tree.tets[s] = t.tets[order[s]];
  for (int q = 0; q < tree.num_quads; ++q) {
    const int s = std::max(step_of[quad_tets[q][0]], step_of[quad_tets[q][1]]);
    tree.quads_after_step[s] = static_cast<std::uint8_t>(tree.quads_after_step[s] | (1u << q));
  }

  // Orientation-preserving maps of the root: the even permutations of the
  // root tet's labels, one per orbit of the rotations fixing it.
  static const int even[12][4] = { { 0, 1, 2, 3 }, { 0, 2, 3, 1 }, { 0, 3, 1, 2 }, { 1, 0, 3, 2 },
                                   { 1, 2, 0, 3 }, { 1, 3, 2, 0 }, { 2, 0, 1, 3 }, { 2, 1, 3, 0 },
                                   { 2, 3, 0, 1 }, { 3, 0, 2, 1 }, { 3, 1, 0, 2 }, { 3, 2, 1, 0 } };
  const LocalTet& root = t.tets[r];
  for (const auto& perm : even) {
    std::array<std::int8_t, 4> a;
    for (int k = 0; k < 4; ++k) a[k] = root[perm[k]];
    bool seen = false;
    for (const auto& b : tree.assignments)
      for (const Labels& p : stabilizer) {
        bool same = true;
        for (int k = 0; k < 4; ++k) same = same && p[b[k]] == a[k];
        seen = seen || same;
      }
    if (!seen) tree.assignments.push_back(a);
  }
  return tree;
}

void add_trees(const Shape& shape, const std::vector<Template>& candidates,
               std::vector<SearchTree>& trees) {
  const std::vector<Labels> rots = rotations(shape);
  std::vector<Tets> kept;
  for (const Template& t : candidates) {
    bool known = false;
    for (const Labels& p : rots)
      known = known || std::find(kept.begin(), kept.end(), canonical(apply(p, t.tets))) != kept.end();
    if (known) continue;
    const Tets key = canonical(t.tets);
    kept.push_back(key);
    // The triangulation's rotations and how they permute its tets.
    const int n = static_cast<int>(t.tets.size());
    std::vector<Labels> symmetries;
    std::vector<std::vector<int>> moves;
    for (const Labels& p : rots) {
      const Tets image = apply(p, t.tets);
      if (canonical(image) != key) continue;
      std::vector<int> move(n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          if (sorted(image[i]) == sorted(t.tets[j])) move[i] = j;
      symmetries.push_back(p);
      moves.push_back(move);
    }
    // One tree per orbit of tets, rooted at its smallest member.
    std::vector<bool> covered(n, false);
    for (int r = 0; r < n; ++r) {
      if (covered[r]) continue;
      std::vector<Labels> stabilizer;
      for (std::size_t k = 0; k < symmetries.size(); ++k) {
        covered[moves[k][r]] = true;
        if (moves[k][r] == r) stabilizer.push_back(symmetries[k]);
      }
      trees.push_back(make_tree(shape, t, r, stabilizer));
    }
  }
}

std::vector<SearchTree> build_search_trees() {
  std::vector<SearchTree> trees;
  std::vector<Template> hexes;
  for (int type = 0; type < kHexDecompositionTypes; ++type)
    for (bool mirrored : { false, true }) {
      const HexDecomposition& d = hex_decomposition(static_cast<HexDecompositionType>(type), mirrored);
      hexes.push_back({ d.tets, type, mirrored });
    }
  add_trees(make_shape(CellKind::Hexahedron), hexes, trees);

  std::vector<Template> wedges;
  for (int diagonals = 0; diagonals < 8; ++diagonals) {
    std::array<LocalTet, 3> tets;
    if (wedge_decomposition(static_cast<std::uint8_t>(diagonals), tets))
      wedges.push_back({ Tets(tets.begin(), tets.end()), -1, false });
  }
  add_trees(make_shape(CellKind::Wedge), wedges, trees);

  std::vector<Template> pyramids;
  for (int diagonal = 0; diagonal < 2; ++diagonal) {
    const auto tets = pyramid_decomposition(diagonal);
    pyramids.push_back({ Tets(tets.begin(), tets.end()), -1, false });
  }
  add_trees(make_shape(CellKind::Pyramid), pyramids, trees);
  return trees;
}

}  // namespace

int cell_quads(CellKind kind, const std::array<std::int8_t, 4>*& quads) {
  switch (kind) {
    case CellKind::Hexahedron: quads = kHexFaces.data(); return 6;
    case CellKind::Wedge: quads = kWedgeQuadFaces.data(); return 3;
    case CellKind::Pyramid: quads = kPyramidBase.data(); return 1;
    case CellKind::Tetra: break;
  }
  quads = nullptr;
  return 0;
}

const std::vector<SearchTree>& search_trees() {
  static const std::vector<SearchTree> trees = build_search_trees();
  return trees;
}

}  // namespace tet_to_hex
}  // namespace femorph
