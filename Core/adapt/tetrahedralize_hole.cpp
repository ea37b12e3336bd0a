// Thesis 3.5.5 "Tetrahedrization": in the contact case Adapt removes the tets
// near the contact region, builds the new material interfaces inside the
// hole, and refills the hole with TetGen's constrained Delaunay refinement.
// The hole's boundary must not change (the kept mesh stays conformal) and the
// interfaces must stay whole, so no Steiner point may go on a facet (-Y);
// points inside are free (-q refines to the radius-edge bound).
//
// The material of each new tet is not taken from seed points (a seed placed
// by guessing can fall into the wrong region of a thin layer): the tets are
// flood-filled across the faces that are no facet, and each region takes the
// material its facets' sides name. Then every facet is checked to be a face
// of the expected tets, which also proves that no point went on it.
#include "adapt/adapt.h"

#include "adapt/tetgen_plc.h"
#include "geometry/predicates.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <string>
#include <utility>

namespace femorph {

namespace {

using Key = std::array<index_t, 3>;

Key sorted_key(index_t a, index_t b, index_t c) {
  Key k{{a, b, c}};
  std::sort(k.begin(), k.end());
  return k;
}

std::string facet_name(std::size_t f, const HoleFacet& F) {
  return "facet " + std::to_string(f) + " (" + std::to_string(F.v[0]) + ", " + std::to_string(F.v[1]) + ", " +
         std::to_string(F.v[2]) + ")";
}

std::string edge_name(index_t a, index_t b) {
  return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

/// Exactly collinear (or coincident) corners: the normal (b - a) x (c - a)
/// is zero iff orient3d(a, b, c, a + e_k) vanishes for the three axes.
bool degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  for (int k = 0; k < 3; ++k)
    if (orient3d_sign(a, b, c, a + Vec3::Unit(k)) != 0) return false;
  return true;
}

/// True when (x, y, z) is a cyclic rotation of (v0, v1, v2).
bool same_cycle(const Key& xyz, const std::array<index_t, 3>& v) {
  for (int r = 0; r < 3; ++r)
    if (xyz[0] == v[r] && xyz[1] == v[(r + 1) % 3] && xyz[2] == v[(r + 2) % 3]) return true;
  return false;
}

/// Checks the facets: ids, sides, no degenerate or repeated facet, no
/// coincident points, the hole boundary (facets with -1 on a side) a closed
/// edge-manifold surface whose sides agree, no interface ending in the hole.
Status check_facets(const std::vector<Vec3>& points, const std::vector<HoleFacet>& facets) {
  if (facets.empty()) return Status::failure("no facet");
  const index_t n = static_cast<index_t>(points.size());
  std::map<Key, std::size_t> seen;
  for (std::size_t f = 0; f < facets.size(); ++f) {
    const HoleFacet& F = facets[f];
    for (const index_t v : F.v)
      if (v < 0 || v >= n) return Status::failure(facet_name(f, F) + " has a point id out of range");
    if (F.v[0] == F.v[1] || F.v[1] == F.v[2] || F.v[0] == F.v[2])
      return Status::failure(facet_name(f, F) + " repeats a point");
    if (F.front < -1 || F.back < -1) return Status::failure(facet_name(f, F) + " has a material below -1");
    if (F.front == F.back)
      return Status::failure(facet_name(f, F) + " has material " + std::to_string(F.front) + " on both sides");
    if (degenerate_triangle(points[F.v[0]], points[F.v[1]], points[F.v[2]]))
      return Status::failure(facet_name(f, F) + " is a degenerate triangle (collinear points)");
    const auto ins = seen.emplace(sorted_key(F.v[0], F.v[1], F.v[2]), f);
    if (!ins.second) return Status::failure(facet_name(f, F) + " repeats facet " + std::to_string(ins.first->second));
  }
  // The points the facets use: no two at one position (TetGen would merge
  // them, and the kept mesh could not be joined).
  std::vector<index_t> used;
  for (const HoleFacet& F : facets) used.insert(used.end(), F.v.begin(), F.v.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<index_t> by_position = used;
  const auto less = [&](index_t a, index_t b) {
    return std::lexicographical_compare(points[a].data(), points[a].data() + 3, points[b].data(), points[b].data() + 3);
  };
  std::sort(by_position.begin(), by_position.end(), less);
  for (std::size_t i = 1; i < by_position.size(); ++i)
    if (points[by_position[i - 1]] == points[by_position[i]])
      return Status::failure("points " + std::to_string(std::min(by_position[i - 1], by_position[i])) + " and " +
                             std::to_string(std::max(by_position[i - 1], by_position[i])) + " coincide");
  // Edges: (a < b) -> boundary facets on it, the sum of their directions
  // with the normal out of the hole (+1 for a -> b), and all facets on it.
  struct EdgeUse {
    int boundary = 0, direction = 0, all = 0;
  };
  std::map<std::pair<index_t, index_t>, EdgeUse> edges;
  bool any_boundary = false;
  for (const HoleFacet& F : facets) {
    const bool boundary = F.front == -1 || F.back == -1;
    any_boundary = any_boundary || boundary;
    for (int i = 0; i < 3; ++i) {
      index_t a = F.v[i], b = F.v[(i + 1) % 3];
      // Out of the hole: towards the -1 side.
      int dir = F.front == -1 ? 1 : -1;
      if (a > b) {
        std::swap(a, b);
        dir = -dir;
      }
      EdgeUse& e = edges[{a, b}];
      ++e.all;
      if (boundary) {
        ++e.boundary;
        e.direction += dir;
      }
    }
  }
  if (!any_boundary) return Status::failure("no facet has -1 (outside the hole) on a side: the hole is not closed");
  for (const auto& [ab, e] : edges) {
    if (e.boundary == 1)
      return Status::failure("open hole boundary: " + edge_name(ab.first, ab.second) + " lies on one boundary facet");
    if (e.boundary > 2)
      return Status::failure("non-manifold hole boundary: " + edge_name(ab.first, ab.second) + " lies on " +
                             std::to_string(e.boundary) + " boundary facets");
    if (e.boundary == 2 && e.direction != 0)
      return Status::failure("the hole boundary's facets disagree on their outside at " +
                             edge_name(ab.first, ab.second));
    if (e.all < 2)
      return Status::failure("an interface ends inside the hole at " + edge_name(ab.first, ab.second));
  }
  return Status::success();
}

}  // namespace

Status tetrahedralize_hole(std::vector<Vec3>& points, const std::vector<HoleFacet>& facets, double radius_edge_ratio,
                           std::vector<Tet>& tets, std::vector<int>& material) {
  tets.clear();
  material.clear();
  const auto fail = [](const std::string& why) { return Status::failure("tetrahedralize_hole: " + why); };
  // TetGen's refinement need not end for ratios below 1 (its manual).
  if (!std::isfinite(radius_edge_ratio) || radius_edge_ratio < 1)
    return fail("the radius-edge ratio must be at least 1");
  if (const Status s = check_facets(points, facets); !s) return fail(s.message);

  // TetGen gets only the facets' points, in ascending id order (deterministic).
  std::vector<index_t> local(points.size(), kInvalidIndex);
  std::vector<index_t> global;
  for (const HoleFacet& F : facets)
    for (const index_t v : F.v) local[v] = 0;
  for (std::size_t v = 0; v < points.size(); ++v)
    if (local[v] == 0) {
      local[v] = static_cast<index_t>(global.size());
      global.push_back(static_cast<index_t>(v));
    }
  std::vector<Vec3> plc_points(global.size());
  for (std::size_t i = 0; i < global.size(); ++i) plc_points[i] = points[global[i]];
  std::vector<Key> plc_facets(facets.size());
  std::map<Key, index_t> facet_of;  // sorted local ids -> facet
  for (std::size_t f = 0; f < facets.size(); ++f) {
    for (int k = 0; k < 3; ++k) plc_facets[f][k] = local[facets[f].v[k]];
    facet_of.emplace(sorted_key(plc_facets[f][0], plc_facets[f][1], plc_facets[f][2]), static_cast<index_t>(f));
  }

  // p: the facets are a PLC (TetGen removes the tets outside it); Y: no
  // Steiner point on a facet; q: radius-edge ratio bound, points inside
  // only. Not Q: tetgen_plc captures TetGen's words, which say why it
  // stopped on an error. No hole points: a void inside the hole (kept tets
  // surrounded by it) is meshed and dropped by the flood fill below.
  char switches[64];
  std::snprintf(switches, sizeof switches, "pYq%.17g", radius_edge_ratio);
  std::vector<Vec3> out_points;
  std::vector<Tet> out_tets;
  if (const Status s = internal::tetgen_plc(plc_points, plc_facets, {}, switches, out_points, out_tets); !s)
    return fail(s.message);
  if (out_tets.empty()) return fail("TetGen returned no tet");

  // Faces of the output: (sorted key, 4 t + f), sorted, so that equal keys
  // are adjacent.
  const std::size_t nt = out_tets.size();
  std::vector<std::pair<Key, index_t>> faces;
  faces.reserve(4 * nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (int f = 0; f < 4; ++f) {
      const Tet& T = out_tets[t];
      faces.emplace_back(sorted_key(T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]),
                         static_cast<index_t>(4 * t + f));
    }
  std::sort(faces.begin(), faces.end());
  // The material on the side of facet `f` where tet face `code` (oriented out
  // of its positive tet) lies: the tet is behind the face's normal.
  const auto side = [&](index_t f, index_t code) {
    const Tet& T = out_tets[code >> 2];
    const int lf = code & 3;
    const Key xyz{{T[kTetFace[lf][0]], T[kTetFace[lf][1]], T[kTetFace[lf][2]]}};
    return same_cycle(xyz, plc_facets[f]) ? facets[f].back : facets[f].front;
  };

  // Flood fill across the faces that are no facet (thesis 3.5.5: a region
  // between facets is one material).
  std::vector<index_t> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](index_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    if (j - i > 2) return fail("TetGen returned a face shared by more than two tets");
    if (j - i == 2 && !facet_of.count(faces[i].first)) {
      const index_t a = find(faces[i].second >> 2), b = find(faces[i + 1].second >> 2);
      parent[std::max(a, b)] = std::min(a, b);
    }
    i = j;
  }
  // Each region's material from the facet sides facing it; a face on
  // TetGen's outer boundary that is no facet faces the outside (-1).
  constexpr int kUnset = -2;
  std::vector<int> region_material(nt, kUnset);
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    const auto it = facet_of.find(faces[i].first);
    for (std::size_t k = i; k < j; ++k) {
      int m;
      if (it != facet_of.end()) m = side(it->second, faces[k].second);
      else if (j - i == 1) m = -1;
      else continue;
      int& r = region_material[find(faces[k].second >> 2)];
      if (r == kUnset) r = m;
      else if (r != m)
        return fail("a region of the refill is bounded by facet sides of materials " + std::to_string(std::min(r, m)) +
                    " and " + std::to_string(std::max(r, m)) +
                    " (an interface does not separate them, or a facet's sides are wrong)");
    }
    i = j;
  }

  // The refill: the tets of regions with a material.
  std::vector<char> keep(nt, 0);
  std::vector<int> tet_material(nt, -1);
  for (std::size_t t = 0; t < nt; ++t) {
    const int m = region_material[find(static_cast<index_t>(t))];
    if (m == kUnset) return fail("a region of the refill touches no facet");
    tet_material[t] = m;
    keep[t] = m >= 0;
  }

  // Every facet is a face of the expected kept tets: a boundary facet of one,
  // on its material side; an interface of two, one on each side. TetGen's
  // output is conforming, so then no point lies on a facet.
  std::vector<int> on_facet(facets.size(), 0);
  std::vector<std::array<int, 2>> sides(facets.size(), {{kUnset, kUnset}});
  std::size_t open_faces = 0;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    const auto it = facet_of.find(faces[i].first);
    int kept_here = 0;
    for (std::size_t k = i; k < j; ++k)
      if (keep[faces[k].second >> 2]) {
        ++kept_here;
        if (it != facet_of.end()) sides[it->second][on_facet[it->second]++ & 1] = side(it->second, faces[k].second);
      }
    // A face of one kept tet must be a hole boundary facet.
    if (kept_here == 1 && (it == facet_of.end() || (facets[it->second].front != -1 && facets[it->second].back != -1)))
      ++open_faces;
    i = j;
  }
  for (std::size_t f = 0; f < facets.size(); ++f) {
    const HoleFacet& F = facets[f];
    const bool boundary = F.front == -1 || F.back == -1;
    const int inside = F.front == -1 ? F.back : F.front;
    const bool ok = boundary ? on_facet[f] == 1 && sides[f][0] == inside
                             : on_facet[f] == 2 && std::min(sides[f][0], sides[f][1]) == std::min(F.front, F.back) &&
                                   std::max(sides[f][0], sides[f][1]) == std::max(F.front, F.back);
    if (!ok) return fail("TetGen split a facet: " + facet_name(f, F) + " is not a face of the refill as expected");
  }
  if (open_faces) return fail("the refill's boundary is not the hole's (" + std::to_string(open_faces) + " faces)");

  // Output: the facets' points keep their ids, the Steiner points the kept
  // tets use are appended in TetGen's order.
  std::vector<index_t> out_id(out_points.size(), kInvalidIndex);
  for (std::size_t i = 0; i < global.size(); ++i) out_id[i] = global[i];
  for (std::size_t t = 0; t < nt; ++t)
    if (keep[t])
      for (const index_t v : out_tets[t])
        if (out_id[v] < 0) out_id[v] = -2;  // a Steiner point in use
  for (std::size_t i = global.size(); i < out_points.size(); ++i)
    if (out_id[i] == -2) {
      out_id[i] = static_cast<index_t>(points.size());
      points.push_back(out_points[i]);
    }
  for (std::size_t t = 0; t < nt; ++t)
    if (keep[t]) {
      const Tet& T = out_tets[t];
      tets.push_back({{out_id[T[0]], out_id[T[1]], out_id[T[2]], out_id[T[3]]}});
      material.push_back(tet_material[t]);
    }
  return Status::success();
}

}  // namespace femorph
