// The assembly mode of FEMorph Adapt (thesis 3.7.4): a crank and a bearing
// meshed separately (non-conforming, no space mesh); the crank turns 10
// degrees per step and every step's contact must be conformal. The checks
// are independent of the code under test: faces matched by their vertex ids,
// boundary faces of the two parts compared by position, the validity checker.
#include "adapt/adapt.h"

#include "quality/check_validity.h"
#include "quality/tet_quality.h"
#include "test_adapt_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace femorph {
namespace {

double part_volume(const std::vector<Vec3>& p, const std::vector<Tet>& tets, const std::vector<int>& mat, int which) {
  double v = 0;
  for (std::size_t t = 0; t < tets.size(); ++t)
    if (mat[t] == which)
      v += (p[tets[t][1]] - p[tets[t][0]]).dot((p[tets[t][2]] - p[tets[t][0]]).cross(p[tets[t][3]] - p[tets[t][0]])) / 6;
  return v;
}

struct AssemblyRun {
  int steps = 0;
  double worst_stretch = 1, max_drift = 0;
  std::vector<double> seconds;
};

// Turns the crank `steps` x 10 degrees and checks every step (see the file's
// comment); the crank's surface at its ends out of the bearing (never near
// the contact: |z| > Lb / 2 + (Lc - Lb) / 3; inside, the region's ring of
// large inner tets may reach that far) and the bearing's outer surface are
// the input's, exactly moved and unchanged.
AssemblyRun run_crank(const testing::CrankAssembly& g, const RigidMotion& motion, int steps) {
  AssemblyRun run;
  Status made;
  const testing::MaterialMesh mm = testing::make_crank_assembly(g, &made);
  EXPECT_TRUE(made) << made.message;
  if (!made) return run;
  AdaptOptions options;
  options.moving_object = 1;
  AdaptSession session;
  const Status s = session.init(mm.points, mm.tets, mm.material, motion, options);
  EXPECT_TRUE(s) << s.message;
  if (!s) return run;
  EXPECT_TRUE(session.assembly());
  // The input is not conformal: the parts share no face, and the crank's
  // lower half lies on the bore.
  const AdaptOutput input = session.output();
  const double edge = std::min(g.crank_edge(), g.bearing_edge());
  const testing::AssemblyConformity c0 = testing::assembly_conformity(input, g.r, 0.1 * edge, 0.05 * edge);
  EXPECT_EQ(c0.shared, 0u);
  EXPECT_GT(c0.coincident, 0u);
  const double crank_volume = part_volume(mm.points, mm.tets, mm.material, 1);
  const double bearing_volume = part_volume(mm.points, mm.tets, mm.material, 2);
  std::vector<Vec3> ends, outer;
  for (std::size_t t = 0; t < mm.tets.size(); ++t)
    for (const index_t v : mm.tets[t]) {
      const Vec3& p = mm.points[v];
      const double rho = std::hypot(p.x(), p.y());
      const bool crank_surface = rho > g.r - 1e-9 || std::abs(p.z()) > 0.5 * g.Lc - 1e-9;
      if (mm.material[t] == 1 && crank_surface && std::abs(p.z()) > 0.5 * g.Lb + (g.Lc - g.Lb) / 3)
        ends.push_back(p);
      if (mm.material[t] == 2 && rho > g.R - 1e-9) outer.push_back(p);
    }
  const auto less = [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(outer.begin(), outer.end(), less);
  outer.erase(std::unique(outer.begin(), outer.end()), outer.end());
  std::sort(ends.begin(), ends.end(), less);
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  for (int n = 1; n <= steps; ++n) {
    AdaptStepReport report;
    const Status st = session.advance(&report);
    EXPECT_TRUE(st) << "step " << n << ": " << st.message;
    if (!st) return run;
    const AdaptOutput out = session.output();
    const ValidityReport v = check_validity(out.points, out.tets);
    EXPECT_TRUE(v.ok()) << "step " << n << ": " << v.summary();
    const testing::AssemblyConformity c = testing::assembly_conformity(out, g.r, 0.1 * edge, 0.05 * edge);
    EXPECT_EQ(c.coincident, 0u) << "step " << n << ": crank faces lying on bearing faces, not shared";
    EXPECT_NEAR(c.shared_area, g.contact_area(), 0.01 * g.contact_area()) << "step " << n;
    EXPECT_EQ(report.contact_faces, c.shared) << "step " << n;
    // Volumes: the crank's lower half takes the bore's polygon.
    EXPECT_NEAR(part_volume(out.points, out.tets, out.material, 1), crank_volume, 0.01 * crank_volume) << "step " << n;
    EXPECT_NEAR(part_volume(out.points, out.tets, out.material, 2), bearing_volume, 1e-9 * bearing_volume)
        << "step " << n;
    // Rigid away from the contact: the crank's ends moved by the pose, the
    // bearing's outer surface unchanged; every crank point, mapped back,
    // inside its initial cylinder.
    const RigidPose pose = motion.pose(n), back = pose.inverse();
    std::vector<Vec3> crank_now, bearing_now;
    for (std::size_t t = 0; t < out.tets.size(); ++t)
      for (const index_t p : out.tets[t]) (out.material[t] == 1 ? crank_now : bearing_now).push_back(out.points[p]);
    std::size_t outside = 0, ends_found = 0, outer_found = 0;
    std::vector<Vec3> crank_back;
    for (const Vec3& p : crank_now) {
      const Vec3 x = back.apply(p);
      outside += std::hypot(x.x(), x.y()) > g.r + 1e-9 || std::abs(x.z()) > 0.5 * g.Lc + 1e-9 * g.Lc;
      crank_back.push_back(x);
    }
    EXPECT_EQ(outside, 0u) << "step " << n << ": crank points outside the crank's initial cylinder";
    for (const Vec3& p : ends)
      for (const Vec3& x : crank_back)
        if ((x - p).norm() < 1e-9) {
          ++ends_found;
          break;
        }
    std::sort(bearing_now.begin(), bearing_now.end(), less);
    for (const Vec3& p : outer) outer_found += std::binary_search(bearing_now.begin(), bearing_now.end(), p, less);
    EXPECT_EQ(ends_found, ends.size()) << "step " << n << ": the crank's ends' surface did not move rigidly";
    EXPECT_EQ(outer_found, outer.size()) << "step " << n << ": the bearing's outer surface changed";
    const double drift = std::abs(double(out.points.size()) / double(mm.points.size()) - 1);
    EXPECT_LE(drift, 0.10) << "step " << n;
    run.max_drift = std::max(run.max_drift, drift);
    run.worst_stretch = std::min(run.worst_stretch, report.min_stretch);
    run.seconds.push_back(report.seconds);
    run.steps = n;
    std::printf("assembly step %d: %zu points (input %zu), %zu tets, contact faces %zu (area %.4f of %.4f), "
                "min stretch %.3f, %.3f s (contact %.3f, improve %.3f)\n",
                n, out.points.size(), mm.points.size(), out.tets.size(), c.shared, c.shared_area, g.contact_area(),
                report.min_stretch, report.seconds, report.seconds_contact, report.seconds_improve);
    if (::testing::Test::HasFailure()) return run;
  }
  return run;
}

// Thesis 3.7.4 at test size: the crank turns a full turn in 36 steps of 10
// degrees in the bearing's bore; conformal at contact every step.
TEST(AdaptAssembly, CrankTurnsInBearing) {
  const testing::CrankAssembly g;
  const int steps = 36;
  RigidMotion motion;
  motion.rotation_axis = Vec3::UnitZ();
  motion.rotation_degrees_per_step = 10;
  const AssemblyRun run = run_crank(g, motion, steps);
  ASSERT_EQ(run.steps, steps);
  // The zone's refill and 3.6 on it and the ring around it keep the
  // quality (thesis 3.7.4: above the recommended lower limit).
  EXPECT_GE(run.worst_stretch, 0.1);
  std::vector<double> t = run.seconds;
  std::sort(t.begin(), t.end());
  std::printf("crank in bearing: %d steps, min stretch %.3f, largest vertex drift %.1f%%, median %.3f s/step\n", steps,
              run.worst_stretch, 100 * run.max_drift, t[t.size() / 2]);
}

// A screw motion: the crank turns 7 degrees and slides 0.05 along its axis
// per step (it still spans the bore): the contact slides too.
TEST(AdaptAssembly, CrankScrewsThroughBearing) {
  const testing::CrankAssembly g;
  const int steps = 12;
  RigidMotion motion;
  motion.rotation_axis = Vec3::UnitZ();
  motion.rotation_degrees_per_step = 7;
  motion.translation_per_step = Vec3(0, 0, 0.05);
  const AssemblyRun run = run_crank(g, motion, steps);
  ASSERT_EQ(run.steps, steps);
  EXPECT_GE(run.worst_stretch, 0.1);
}

// Bad input: parts that overlap (a crank wider than the bore) are refused
// at init, naming the overlap.
TEST(AdaptAssembly, OverlappingPartsAreRefused) {
  testing::CrankAssembly g;
  Status made;
  const testing::MaterialMesh mm = testing::make_crank_assembly(g, &made);
  ASSERT_TRUE(made) << made.message;
  std::vector<Vec3> points = mm.points;
  // Scale the crank by 1.15 about its axis (each point once).
  std::vector<std::uint8_t> done(points.size(), 0);
  for (std::size_t t = 0; t < mm.tets.size(); ++t)
    if (mm.material[t] == 1)
      for (const index_t v : mm.tets[t])
        if (!done[v]) {
          done[v] = 1;
          points[v] = Vec3(1.15 * points[v].x(), 1.15 * points[v].y(), points[v].z());
        }
  RigidMotion motion;
  motion.rotation_axis = Vec3::UnitZ();
  motion.rotation_degrees_per_step = 10;
  AdaptOptions options;
  AdaptSession session;
  const Status s = session.init(points, mm.tets, mm.material, motion, options);
  EXPECT_FALSE(s);
  EXPECT_NE(s.message.find("overlap"), std::string::npos) << s.message;
}

// Bad motion: a step that pushes the crank into the bearing is refused,
// naming the step; the session stays where it was.
TEST(AdaptAssembly, PushIntoTheBearingIsRefused) {
  const testing::CrankAssembly g;
  const testing::MaterialMesh mm = testing::make_crank_assembly(g);
  ASSERT_FALSE(mm.tets.empty());
  RigidMotion motion;
  RigidPose turn, push;
  turn.R = Eigen::AngleAxisd(degrees_to_radians(10.0), Vec3::UnitZ()).toRotationMatrix();
  push = turn;
  push.t = Vec3(0, -0.3, 0);
  motion.table = {turn, push};
  AdaptOptions options;
  AdaptSession session;
  ASSERT_TRUE(session.init(mm.points, mm.tets, mm.material, motion, options));
  ASSERT_TRUE(session.advance());
  const AdaptOutput before = session.output();
  const Status st = session.advance();
  EXPECT_FALSE(st);
  EXPECT_NE(st.message.find("step 2 refused"), std::string::npos) << st.message;
  EXPECT_NE(st.message.find("object 2"), std::string::npos) << st.message;
  EXPECT_EQ(session.current_step(), 1);
  const AdaptOutput after = session.output();
  EXPECT_EQ(after.points, before.points);
  EXPECT_EQ(after.tets, before.tets);
}

// detect_overlap on one tet of part 2 (the unit corner tet) and one of part
// 1 elsewhere: a point deep inside part 2 is an overlap, one on its face or
// within the tolerance of it is not, nor a point of part 1's own tet.
TEST(AdaptAssembly, DetectOverlapByDepth) {
  const std::vector<Vec3> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                                 {5, 0, 0}, {6, 0, 0}, {5, 1, 0}, {5, 0, 1}};
  const std::vector<Tet> tets{{{0, 1, 2, 3}}, {{4, 5, 6, 7}}};
  TetMesh mesh;
  ASSERT_TRUE(mesh.build(points, tets));
  const std::vector<int> material{2, 1};
  const double tol = 0.01;
  EXPECT_TRUE(detect_overlap(mesh, material, 1, {Vec3(0.2, 0.2, 0)}, tol));        // on the face z = 0
  EXPECT_TRUE(detect_overlap(mesh, material, 1, {Vec3(0.2, 0.2, 0.005)}, tol));    // within the tolerance
  EXPECT_TRUE(detect_overlap(mesh, material, 1, {Vec3(5.1, 0.1, 0.1)}, tol));      // part 1's own tet
  EXPECT_TRUE(detect_overlap(mesh, material, 1, {Vec3(2, 2, 2)}, tol));            // outside both
  const Status s = detect_overlap(mesh, material, 1, {Vec3(0.1, 0.1, 0.1)}, tol);  // 0.1 deep
  EXPECT_FALSE(s);
  EXPECT_NE(s.message.find("object 1 would overlap object 2"), std::string::npos) << s.message;
}

// A single part without a space mesh has nothing to adapt.
TEST(AdaptAssembly, ASinglePartIsRefused) {
  const testing::CrankAssembly g;
  const testing::MaterialMesh mm = testing::make_crank_assembly(g);
  ASSERT_FALSE(mm.tets.empty());
  std::vector<Tet> tets;
  std::vector<int> material;
  for (std::size_t t = 0; t < mm.tets.size(); ++t)
    if (mm.material[t] == 1) {
      tets.push_back(mm.tets[t]);
      material.push_back(1);
    }
  std::vector<Vec3> points(mm.points.begin(), mm.points.end());
  AdaptSession session;
  const Status s = session.init(points, tets, material, RigidMotion(), AdaptOptions());
  EXPECT_FALSE(s);
  EXPECT_NE(s.message.find("no cell has material id 0"), std::string::npos) << s.message;
}

}  // namespace
}  // namespace femorph
