// Parameterisation of the vertices (thesis 2.5.4.3): each vertex is fixed,
// mapped onto an updated surface (Method 1), or expressed by its handle
// vertices (Method 2, Eq. 2.9): curve vertices by their division ratio
// between their two curve neighbours, surface vertices by 2D mean value
// coordinates of their 1-ring, inner vertices by 3D mean value coordinates
// of their 1-ring polyhedron. The unknowns of each kind form the sparse
// system of Eq. 2.10, built here once (curves and surfaces factorised).
#include "deform/deform.h"

#include "common/parallel.h"
#include "mesh/surface_mesh.h"
#include "mesh/tet_mesh.h"

#include <algorithm>
#include <chrono>

namespace femorph {

namespace {

using Param = VertexParameterization;
using Triplet = Eigen::Triplet<double>;

/// Rows of one system, gathered before it is factorised.
struct Rows {
  std::vector<index_t> unknowns;
  std::vector<std::vector<std::pair<index_t, double>>> weights;  // per unknown: (vertex, weight)
};

Status factorise(const std::vector<Param::Kind>& kind, Param::Kind unknown_kind, Rows rows, Param::System& out,
                 const char* what, bool iterative) {
  out = Param::System();
  out.unknowns = std::move(rows.unknowns);
  const std::size_t n = out.unknowns.size();
  if (n == 0) return Status::success();
  // Row of each unknown and column of each known, by vertex (-1: none).
  std::vector<index_t> row_of(kind.size(), kInvalidIndex), col_of(kind.size(), kInvalidIndex);
  for (std::size_t i = 0; i < n; ++i) row_of[out.unknowns[i]] = static_cast<index_t>(i);
  std::vector<Triplet> a, b;
  std::size_t entries = n;
  for (const auto& row : rows.weights) entries += row.size();
  a.reserve(entries);
  for (std::size_t i = 0; i < n; ++i) {
    a.emplace_back(static_cast<int>(i), static_cast<int>(i), 1.0);
    for (const auto& [v, w] : rows.weights[i]) {
      if (kind[v] == unknown_kind && row_of[v] >= 0) {
        a.emplace_back(static_cast<int>(i), static_cast<int>(row_of[v]), -w);
      } else {
        if (col_of[v] < 0) {
          col_of[v] = static_cast<index_t>(out.knowns.size());
          out.knowns.push_back(v);
        }
        b.emplace_back(static_cast<int>(i), static_cast<int>(col_of[v]), w);
      }
    }
  }
  Eigen::SparseMatrix<double> matrix(static_cast<int>(n), static_cast<int>(n));
  matrix.setFromTriplets(a.begin(), a.end());
  out.rhs.resize(static_cast<int>(n), static_cast<int>(out.knowns.size()));
  out.rhs.setFromTriplets(b.begin(), b.end());
  bool ok;
  if (!iterative) {
    out.lu = std::make_shared<Eigen::SparseLU<Eigen::SparseMatrix<double>>>();
    out.lu->compute(matrix);
    ok = out.lu->info() == Eigen::Success;
  } else {
    out.matrix = std::move(matrix);
    out.iterative = std::make_shared<
        Eigen::BiCGSTAB<Eigen::SparseMatrix<double>, Eigen::DiagonalPreconditioner<double>>>();
    out.iterative->setTolerance(1e-13);
    out.iterative->setMaxIterations(2000);
    out.iterative->compute(out.matrix);
    ok = out.iterative->info() == Eigen::Success;
  }
  if (!ok) {
    return Status::failure(std::string("the system of the ") + what +
                           " vertices (Eq. 2.10) could not be factorised: the mesh has vertices outside their "
                           "1-ring (inverted or flat elements?)");
  }
  return Status::success();
}

}  // namespace

Status parameterize_vertices(const TetMesh& mesh, const DeformPlan& plan, const std::vector<std::uint8_t>& deformable,
                             VertexParameterization& out, bool inner) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  out = VertexParameterization();
  const index_t nv = mesh.vertex_slots();
  out.kind.assign(nv, Param::Inner);
  out.region.assign(nv, kInvalidIndex);
  out.curve_regions.assign(nv, {kInvalidIndex, kInvalidIndex});
  out.mapped_regions.assign(nv, {});
  out.deformable = deformable;

  // Vertices whose whole ball is in the deformable region may move (free).
  std::vector<std::uint8_t> free(nv, 1);

  // The boundary around the region: every vertex that may move (in a
  // deformable tet, or on a moved region, which the map moves wherever it
  // is) with its whole fan; the others stay fixed.
  SurfaceMesh surface;
  Status extracted;
  if (deformable.empty()) {
    extracted = extract_boundary_surface(mesh, surface);
  } else {
    std::vector<std::uint8_t> near(nv, 0);
    for (index_t t = 0; t < mesh.tet_slots(); ++t) {
      if (!mesh.tet_alive(t)) continue;
      const Tet& T = mesh.tet(t);
      if (t < static_cast<index_t>(deformable.size()) && deformable[t]) {
        for (const index_t v : T) near[v] = 1;
      } else {
        for (const index_t v : T) free[v] = 0;
      }
      for (int f = 0; f < 4; ++f) {
        const index_t r = mesh.face_region(t, f);
        if (!mesh.is_boundary_face(t, f) || r < 0 || r >= static_cast<index_t>(plan.roles.size())) continue;
        if (plan.roles[r] == RegionRole::Control || plan.roles[r] == RegionRole::Following) {
          for (int k = 0; k < 3; ++k) near[T[kTetFace[f][k]]] = 1;
        }
      }
    }
    extracted = extract_boundary_surface_near(mesh, near, surface);
  }
  if (!extracted) return extracted;
  const index_t ns = surface.num_points();
  std::vector<index_t> tri_region(surface.num_triangles());
  for (index_t f = 0; f < surface.num_triangles(); ++f) {
    const index_t code = surface.source_face[f];
    tri_region[f] = mesh.face_region(code / 4, code % 4);
  }
  const auto role = [&](index_t r) {
    return r >= 0 && r < static_cast<index_t>(plan.roles.size()) ? plan.roles[r] : RegionRole::Fixed;
  };

  // Kinds of the boundary vertices (2.5.4.5's vertex types).
  std::vector<std::vector<index_t>> vregions(ns);
  std::vector<std::uint8_t> bounded(plan.roles.size(), 0);  // the region has a curve
  for (index_t s = 0; s < ns; ++s) {
    auto& list = vregions[s];
    for (index_t k = surface.vertex_offsets[s]; k < surface.vertex_offsets[s + 1]; ++k) {
      const index_t r = tri_region[surface.vertex_triangles[k]];
      if (std::find(list.begin(), list.end(), r) == list.end()) list.push_back(r);
    }
    if (list.size() > 1) {
      for (const index_t r : list) {
        if (r >= 0 && r < static_cast<index_t>(bounded.size())) bounded[r] = 1;
      }
    }
  }
  for (index_t s = 0; s < ns; ++s) {
    const auto& list = vregions[s];
    const index_t v = surface.source_vertex[s];
    bool fixed = false, moved = false;
    for (const index_t r : list) {
      const RegionRole ro = role(r);
      fixed = fixed || ro == RegionRole::Fixed;
      moved = moved || ro == RegionRole::Control || ro == RegionRole::Following;
    }
    if (fixed) {
      out.kind[v] = Param::Fixed;
    } else if (moved && plan.solve_moved_interior && list.size() == 1 && list[0] >= 0 &&
               bounded[list[0]]) {
      out.kind[v] = Param::Surface;
      out.region[v] = list[0];
    } else if (moved) {
      out.kind[v] = Param::Mapped;
      for (const index_t r : list) {
        const RegionRole ro = role(r);
        if (out.region[v] < 0 && (ro == RegionRole::Control || ro == RegionRole::Following)) out.region[v] = r;
      }
      out.mapped_regions[v] = list;
    } else if (!free[v] || list.size() > 2) {
      out.kind[v] = Param::Fixed;  // outside the region, or a corner of deformed regions only
    } else if (list.size() == 2) {
      out.kind[v] = Param::Curve;
      out.curve_regions[v] = {list[0], list[1]};
    } else {
      out.kind[v] = Param::Surface;
      out.region[v] = list[0];
    }
  }
  for (index_t v = 0; v < nv; ++v) {
    if (!mesh.vertex_alive(v)) {
      out.kind[v] = Param::Fixed;
    } else if (out.kind[v] == Param::Inner && (!free[v] || !inner)) {
      out.kind[v] = Param::Fixed;
    }
  }

  for (index_t v = 0; v < nv; ++v) {
    if (out.kind[v] == Param::Mapped) out.mapped.push_back(v);
    if (mesh.vertex_alive(v)) out.scale = std::max(out.scale, mesh.point(v).cwiseAbs().maxCoeff());
  }

  // Curve vertices: the division ratio between the two neighbours along
  // their curve (2.5.4.3, boundary edge vertex).
  Rows curve_rows, surface_rows, inner_rows;
  std::vector<index_t> surface_id(nv, kInvalidIndex);
  for (index_t s = 0; s < ns; ++s) surface_id[surface.source_vertex[s]] = s;
  for (index_t s = 0; s < ns; ++s) {
    const index_t v = surface.source_vertex[s];
    if (out.kind[v] != Param::Curve) continue;
    const auto cr = out.curve_regions[v];
    std::vector<index_t> along;
    for (index_t k = surface.vertex_offsets[s]; k < surface.vertex_offsets[s + 1]; ++k) {
      const index_t f = surface.vertex_triangles[k];
      const Tri& tri = surface.triangles[f];
      for (int e = 0; e < 3; ++e) {
        if (tri[e] != s) continue;
        // The edge leaving s in this triangle and the triangle across it.
        const index_t g = surface.neighbors[f][e];
        if (g < 0) continue;
        const index_t ra = tri_region[f], rb = tri_region[g];
        if ((ra == cr[0] && rb == cr[1]) || (ra == cr[1] && rb == cr[0])) along.push_back(tri[(e + 1) % 3]);
      }
    }
    if (along.size() != 2) {
      out.kind[v] = Param::Fixed;
      continue;
    }
    const Vec3& x = mesh.point(v);
    const index_t a = surface.source_vertex[along[0]], b = surface.source_vertex[along[1]];
    const double da = (mesh.point(a) - x).norm(), db = (mesh.point(b) - x).norm();
    curve_rows.unknowns.push_back(v);
    curve_rows.weights.push_back({{a, db / (da + db)}, {b, da / (da + db)}});
  }

  // Surface vertices: 2D mean value coordinates over their triangle fan.
  std::vector<Vec3> ring;
  std::vector<index_t> ring_ids;
  std::vector<std::array<int, 2>> fan;
  std::vector<double> weights;
  for (index_t s = 0; s < ns; ++s) {
    const index_t v = surface.source_vertex[s];
    if (out.kind[v] != Param::Surface) continue;
    ring.clear();
    ring_ids.clear();
    fan.clear();
    const auto local = [&](index_t sv) {
      const index_t id = surface.source_vertex[sv];
      const auto it = std::find(ring_ids.begin(), ring_ids.end(), id);
      if (it != ring_ids.end()) return static_cast<int>(it - ring_ids.begin());
      ring_ids.push_back(id);
      ring.push_back(mesh.point(id));
      return static_cast<int>(ring_ids.size() - 1);
    };
    for (index_t k = surface.vertex_offsets[s]; k < surface.vertex_offsets[s + 1]; ++k) {
      const Tri& tri = surface.triangles[surface.vertex_triangles[k]];
      const int e = tri[0] == s ? 0 : tri[1] == s ? 1 : 2;
      fan.push_back({local(tri[(e + 1) % 3]), local(tri[(e + 2) % 3])});
    }
    mean_value_coordinates_2d(mesh.point(v), ring, fan, weights);
    surface_rows.unknowns.push_back(v);
    std::vector<std::pair<index_t, double>> row;
    for (std::size_t j = 0; j < ring_ids.size(); ++j) row.emplace_back(ring_ids[j], weights[j]);
    surface_rows.weights.push_back(std::move(row));
  }
  const auto t1 = Clock::now();

  // Inner vertices: 3D mean value coordinates of their 1-ring polyhedron.
  if (inner) {
    for (index_t v = 0; v < nv; ++v) {
      if (out.kind[v] == Param::Inner) inner_rows.unknowns.push_back(v);
    }
    const auto n = static_cast<long>(inner_rows.unknowns.size());
    inner_rows.weights.resize(inner_rows.unknowns.size());
    parallel_for_chunks(
        n,
        [&](long begin, long end, int) {
          std::vector<index_t> ids;
          std::vector<double> w;
          for (long i = begin; i < end; ++i) {
            vertex_ring_mvc(mesh, inner_rows.unknowns[i], ids, w);
            auto& row = inner_rows.weights[i];
            for (std::size_t j = 0; j < ids.size(); ++j) row.emplace_back(ids[j], w[j]);
          }
        },
        kParallelMinItems / 4, 256);
  }

  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const Tet& T = mesh.tet(t);
    const auto moves = [&](index_t v) { return out.kind[v] != Param::Fixed; };
    if (moves(T[0]) || moves(T[1]) || moves(T[2]) || moves(T[3])) out.moving_tets.push_back(t);
  }

  const auto t_inner_rows = Clock::now();
  // Curves and surfaces are 1D and 2D systems: their factors stay sparse at
  // any size. The inside's factors would fill in (3D) and cost more than
  // the solves: it is solved iteratively, warm-started by superposition.
  Status s = factorise(out.kind, Param::Curve, std::move(curve_rows), out.curves, "curve", false);
  if (s) s = factorise(out.kind, Param::Surface, std::move(surface_rows), out.surfaces, "surface", false);
  const auto t2 = Clock::now();
  if (s) s = factorise(out.kind, Param::Inner, std::move(inner_rows), out.inner, "inner", true);
  const auto t3 = Clock::now();
  const auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  out.seconds_surface = seconds(t0, t1) + seconds(t_inner_rows, t2);
  out.seconds_inner = seconds(t1, t_inner_rows) + seconds(t2, t3);
  return s;
}

}  // namespace femorph
