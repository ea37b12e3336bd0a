// What FEMorph Improve aims at (make_improve_target, thesis 2.6.3-2.6.4):
// the density field travels with the material from a reference of the same
// connectivity and is taken in space otherwise; the acceptable geometric
// error comes from the reference's segmentation when it matches, else from
// the mesh itself. Also the pack/unpack pair of the curve rows the target's
// geometry is read from.
#include "improve/control_shape_accuracy.h"
#include "improve/improve_target.h"
#include "mesh/tet_mesh.h"
#include "segment/segmentation.h"
#include "test_improve_meshes.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace femorph {
namespace {

using testing::make_cube_mesh;
using testing::improve_meshes::build;
using testing::improve_meshes::make_annulus;
using testing::improve_meshes::make_grid_mesh;

// Mean of the target density over the tets' centroids.
double mean_target_density(const TetMesh& mesh, const DensityGrid& grid) {
  double sum = 0;
  std::size_t n = 0;
  for (index_t t = 0; t < mesh.tet_slots(); ++t) {
    const Tet& T = mesh.tet(t);
    const Vec3 c = (mesh.point(T[0]) + mesh.point(T[1]) + mesh.point(T[2]) + mesh.point(T[3])) / 4;
    sum += grid.cell_density(c);
    ++n;
  }
  return sum / static_cast<double>(n);
}

TEST(ImproveTarget, WithoutReferenceTheMeshKeepsItsOwn) {
  const auto annulus = make_annulus();
  const auto grid = make_grid_mesh(annulus.grid);
  const TetMesh mesh = build(grid.mesh);
  const ImproveTarget target = make_improve_target(mesh, &annulus.geometry, nullptr);
  EXPECT_TRUE(target.warnings.empty());
  ASSERT_FALSE(target.density.empty());
  EXPECT_TRUE(target.view().density == &target.density);
  const std::vector<double> own = region_geometric_error(mesh, annulus.geometry);
  ASSERT_EQ(target.acceptable_error.size(), own.size());
  for (std::size_t r = 0; r < own.size(); ++r) {
    if (std::isnan(own[r])) {
      EXPECT_TRUE(std::isnan(target.acceptable_error[r])) << r;
    } else {
      EXPECT_EQ(target.acceptable_error[r], own[r]) << r;
    }
  }
  // The cylinders have a chord error, the caps none.
  EXPECT_GT(own[0], 0);
  EXPECT_TRUE(std::isnan(own[2]));

  ImproveTargetOptions options;
  options.density = false;
  EXPECT_TRUE(make_improve_target(mesh, &annulus.geometry, nullptr, options).density.empty());
  EXPECT_TRUE(make_improve_target(mesh, nullptr, nullptr).acceptable_error.empty());
}

// A reference at half the size has twice the density. With the input's
// connectivity its densities travel with the material onto the input (Eq.
// 2.33): twice the input's own. A reference that is not the input's
// connectivity is taken in space: the input's own mesh (tets listed in
// another order) gives the input's own density.
TEST(ImproveTarget, DensityTravelsWithTheMaterialOrIsTakenInSpace) {
  const auto cube = make_cube_mesh(4, 0.0, 1);
  TetMesh mesh;
  ASSERT_TRUE(mesh.build(cube.points, cube.tets).ok);
  // One grid for all, so that only the densities differ.
  ImproveTargetOptions options;
  options.grid_cell_size = 0.1;
  const double own = mean_target_density(mesh, make_improve_target(mesh, nullptr, nullptr, options).density);
  ASSERT_GT(own, 0);

  ReferenceMesh half;
  for (const Vec3& p : cube.points) half.points.push_back(0.5 * p);
  half.tets = cube.tets;
  const ImproveTarget travelled = make_improve_target(mesh, nullptr, &half, options);
  EXPECT_TRUE(travelled.warnings.empty());
  EXPECT_NEAR(mean_target_density(mesh, travelled.density) / own, 2.0, 1e-9);

  ReferenceMesh reordered;
  reordered.points = cube.points;
  reordered.tets.assign(cube.tets.rbegin(), cube.tets.rend());
  const ImproveTarget inSpace = make_improve_target(mesh, nullptr, &reordered, options);
  EXPECT_NEAR(mean_target_density(mesh, inSpace.density) / own, 1.0, 1e-6);

  // A tet's vertices in another order are the same connectivity.
  ReferenceMesh rotated = half;
  for (Tet& t : rotated.tets) t = Tet{{t[1], t[2], t[0], t[3]}};
  EXPECT_NEAR(mean_target_density(mesh, make_improve_target(mesh, nullptr, &rotated, options).density) / own, 2.0, 1e-9);
}

TEST(ImproveTarget, AcceptableErrorFromAMatchingReferenceSegmentation) {
  const auto annulus = make_annulus();
  const auto grid = make_grid_mesh(annulus.grid);
  const TetMesh mesh = build(grid.mesh);

  // The reference: the annulus with the inner cylinder's radius 10% larger
  // in its fit, so its chord errors differ from the input's.
  ReferenceMesh reference;
  reference.points = grid.mesh.points;
  reference.tets = grid.mesh.tets;
  reference.face_regions = grid.mesh.face_regions;
  reference.geometry = annulus.geometry;
  reference.geometry.regions[1].radius *= 1.1;
  for (const SurfacePrimitive& s : annulus.geometry.regions) reference.region_types.push_back(s.type);
  const std::vector<double> expected = region_geometric_error(reference.points, reference.tets,
                                                              reference.face_regions, reference.geometry);

  const ImproveTarget target = make_improve_target(mesh, &annulus.geometry, &reference);
  EXPECT_TRUE(target.warnings.empty());
  ASSERT_EQ(target.acceptable_error.size(), expected.size());
  EXPECT_EQ(target.acceptable_error[1], expected[1]);
  EXPECT_NE(target.acceptable_error[1], region_geometric_error(mesh, annulus.geometry)[1]);

  // A region whose type changed has no target.
  reference.region_types[0] = SurfaceType::Unknown;
  const ImproveTarget changed = make_improve_target(mesh, &annulus.geometry, &reference);
  EXPECT_TRUE(std::isnan(changed.acceptable_error[0]));
  EXPECT_EQ(changed.acceptable_error[1], expected[1]);

  // A reference without a matching segmentation: the input's own error, and
  // the user is told.
  reference.region_types.pop_back();
  const ImproveTarget own = make_improve_target(mesh, &annulus.geometry, &reference);
  ASSERT_EQ(own.warnings.size(), 1u);
  EXPECT_NE(own.warnings[0].find("no segmentation arrays matching"), std::string::npos);
  EXPECT_EQ(own.acceptable_error[1], region_geometric_error(mesh, annulus.geometry)[1]);
}

TEST(ImproveTarget, TheReferenceMustBeAMesh) {
  const auto cube = make_cube_mesh(2, 0.0, 1);
  ReferenceMesh reference;
  reference.points = cube.points;
  reference.tets = cube.tets;
  EXPECT_TRUE(check_reference_mesh(reference).ok);

  ReferenceMesh repeated = reference;
  repeated.tets[3][2] = repeated.tets[3][0];
  EXPECT_NE(check_reference_mesh(repeated).message.find("tetrahedron 3 uses point"), std::string::npos);

  ReferenceMesh outside = reference;
  outside.tets[5][1] = static_cast<index_t>(outside.points.size());
  EXPECT_NE(check_reference_mesh(outside).message.find("tetrahedron 5 refers to point"), std::string::npos);

  ReferenceMesh flat = reference;
  for (Vec3& p : flat.points) p.z() = 0;
  const Status s = check_reference_mesh(flat);
  EXPECT_NE(s.message.find(std::to_string(cube.tets.size()) + " tetrahedra have zero volume"), std::string::npos)
      << s.message;

  ReferenceMesh mixed = reference;
  std::swap(mixed.tets[0][1], mixed.tets[0][2]);
  EXPECT_NE(check_reference_mesh(mixed).message.find("oriented both ways"), std::string::npos);
}

// pack_curve_parameters and unpack_curve_parameters are inverse.
TEST(CurveParameters, PackUnpackRoundTrip) {
  BoundaryCurve curve;
  curve.type = CurveType::CircularArc;
  curve.curve.type = CurveType::CircularArc;
  curve.curve.center = Vec3(1.5, -2, 3e-7);
  curve.curve.normal = Vec3(0, 0.6, 0.8);
  curve.curve.direction = Vec3(1, 0, 0);
  curve.curve.radius = 4.25;
  curve.curve.minor_radius = 0.5;
  curve.curve.start = Vec3(6, 7, 8);
  curve.curve.end = Vec3(-9, 10, 1e9);
  curve.region_a = 12;
  curve.region_b = kInvalidIndex;
  curve.continuity = Continuity::G1;
  const auto row = pack_curve_parameters(curve);
  const BoundaryCurve back = unpack_curve_parameters(curve.type, row.data());
  EXPECT_EQ(back.type, curve.type);
  EXPECT_EQ(back.curve.type, curve.type);
  EXPECT_EQ(back.curve.center, curve.curve.center);
  EXPECT_EQ(back.curve.normal, curve.curve.normal);
  EXPECT_EQ(back.curve.direction, curve.curve.direction);
  EXPECT_EQ(back.curve.radius, curve.curve.radius);
  EXPECT_EQ(back.curve.minor_radius, curve.curve.minor_radius);
  EXPECT_EQ(back.curve.start, curve.curve.start);
  EXPECT_EQ(back.curve.end, curve.curve.end);
  EXPECT_EQ(back.region_a, 12);
  EXPECT_EQ(back.region_b, kInvalidIndex);
  EXPECT_EQ(back.continuity, Continuity::G1);
  EXPECT_EQ(pack_curve_parameters(back), row);

  curve.continuity = Continuity::G0;
  EXPECT_EQ(unpack_curve_parameters(curve.type, pack_curve_parameters(curve).data()).continuity, Continuity::G0);
  EXPECT_EQ(unpack_curve_parameters(CurveType::Line, nullptr).type, CurveType::Line);
}

}  // namespace
}  // namespace femorph
