// Tables of the decompositions of thesis Fig. 4.5 (section 4.4).
#include "hex/hex_decomposition_types.h"

#include "quality/tet_quality.h"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace femorph {

const std::array<std::array<std::int8_t, 4>, 6> kHexFaces = { {
  { 0, 4, 7, 3 }, { 1, 2, 6, 5 }, { 0, 1, 5, 4 }, { 3, 7, 6, 2 }, { 0, 3, 2, 1 }, { 4, 5, 6, 7 } } };

const std::array<std::array<std::int8_t, 4>, 3> kWedgeQuadFaces = { {
  { 0, 3, 4, 1 }, { 1, 4, 5, 2 }, { 2, 5, 3, 0 } } };

const char* to_string(HexDecompositionType type) {
  static const char* names[] = { "A", "B", "C", "D", "E", "F" };
  return names[static_cast<int>(type)];
}

namespace {

Vec3 hex_node(int i) {
  static const int c[8][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 },
                               { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } };
  return Vec3(c[i][0], c[i][1], c[i][2]);
}

Vec3 wedge_node(int i) {
  static const int c[6][3] = { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 0, 0 },
                               { 0, 0, 1 }, { 0, 1, 1 }, { 1, 0, 1 } };
  return Vec3(c[i][0], c[i][1], c[i][2]);
}

Vec3 pyramid_node(int i) {
  return i == 4 ? Vec3(0.5, 0.5, 1.0) : hex_node(i);
}

template <typename Node>
LocalTet oriented(LocalTet t, Node node) {
  if (tet_signed_volume(node(t[0]), node(t[1]), node(t[2]), node(t[3])) < 0) std::swap(t[2], t[3]);
  return t;
}

bool has_edge(const std::vector<LocalTet>& tets, int a, int b) {
  for (const LocalTet& t : tets) {
    const bool ha = std::find(t.begin(), t.end(), a) != t.end();
    const bool hb = std::find(t.begin(), t.end(), b) != t.end();
    if (ha && hb) return true;
  }
  return false;
}

/// Bit i: the diagonal of quad i, 0 through its nodes 0 and 2, 1 through 1
/// and 3. Exactly one of the two is an edge of a valid triangulation.
template <std::size_t N>
std::uint8_t face_diagonals(const std::vector<LocalTet>& tets,
                            const std::array<std::array<std::int8_t, 4>, N>& faces) {
  std::uint8_t bits = 0;
  for (std::size_t f = 0; f < N; ++f) {
    const bool d0 = has_edge(tets, faces[f][0], faces[f][2]);
    const bool d1 = has_edge(tets, faces[f][1], faces[f][3]);
    if (d0 == d1) throw std::logic_error("hex decomposition table: a quad without one diagonal");
    if (d1) bits |= static_cast<std::uint8_t>(1u << f);
  }
  return bits;
}

/// Sorted tets of sorted nodes: equal for equal triangulations.
std::vector<LocalTet> canonical(std::vector<LocalTet> tets) {
  for (LocalTet& t : tets) std::sort(t.begin(), t.end());
  std::sort(tets.begin(), tets.end());
  return tets;
}

HexDecomposition make_hex(HexDecompositionType type, bool mirrored, std::vector<LocalTet> tets) {
  // "-": the mirror image in x = 1/2 (nodes 0<->1, 2<->3, 4<->5, 6<->7).
  static const std::int8_t mirror[8] = { 1, 0, 3, 2, 5, 4, 7, 6 };
  HexDecomposition d;
  d.type = type;
  d.mirrored = mirrored;
  for (LocalTet t : tets) {
    if (mirrored)
      for (auto& v : t) v = mirror[v];
    d.tets.push_back(oriented(t, hex_node));
  }
  d.diagonals = face_diagonals(d.tets, kHexFaces);
  return d;
}

/// Fig. 4.5 "+" variants, thesis node k = VTK node k - 1. Orientation is
/// fixed afterwards.
std::vector<LocalTet> base_tets(HexDecompositionType type) {
  switch (type) {
    case HexDecompositionType::A:  // corners 1, 3, 6, 8 and centre {5,4,2,7}
      return { { 0, 1, 3, 4 }, { 2, 1, 3, 6 }, { 5, 1, 4, 6 }, { 7, 3, 4, 6 }, { 1, 3, 4, 6 } };
    case HexDecompositionType::B:  // A, flip 2-3 of the centre and corner {5,2,6,7}
      return { { 0, 1, 3, 4 }, { 2, 1, 3, 6 }, { 7, 3, 4, 6 },
               { 3, 5, 4, 1 }, { 3, 5, 1, 6 }, { 3, 5, 6, 4 } };
    case HexDecompositionType::C:  // six tets around the main diagonal 1-7
      return { { 0, 6, 1, 2 }, { 0, 6, 2, 3 }, { 0, 6, 3, 7 },
               { 0, 6, 7, 4 }, { 0, 6, 4, 5 }, { 0, 6, 5, 1 } };
    case HexDecompositionType::D:  // C, bottom quad flipped ({1,3,2}, {1,4,3})
      return { { 6, 0, 1, 3 }, { 6, 1, 2, 3 }, { 0, 6, 3, 7 },
               { 0, 6, 7, 4 }, { 0, 6, 4, 5 }, { 0, 6, 5, 1 } };
    case HexDecompositionType::E:  // C, bottom and top quads flipped
      return { { 6, 0, 1, 3 }, { 6, 1, 2, 3 }, { 0, 6, 3, 7 },
               { 0, 4, 5, 7 }, { 0, 5, 6, 7 }, { 0, 6, 5, 1 } };
    case HexDecompositionType::F:  // B, top quad flipped ({5,6,7}, {5,7,8})
      return { { 0, 1, 3, 4 }, { 2, 1, 3, 6 }, { 3, 4, 5, 7 },
               { 3, 5, 6, 7 }, { 3, 5, 4, 1 }, { 3, 5, 1, 6 } };
  }
  return {};
}

struct Tables {
  std::vector<HexDecomposition> fig45;  // 12: type * 2 + mirrored
  std::vector<HexDecomposition> all;
  std::map<std::uint8_t, std::vector<std::array<LocalTet, 3>>> wedges;

  Tables() {
    for (int t = 0; t < kHexDecompositionTypes; ++t)
      for (bool m : { false, true }) {
        const auto type = static_cast<HexDecompositionType>(t);
        fig45.push_back(make_hex(type, m, base_tets(type)));
      }
    // The 48 symmetries of the cube: axis permutations times reflections.
    std::vector<std::vector<LocalTet>> seen;
    const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 },
                              { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };
    for (const HexDecomposition& d : fig45)
      for (const auto& p : perms)
        for (int flips = 0; flips < 8; ++flips) {
          std::int8_t map[8];
          for (int i = 0; i < 8; ++i) {
            const Vec3 x = hex_node(i);
            Vec3 y;
            for (int k = 0; k < 3; ++k) y[k] = (flips >> k) & 1 ? 1.0 - x[p[k]] : x[p[k]];
            for (int j = 0; j < 8; ++j)
              if (hex_node(j) == y) map[i] = static_cast<std::int8_t>(j);
          }
          std::vector<LocalTet> tets;
          for (LocalTet t : d.tets) {
            for (auto& v : t) v = map[v];
            tets.push_back(oriented(t, hex_node));
          }
          auto key = canonical(tets);
          if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
          seen.push_back(key);
          HexDecomposition s;
          s.type = d.type;
          s.mirrored = d.mirrored;
          s.tets = std::move(tets);
          s.diagonals = face_diagonals(s.tets, kHexFaces);
          all.push_back(std::move(s));
        }
    // Wedges: the cone from each node over the faces not containing it
    // (the opposite quad split either way) gives all six triangulations.
    static const std::int8_t opposite_quad[6] = { 1, 2, 0, 1, 2, 0 };
    static const std::array<std::array<std::int8_t, 3>, 2> tris = { { { 0, 1, 2 }, { 3, 4, 5 } } };
    std::vector<std::vector<LocalTet>> wseen;
    for (int v = 0; v < 6; ++v)
      for (int diag = 0; diag < 2; ++diag) {
        const auto& tri = tris[v < 3 ? 1 : 0];
        const auto& q = kWedgeQuadFaces[opposite_quad[v]];
        std::vector<LocalTet> tets;
        tets.push_back(oriented(LocalTet{ static_cast<std::int8_t>(v), tri[0], tri[1], tri[2] }, wedge_node));
        const std::int8_t a = q[diag], b = q[diag + 1], c = q[diag + 2], d = q[(diag + 3) % 4];
        tets.push_back(oriented(LocalTet{ static_cast<std::int8_t>(v), a, b, c }, wedge_node));
        tets.push_back(oriented(LocalTet{ static_cast<std::int8_t>(v), a, c, d }, wedge_node));
        auto key = canonical(tets);
        if (std::find(wseen.begin(), wseen.end(), key) != wseen.end()) continue;
        wseen.push_back(key);
        wedges[face_diagonals(tets, kWedgeQuadFaces)].push_back({ tets[0], tets[1], tets[2] });
      }
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

}  // namespace

const HexDecomposition& hex_decomposition(HexDecompositionType type, bool mirrored) {
  return tables().fig45[static_cast<std::size_t>(type) * 2 + (mirrored ? 1 : 0)];
}

const std::vector<HexDecomposition>& all_hex_decompositions() { return tables().all; }

std::vector<const HexDecomposition*> hex_decompositions_with_diagonals(std::uint8_t diagonals) {
  std::vector<const HexDecomposition*> out;
  for (const HexDecomposition& d : tables().all)
    if (d.diagonals == diagonals) out.push_back(&d);
  return out;
}

bool wedge_decomposition(std::uint8_t diagonals, std::array<LocalTet, 3>& tets) {
  const auto& w = tables().wedges;
  const auto it = w.find(diagonals);
  if (it == w.end()) return false;
  tets = it->second.front();
  return true;
}

std::array<LocalTet, 2> pyramid_decomposition(int diagonal) {
  if (diagonal == 0)
    return { oriented(LocalTet{ 0, 1, 2, 4 }, pyramid_node), oriented(LocalTet{ 0, 2, 3, 4 }, pyramid_node) };
  return { oriented(LocalTet{ 0, 1, 3, 4 }, pyramid_node), oriented(LocalTet{ 1, 2, 3, 4 }, pyramid_node) };
}

}  // namespace femorph
