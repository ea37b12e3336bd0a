// AdaptSession: the state kept between motion steps (thesis Fig. 3.1): the
// space and object mesh, the materials, the object's rest positions (its
// pose is always applied to them, so rounding does not accumulate), G_d and
// the target density, built once by init().
#include "adapt/adapt.h"
#include "adapt/contact.h"

#include "improve/mesh_density.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace femorph {

namespace {

/// Largest displacement of a point of the box [lo, hi] between two poses:
/// |(R - I) x + t| is convex in x, so a corner attains it.
double largest_box_move(const Vec3& lo, const Vec3& hi, const RigidPose& a, const RigidPose& b) {
  double m = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 x((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
    m = std::max(m, (b.apply(x) - a.apply(x)).norm());
  }
  return m;
}

}  // namespace

std::vector<Vec3> part_surface_points(const TetMesh& mesh, const std::vector<int>& material_by_origin, int material) {
  std::vector<std::uint8_t> on(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t) || material_by_origin[mesh.tet_origin(t)] != material) continue;
    for (int f = 0; f < 4; ++f) {
      const index_t code = mesh.adjacency(t, f);
      if (code >= 0 && material_by_origin[mesh.tet_origin(code >> 2)] == material) continue;
      for (int k = 0; k < 3; ++k) on[mesh.tet(t)[kTetFace[f][k]]] = 1;
    }
  }
  std::vector<Vec3> out;
  for (index_t v = 0; v < mesh.vertex_slots(); ++v)
    if (on[v]) out.push_back(mesh.point(v));
  return out;
}

void stretch_range(const TetMesh& mesh, double* min, double* mean) {
  double lo = std::numeric_limits<double>::infinity(), sum = 0;
  std::size_t n = 0;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const Tet& T = mesh.tet(t);
    const double s = tet_stretch(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2]), mesh.point(T[3]));
    lo = std::min(lo, s);
    sum += s;
    ++n;
  }
  if (min) *min = n ? lo : 0;
  if (mean) *mean = n ? sum / static_cast<double>(n) : 0;
}

Status AdaptSession::init(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                          const std::vector<int>& material, const RigidMotion& motion, const AdaptOptions& options) {
  *this = AdaptSession();
  if (material.size() != tets.size())
    return Status::failure("the material array has " + std::to_string(material.size()) + " values for " +
                           std::to_string(tets.size()) + " cells");
  if (options.moving_object <= 0)
    return Status::failure("the moving object must be a material id > 0 (0 is the space mesh), not " +
                           std::to_string(options.moving_object));
  std::size_t object_tets = 0, space_tets = 0;
  for (const int m : material) {
    if (m < 0) return Status::failure("a material id is negative (" + std::to_string(m) + "); ids are >= 0, 0 = space");
    object_tets += m == options.moving_object;
    space_tets += m == 0;
  }
  if (object_tets == 0)
    return Status::failure("no cell has the moving object's material id " + std::to_string(options.moving_object));
  // No space mesh: an assembly of parts (3.7.4).
  const bool assembly = space_tets == 0;
  if (!(options.distance_threshold > 0)) return Status::failure("the distance threshold must be > 0 cells");
  if (!(options.grid_cell_size >= 0) || !std::isfinite(options.grid_cell_size))
    return Status::failure("the grid cell size must be >= 0 (0: automatic)");
  Status s = mesh_.build(points, tets);
  if (!s) return Status::failure("the input mesh is not valid: " + s.message);
  material_ = material;
  motion_ = motion;
  options_ = options;
  assembly_ = assembly;
  if (assembly && object_tets == tets.size())
    return Status::failure("no cell has material id 0 and every cell is the moving object's: there is neither a space "
                           "mesh nor another part to adapt");

  // The moving object: its vertices, and the surface ones (against space or
  // the outside) that seed G_d.
  const index_t nv = mesh_.vertex_slots();
  object_index_.assign(static_cast<std::size_t>(nv), kInvalidIndex);
  std::vector<std::uint8_t> on_surface(static_cast<std::size_t>(nv), 0), on_other(static_cast<std::size_t>(nv), 0);
  for (index_t t = 0; t < mesh_.tet_slots(); ++t) {
    const int m = material_[mesh_.tet_origin(t)];
    if (m != options.moving_object) {
      if (m != 0)
        for (const index_t v : mesh_.tet(t)) on_other[v] = 1;
      continue;
    }
    for (const index_t v : mesh_.tet(t))
      if (object_index_[v] < 0) {
        object_index_[v] = static_cast<index_t>(object_vertices_.size());
        object_vertices_.push_back(v);
        object_rest_.push_back(mesh_.point(v));
      }
    for (int f = 0; f < 4; ++f) {
      const index_t code = mesh_.adjacency(t, f);
      if (code >= 0 && material_[mesh_.tet_origin(code >> 2)] == options.moving_object) continue;
      for (int k = 0; k < 3; ++k) on_surface[mesh_.tet(t)[kTetFace[f][k]]] = 1;
    }
  }
  // An object none of whose surface faces borders another tet is a mesh of
  // its own: its interface with the space is not conformal (unmerged
  // duplicate points, or parts meshed separately: the assembly mode).
  std::size_t surface_faces = 0, shared_faces = 0;
  for (index_t t = 0; t < mesh_.tet_slots(); ++t) {
    if (material_[mesh_.tet_origin(t)] != options.moving_object) continue;
    for (int f = 0; f < 4; ++f) {
      const index_t code = mesh_.adjacency(t, f);
      if (code >= 0 && material_[mesh_.tet_origin(code >> 2)] == options.moving_object) continue;
      ++surface_faces;
      shared_faces += code >= 0;
    }
  }
  if (!assembly && surface_faces > 0 && shared_faces == 0)
    return Status::failure("the moving object (material " + std::to_string(options.moving_object) +
                           ") shares no face with the space mesh: the interface is not conformal (merge coincident "
                           "points first; separately meshed parts without a space mesh are an assembly, 3.7.4)");
  std::vector<Vec3> surface;
  Vec3 olo = Vec3::Constant(std::numeric_limits<double>::infinity()), ohi = -olo;
  for (const index_t v : object_vertices_) {
    if (!assembly && mesh_.on_boundary(v))
      return Status::failure("the moving object (material " + std::to_string(options.moving_object) +
                             ") touches the domain's outer boundary: it could not move without changing it");
    if (on_surface[v]) {
      surface.push_back(mesh_.point(v));
      object_surface_.push_back(v);
    }
    olo = olo.cwiseMin(mesh_.point(v));
    ohi = ohi.cwiseMax(mesh_.point(v));
  }
  box_lo_ = Vec3::Constant(std::numeric_limits<double>::infinity());
  box_hi_ = -box_lo_;
  for (index_t v = 0; v < nv; ++v)
    if (mesh_.vertex_alive(v)) {
      box_lo_ = box_lo_.cwiseMin(mesh_.point(v));
      box_hi_ = box_hi_.cwiseMax(mesh_.point(v));
    }

  // 3.4.1: cells ~6x the largest displacement of an object vertex in a step.
  double step_move = 0;
  const int sampled = motion.table.empty() ? 1 : static_cast<int>(std::min<std::size_t>(motion.table.size(), 10000));
  for (int n = 1; n <= sampled; ++n)
    step_move = std::max(step_move, largest_box_move(olo, ohi, motion.pose(n - 1), motion.pose(n)));
  const double diagonal = (box_hi_ - box_lo_).norm();
  cell_ = options.grid_cell_size > 0 ? options.grid_cell_size : 6 * step_move;
  // Without motion, or with a tiny one, cells of the mesh's own scale.
  const std::vector<Tet> live = live_tet_list(mesh_);
  const double edge = mean_edge_length(mesh_.points(), live);
  cell_ = std::max(cell_, edge);
  // Bound G_v to about 8M cells.
  const Vec3 extent = box_hi_ - box_lo_;
  cell_ = std::max(cell_, std::cbrt(extent.x() * extent.y() * extent.z() / 8e6));
  if (!(cell_ > 0) || !std::isfinite(cell_) || !(diagonal > 0)) return Status::failure("the mesh has no extent");
  distance_grid_ = build_distance_grid(surface, cell_, options.distance_threshold);

  if (options.improve) {
    auto density = std::make_shared<DensityGrid>();
    const std::vector<double> rho = vertex_density(mesh_.points(), live);
    if (density->build(mesh_.points(), live, rho, 0.5 * edge, std::size_t(1) << 24, false)) density_ = density;
  }
  stretch_.assign(static_cast<std::size_t>(mesh_.tet_slots()), std::numeric_limits<double>::quiet_NaN());
  std::vector<index_t> all;
  for (index_t t = 0; t < mesh_.tet_slots(); ++t)
    if (mesh_.tet_alive(t)) all.push_back(t);
  refresh_stretch({}, all);
  initial_ = AdaptStepReport();
  initial_.vertices = mesh_.live_vertices();
  initial_.tets = mesh_.live_tets();
  stretch_range(mesh_, &initial_.min_stretch, &initial_.mean_stretch);
  initial_.substeps = 0;
  const double input_min = initial_.min_stretch;
  input_vertices_ = mesh_.live_vertices();
  input_min_stretch_ = input_min;
  quality_floor_ = options.quality_floor > 0 ? options.quality_floor : std::clamp(1.1 * input_min, 0.1, 0.4);
  const Status contact = init_contact();
  if (!contact) return contact;
  if (assembly) {
    // 3.7.4's input: parts that touch, never overlap.
    if (!contact_) return Status::failure("an assembly (no space mesh) needs a second part to contact");
    std::set<int> parts(material_.begin(), material_.end());
    for (const int m : parts) {
      const Status o = detect_overlap(mesh_, material_, m, part_surface_points(mesh_, material_, m),
                                      kOverlapTolerance * contact_->spacing);
      if (!o) return Status::failure("the assembly's parts overlap: " + o.message);
    }
  }
  if (contact_) initial_.contact_faces = count_object_contact_faces(mesh_, material_);
  // Objects in contact at step 0: the shared vertices stay with the other
  // object (the first step's contact zone takes them).
  if (std::any_of(object_vertices_.begin(), object_vertices_.end(), [&](index_t v) { return on_other[v] != 0; })) {
    std::vector<index_t> all_vertices;
    for (index_t v = 0; v < nv; ++v)
      if (mesh_.vertex_alive(v)) all_vertices.push_back(v);
    rebuild_object_vertices(all_vertices, RigidPose());
  }
  return Status::success();
}

void AdaptSession::refresh_stretch(const std::vector<index_t>& removed, const std::vector<index_t>& added) {
  if (stretch_.size() < static_cast<std::size_t>(mesh_.tet_slots()))
    stretch_.resize(static_cast<std::size_t>(mesh_.tet_slots()), std::numeric_limits<double>::quiet_NaN());
  for (const index_t t : removed) stretch_[t] = std::numeric_limits<double>::quiet_NaN();
  for (const index_t t : added) {
    const Tet& T = mesh_.tet(t);
    stretch_[t] = tet_stretch(mesh_.point(T[0]), mesh_.point(T[1]), mesh_.point(T[2]), mesh_.point(T[3]));
  }
}

AdaptStepReport AdaptSession::initial_report() const { return initial_; }

AdaptOutput AdaptSession::output() const {
  AdaptOutput out;
  std::vector<index_t> id(static_cast<std::size_t>(mesh_.vertex_slots()), kInvalidIndex);
  for (index_t v = 0; v < mesh_.vertex_slots(); ++v) {
    if (!mesh_.vertex_alive(v)) continue;
    id[v] = static_cast<index_t>(out.points.size());
    out.points.push_back(mesh_.point(v));
    out.point_origin.push_back(mesh_.vertex_origin(v));
    if (step_ > 0) out.point_previous.push_back(step_origin_[v]);
  }
  for (index_t t = 0; t < mesh_.tet_slots(); ++t) {
    if (!mesh_.tet_alive(t)) continue;
    Tet T = mesh_.tet(t);
    for (index_t& v : T) v = id[v];
    out.tets.push_back(T);
    out.cell_origin.push_back(mesh_.tet_origin(t));
    out.material.push_back(material_[mesh_.tet_origin(t)]);
  }
  return out;
}

std::size_t AdaptSession::memory_bytes() const {
  return sizeof(*this) + mesh_.memory_bytes() + material_.capacity() * sizeof(int) +
         (object_vertices_.capacity() + object_index_.capacity()) * sizeof(index_t) +
         object_rest_.capacity() * sizeof(Vec3) + distance_grid_.distance.capacity() * sizeof(float) +
         stretch_.capacity() * sizeof(double);
}

}  // namespace femorph
