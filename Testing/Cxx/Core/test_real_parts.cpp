// The core mesh on real parts made by other people (shared/realparts, Medit
// meshes): it builds, agrees with the independent checker, and survives
// random local operations that keep the part's shape and volume.
#include "io/read_medit_mesh.h"
#include "mesh/tet_mesh.h"
#include "quality/check_validity.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

namespace femorph {
namespace {

class RealPart : public ::testing::TestWithParam<const char*> {};

TEST_P(RealPart, BuildsAndSurvivesShapePreservingOperations) {
  const std::string path = std::string(FEMORPH_REALPARTS_DIR) + "/" + GetParam();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found";
  MeditMesh medit;
  const Status read = read_medit_mesh(path, medit);
  ASSERT_TRUE(read.ok) << read.message;

  TetMesh m;
  BuildReport report;
  const Status built = m.build(medit.points, medit.tets, {}, &report);
  ASSERT_TRUE(built.ok) << built.message;
  EXPECT_EQ(m.live_tets(), medit.tets.size());
  const ValidityReport input_check = check_validity(medit.points, medit.tets);
  EXPECT_TRUE(input_check.ok()) << input_check.summary();
  EXPECT_EQ(report.boundary_faces, input_check.boundary_faces);
  const double volume = testing::total_volume(medit.points, medit.tets);

  // Operations that cannot change the shape of an unsegmented part: splits
  // (boundary edges and faces are split in their plane), interior flips, and
  // collapses that keep every boundary vertex where it is.
  std::mt19937_64 rng(7);
  int accepted = 0;
  for (int i = 0; i < 20000; ++i) {
    index_t t;
    do t = static_cast<index_t>(rng() % static_cast<std::uint64_t>(m.tet_slots()));
    while (!m.tet_alive(t));
    const std::uint64_t r = rng();
    static const int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    const index_t a = m.tet(t)[edges[r % 6][0]], b = m.tet(t)[edges[r % 6][1]];
    OpStatus s = OpStatus::InvalidArgument;
    switch ((r >> 8) % 5) {
      case 0: s = m.split_edge(a, b, nullptr, nullptr, t); break;
      case 1: s = m.flip_23(t, static_cast<int>((r >> 16) & 3)); break;
      case 2: s = m.flip_32(a, b, t); break;
      case 3: s = m.flip_44(a, b, static_cast<int>((r >> 16) & 1), t); break;
      default:
        // Half-edge collapse of an inner vertex onto its neighbour.
        if (m.vertex_class(a) == VertexClass::Inner) s = m.half_edge_collapse(Keep{b}, Remove{a});
        break;
    }
    accepted += s == OpStatus::Ok;
  }
  EXPECT_GT(accepted, 5000);
  const Status consistent = m.check_consistency();
  ASSERT_TRUE(consistent.ok) << consistent.message;
  const CompactMesh out = m.compact();
  const ValidityReport after = check_validity(out.points, out.tets);
  EXPECT_TRUE(after.ok()) << after.summary();
  EXPECT_NEAR(testing::total_volume(out.points, out.tets), volume, 1e-12 * volume);
}

INSTANTIATE_TEST_SUITE_P(SharedRealParts, RealPart, ::testing::Values("fandisk_tet.mesh", "chamfer_tet.mesh"));

}  // namespace
}  // namespace femorph
