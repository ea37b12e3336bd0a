// One motion step of thesis Fig. 3.1 (A2): without contact (3.5.1: "only (ii)
// rigid transformation and (iii) deformed region adaptation"), with contact
// also the contact zone (adapt_contact.cpp), followed by the quality
// improvement of 3.6. Beyond the thesis: a step whose embedding
// would invert elements is split into halves (screw sub-steps), each adapted
// and improved in turn; a step that cannot be done is refused and the mesh
// stays at the previous step.
#include "adapt/adapt.h"
#include "adapt/contact.h"

#include "mesh/vertex_stencil.h"
#include "quality/tet_quality.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <unordered_set>

namespace femorph {

std::size_t count_object_contact_faces(const TetMesh& mesh, const std::vector<int>& material_by_origin) {
  std::size_t n = 0;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const int m = material_by_origin[mesh.tet_origin(t)];
    if (m <= 0) continue;
    for (int f = 0; f < 4; ++f) {
      const index_t code = mesh.adjacency(t, f);
      if (code < 0 || (code >> 2) < t) continue;  // each face once: from its lower tet
      const int o = material_by_origin[mesh.tet_origin(code >> 2)];
      n += o > 0 && o != m;
    }
  }
  return n;
}

Status AdaptSession::move_to(const RigidPose& to, AdaptStepReport& report, bool* retry, bool keep_quality) {
  *retry = false;
  using Clock = std::chrono::steady_clock;
  auto lap = Clock::now();
  const auto since = [&lap]() {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - lap).count();
    lap = now;
    return s;
  };
  // 3.4.2 at the new pose; with contact (or shared vertices left by the
  // last one), the zone around it joins the region (3.5.2).
  std::vector<ContactRegion> contacts;
  std::vector<index_t> zone;
  if (contact_) {
    contacts = contacts_at(to);
    if (!contacts.empty() || !contact_->shared.empty()) zone = contact_zone(contacts);
  }
  // 3.4.3 at the current pose.
  const VertexGrid vertex_grid = build_vertex_grid(mesh_, box_lo_, box_hi_, cell_);
  std::vector<index_t> region = extract_deformed_region(mesh_, material_, vertex_grid, distance_grid_,
                                                        pose_.inverse(), options_.distance_threshold);
  if (assembly_ && !zone.empty()) {
    // Beyond the thesis: an assembly has no space, so no K_Df; the parts'
    // tets around the zone (one ring) join the region instead, so that 3.6
    // moves the zone's boundary vertices too (they are inner there).
    std::vector<std::uint8_t> in_zone(static_cast<std::size_t>(mesh_.tet_slots()), 0);
    for (const index_t t : zone) in_zone[t] = 1;
    std::vector<index_t> ball;
    std::vector<std::uint8_t> seen(static_cast<std::size_t>(mesh_.vertex_slots()), 0);
    for (const index_t t : zone)
      for (const index_t v : mesh_.tet(t)) {
        if (seen[v]) continue;
        seen[v] = 1;
        mesh_.vertex_ball(v, ball);
        for (const index_t b : ball)
          if (!in_zone[b]) {
            in_zone[b] = 1;
            region.push_back(b);
          }
      }
  }
  // Beyond the thesis: with a space mesh too, one ring of the fixed
  // objects' tets around the zone, so that 3.6 may move the zone's boundary
  // vertices inside those objects (the refill's worst tets end there); while
  // the objects touch (faces in contact), the moving object's ring too (its
  // contact side took the other's points; its interior may follow).
  std::vector<index_t> fixed_ring;
  if (!assembly_ && !zone.empty()) {
    const bool touching = std::any_of(contacts.begin(), contacts.end(),
                                      [](const ContactRegion& c) { return c.moving_area > 0; });
    fixed_ring = fixed_object_ring(zone, touching);
  }
  const std::vector<index_t> deformed = region;
  const auto with_zone = [&](const std::vector<index_t>& ring) {
    std::vector<index_t> out = deformed;
    out.insert(out.end(), ring.begin(), ring.end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    std::vector<index_t> both;
    std::set_union(out.begin(), out.end(), zone.begin(), zone.end(), std::back_inserter(both));
    // The union may pinch where the zone's object tets meet the space part:
    // close it with tets of the zone's materials.
    std::set<int> zone_materials{0, options_.moving_object};
    for (const index_t t : zone) zone_materials.insert(material_[mesh_.tet_origin(t)]);
    const auto may_take = [&](index_t t) { return zone_materials.count(material_[mesh_.tet_origin(t)]) > 0; };
    close_region(mesh_, both, may_take);
    std::sort(both.begin(), both.end());
    return both;
  };
  if (!zone.empty()) region = with_zone(fixed_ring);
  report.seconds_region += since();
  if (assembly_ && region.empty()) {
    // An assembly's part away from the others: (ii) only.
    for (std::size_t k = 0; k < object_vertices_.size(); ++k)
      mesh_.set_point(object_vertices_[k], to.apply(object_rest_[k]));
    pose_ = to;
    ++mesh_version_;
    report.moved_vertices += object_vertices_.size();
    return Status::success();
  }
  RegionMesh rm;
  Status s = make_region_mesh(mesh_, region, rm);
  if (!s && !fixed_ring.empty()) {
    // The ring made no clean submesh: the region without it.
    region = with_zone({});
    s = make_region_mesh(mesh_, region, rm);
  }
  report.seconds_submesh += since();
  if (!s) return s;
  const index_t built = static_cast<index_t>(rm.global_vertex.size());
  std::vector<std::uint8_t> moved(static_cast<std::size_t>(built), 0);
  std::vector<Vec3> moved_position(static_cast<std::size_t>(built), Vec3::Zero());
  for (index_t v = 0; v < built; ++v) {
    const index_t g = rm.global_vertex[v];
    // Vertices made after init() (splits) are never the object's.
    const index_t k = g < static_cast<index_t>(object_index_.size()) ? object_index_[g] : kInvalidIndex;
    if (k < 0) continue;
    moved[v] = 1;
    moved_position[v] = to.apply(object_rest_[k]);
  }
  // Other objects stay (the region holds their tets in a contact zone).
  if (!zone.empty())
    for (index_t t = 0; t < rm.mesh.tet_slots(); ++t) {
      if (!rm.mesh.tet_alive(t)) continue;
      const int m = material_[mesh_.tet_origin(rm.global_tet[rm.mesh.tet_origin(t)])];
      if (m == 0 || m == options_.moving_object) continue;
      for (const index_t v : rm.mesh.tet(t))
        if (!moved[v]) {
          moved[v] = 1;
          moved_position[v] = rm.mesh.point(v);
        }
    }
  std::size_t inner = 0;
  const TetMesh before = rm.mesh;
  s = embed_deformed_region(rm, moved, moved_position, &inner);
  report.seconds_embed += since();
  if (!s) return s;
  report.deformed_region_tets += region.size();
  report.inner_vertices += inner;
  if (!zone.empty()) {
    // The zone's tets in the region's ids (build-time: the order of region).
    std::vector<index_t> local;
    for (std::size_t i = 0, j = 0; i < region.size() && j < zone.size(); ++i)
      if (region[i] == zone[j]) {
        local.push_back(static_cast<index_t>(i));
        ++j;
      }
    s = remesh_contact_zone(rm, local, contacts, to);
    report.seconds_contact += since();
    if (!s) {
      *retry = true;
      return s;
    }
  }
  // (iii) must leave no inverted element for Improve to start from a
  // valid mesh; a smaller sub-step does.
  for (index_t t = 0; t < rm.mesh.tet_slots(); ++t)
    if (rm.mesh.tet_alive(t) && rm.mesh.orientation(t) <= 0) {
      *retry = true;
      return Status::failure("the embedding inverts elements");
    }
  if (options_.improve && !zone.empty()) {
    s = improve_material_parts(rm, material_, mesh_, density_.get(), density_scale_, quality_floor_);
    report.seconds_improve += since();
    if (!s) {
      *retry = true;
      return s;
    }
  } else if (options_.improve) {
    s = improve_deformed_region(rm, density_.get(), density_scale_, quality_floor_);
    report.seconds_improve += since();
    if (!s) {
      *retry = true;
      return s;
    }
  }
  // The goal: no step below the input's minimum stretch. A region that
  // ends below it is tried again in smaller sub-steps (the last halvings
  // accept it). Not with contact: sub-steps leave more points on the
  // contact surfaces, and the refill's quality does not grow with them.
  if (keep_quality && zone.empty()) {
    double region_min = 0;
    stretch_range(rm.mesh, &region_min, nullptr);
    if (region_min < input_min_stretch_) {
      *retry = true;
      return Status::failure("the adapted region's minimum stretch would fall below the input's");
    }
  }

  // Where each vertex of the adapted region takes its data from in the
  // previous step's mesh: interpolated in space (field transfer). Beyond the
  // region's old boundary on the object's side: the object's tets at the
  // previous pose (their rest positions, mapped back).
  std::vector<VertexStencil> previous(static_cast<std::size_t>(built));
  for (index_t v = 0; v < built; ++v) previous[v] = step_origin_[rm.global_vertex[v]];
  const RigidPose back = pose_.inverse();
  const TransferBeyond into_object = [&](const Vec3& p, const std::array<index_t, 3>& face, VertexStencil& out) {
    const index_t a = rm.global_vertex[face[0]], b = rm.global_vertex[face[1]], c = rm.global_vertex[face[2]];
    int lf = 0;
    index_t t = mesh_.find_face(a, b, c, &lf);
    if (t < 0) return false;
    if (material_[mesh_.tet_origin(t)] != options_.moving_object) {
      const index_t code = mesh_.adjacency(t, lf);
      if (code < 0) return false;
      t = code >> 2;
      if (material_[mesh_.tet_origin(t)] != options_.moving_object) return false;
    }
    const Vec3 q = back.apply(p);
    // A vertex the object shares with another one (contact) has no rest
    // position of its own: its place now, mapped back.
    const auto rest = [&](index_t v) {
      const index_t k = v < static_cast<index_t>(object_index_.size()) ? object_index_[v] : kInvalidIndex;
      return k >= 0 ? object_rest_[k] : Vec3(back.apply(mesh_.point(v)));
    };
    for (int steps = 0; steps < 1000; ++steps) {
      const Tet& T = mesh_.tet(t);
      Eigen::Matrix3d m;
      m.col(0) = rest(T[1]) - rest(T[0]);
      m.col(1) = rest(T[2]) - rest(T[0]);
      m.col(2) = rest(T[3]) - rest(T[0]);
      const Vec3 x = m.partialPivLu().solve(q - rest(T[0]));
      const double w[4] = {1 - x.sum(), x.x(), x.y(), x.z()};
      int worst = 0;
      for (int k = 1; k < 4; ++k)
        if (w[k] < w[worst]) worst = k;
      if (w[worst] >= -1e-12) {
        const VertexStencil* stencils[4];
        for (int k = 0; k < 4; ++k) stencils[k] = &step_origin_[T[k]];
        out = combine_stencils(stencils, w, 4);
        return true;
      }
      const index_t code = mesh_.adjacency(t, worst);
      if (code < 0 || material_[mesh_.tet_origin(code >> 2)] != options_.moving_object) return false;
      t = code >> 2;
    }
    return false;
  };
  std::vector<VertexStencil> origin = transfer_point_data(before, rm.mesh, previous, into_object);
  for (index_t v = 0; v < built; ++v)
    if (moved[v]) origin[v] = previous[v];  // the object's data moves with it

  // Splice the region back: build-time vertices keep their ids, new ones
  // are created with stencils composed back to the input's points.
  const TetMesh& sub = rm.mesh;
  std::vector<index_t> name(static_cast<std::size_t>(sub.vertex_slots()), kInvalidIndex);
  std::vector<Vec3> new_points;
  std::vector<VertexStencil> new_origins, new_step_origins;
  for (index_t v = 0; v < sub.vertex_slots(); ++v) {
    if (!sub.vertex_alive(v)) continue;
    if (v < built) {
      name[v] = rm.global_vertex[v];
      continue;
    }
    name[v] = -1 - static_cast<index_t>(new_points.size());
    new_points.push_back(sub.point(v));
    // The region's stencil (build-time ids) composed with the input's.
    const VertexStencil& local = sub.vertex_origin(v);
    const VertexStencil* input[4];
    double weights[4];
    int n = 0;
    for (int k = 0; k < 4; ++k)
      if (local.ids[k] >= 0 && local.ids[k] < built) {
        input[n] = &mesh_.vertex_origin(rm.global_vertex[local.ids[k]]);
        weights[n++] = local.weights[k];
      }
    new_origins.push_back(n ? combine_stencils(input, weights, n) : VertexStencil());
    new_step_origins.push_back(origin[v]);
  }
  std::vector<Tet> tets;
  std::vector<index_t> origins;
  std::vector<std::array<index_t, 3>> boundary;
  for (index_t t = 0; t < sub.tet_slots(); ++t) {
    if (!sub.tet_alive(t)) continue;
    Tet T = sub.tet(t);
    for (index_t& v : T) v = name[v];
    for (int f = 0; f < 4; ++f)
      if (sub.is_boundary_face(t, f)) boundary.push_back({T[kTetFace[f][0]], T[kTetFace[f][1]], T[kTetFace[f][2]]});
    tets.push_back(T);
    origins.push_back(mesh_.tet_origin(rm.global_tet[sub.tet_origin(t)]));
  }
  // Positions first (replace_cavity compares ids only).
  std::vector<Vec3> previous_position(static_cast<std::size_t>(built));
  for (index_t v = 0; v < built; ++v) {
    previous_position[v] = mesh_.point(rm.global_vertex[v]);
    if (sub.vertex_alive(v)) mesh_.set_point(rm.global_vertex[v], sub.point(v));
  }
  std::vector<index_t> created;
  // An assembly's zone changes the parts' surfaces (3.7.4): only its faces
  // with the kept tets must stay.
  s = assembly_ ? mesh_.replace_boundary_cavity(region, tets, origins, new_points, new_origins, &created)
                : mesh_.replace_cavity(region, tets, origins, new_points, new_origins, &created, &boundary);
  if (!s) {
    for (index_t v = 0; v < built; ++v) mesh_.set_point(rm.global_vertex[v], previous_position[v]);
    return Status::failure("the adapted region could not be put back (" + s.message + ")");
  }
  refresh_stretch(region, mesh_.touched_tets());
  std::size_t moved_space = new_points.size();
  for (index_t v = 0; v < built; ++v) moved_space += !moved[v] && sub.vertex_alive(v) && sub.point(v) != previous_position[v];
  report.moved_vertices += moved_space + object_vertices_.size();
  if (step_origin_.size() < static_cast<std::size_t>(mesh_.vertex_slots()))
    step_origin_.resize(static_cast<std::size_t>(mesh_.vertex_slots()));
  for (index_t v = 0; v < built; ++v)
    if (sub.vertex_alive(v)) step_origin_[rm.global_vertex[v]] = origin[v];
  for (std::size_t i = 0; i < created.size(); ++i) step_origin_[created[i]] = new_step_origins[i];
  if (contact_ && (!zone.empty() || !contact_->shared.empty())) {
    std::vector<index_t> placed(created);
    for (index_t v = 0; v < built; ++v)
      if (sub.vertex_alive(v)) placed.push_back(rm.global_vertex[v]);
    rebuild_object_vertices(placed, to);
  }
  // (ii) the whole object moves rigidly (its inside is no part of K_Df).
  for (std::size_t k = 0; k < object_vertices_.size(); ++k)
    mesh_.set_point(object_vertices_[k], to.apply(object_rest_[k]));
  pose_ = to;
  ++mesh_version_;
  report.seconds_splice += since();
  return Status::success();
}

Status AdaptSession::advance(AdaptStepReport* report_out) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const int next = step_ + 1;
  if (!motion_.table.empty() && next > static_cast<int>(motion_.table.size()))
    return Status::failure("step " + std::to_string(next) + " is beyond the motion table's " +
                           std::to_string(motion_.table.size()) + " rows");
  // Each vertex's data source in this step's input (the previous output,
  // dense ids): itself, until the region's adaptation says otherwise.
  std::vector<VertexStencil> last_step_origin = std::move(step_origin_);
  step_origin_.assign(static_cast<std::size_t>(mesh_.vertex_slots()), VertexStencil());
  {
    index_t dense = 0;
    for (index_t v = 0; v < mesh_.vertex_slots(); ++v)
      if (mesh_.vertex_alive(v)) {
        step_origin_[v].ids[0] = dense++;
        step_origin_[v].weights[0] = 1;
      }
  }
  AdaptStepReport report;
  report.step = next;
  report.substeps = 0;
  const RigidPose target = motion_.pose(next);
  {
    // Vertices that end on another object's surface (contact) are no
    // penetration; the walk cannot tell them.
    std::unordered_set<index_t> touching;
    for (const ContactRegion& c : contacts_at(target)) touching.insert(c.moving_vertices.begin(), c.moving_vertices.end());
    std::vector<index_t> walkers;
    std::vector<Vec3> moved;
    for (const index_t v : object_surface_) {
      if (touching.count(v)) continue;
      walkers.push_back(v);
      moved.push_back(target.apply(object_rest_[object_index_[v]]));
    }
    // An assembly has no space to walk through: the moved surface is
    // located in the other parts instead.
    Status p = assembly_ ? check_assembly_overlap(target)
                         : detect_penetration(mesh_, material_, options_.moving_object, walkers, moved);
    if (p && contact_ && !contact_->shared.empty()) p = check_shared_vertices(target);
    if (!p)
      return Status::failure("step " + std::to_string(next) + " refused: " + p.message + " (earlier steps are kept)");
  }
  // A failed attempt leaves the mesh as it was; only sub-steps need a copy
  // to return to (taken at the first halving, before any sub-step is done).
  TetMesh saved_mesh;
  std::vector<double> saved_stretch;
  const RigidPose saved_pose = pose_;
  int halvings = 0;
  // The remaining motion is done in sub-steps of 1 / 2^halvings of it.
  double done = 0;
  while (done < 1 - 1e-12) {
    const double fraction = std::min(1.0, std::ldexp(1.0, -halvings) / (1 - done));
    const RigidPose rest = target.after(pose_.inverse());
    const RigidPose to = fraction >= 1 ? target : rest.fraction(fraction).after(pose_);
    bool retry = false;
    // Sub-steps for quality alone: at most 1 / 8 of the step.
    const Status s = move_to(to, report, &retry, options_.improve && halvings < std::min(3, options_.max_halvings));
    if (s) {
      done += (1 - done) * fraction;
      ++report.substeps;
      continue;
    }
    if (retry && halvings < options_.max_halvings) {
      if (halvings++ == 0) {
        saved_mesh = mesh_;
        saved_stretch = stretch_;
      }
      continue;
    }
    step_origin_ = std::move(last_step_origin);
    if (halvings > 0) {
      mesh_ = std::move(saved_mesh);
      ++mesh_version_;
      stretch_ = std::move(saved_stretch);
      pose_ = saved_pose;
    }
    std::ostringstream os;
    os << "step " << next << " refused: " << s.message;
    if (retry)
      os << ", even in " << (1 << halvings) << " sub-steps; the moving object may penetrate another object "
         << "or the domain's boundary, or the space around it is too thin (earlier steps are kept)";
    return Status::failure(os.str());
  }
  step_ = next;
  // A mesh that lost vertices asks for a denser target in the next step's
  // region (and the other way round): an integral control of the count.
  const double count_ratio = static_cast<double>(input_vertices_) / static_cast<double>(mesh_.live_vertices());
  density_scale_ = std::clamp(density_scale_ * std::clamp(count_ratio * count_ratio, 0.95, 1.05), 0.5, 2.0);
  report.vertices = mesh_.live_vertices();
  report.tets = mesh_.live_tets();
  double lo = std::numeric_limits<double>::infinity(), sum = 0;
  std::size_t n = 0;
  for (const double x : stretch_) {
    if (std::isnan(x)) continue;
    lo = std::min(lo, x);
    sum += x;
    ++n;
  }
  report.min_stretch = n ? lo : 0;
  report.mean_stretch = n ? sum / static_cast<double>(n) : 0;
  // Contact faces after the step (3.7.3); a single object has none.
  if (contact_) report.contact_faces = count_object_contact_faces(mesh_, material_);
  report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (report_out) *report_out = std::move(report);
  return Status::success();
}

}  // namespace femorph
