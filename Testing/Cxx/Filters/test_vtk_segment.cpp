// vtkFEMorphSegment: defaults and clamps equal the core's and the XML's, the
// three outputs, bad input refused with messages naming the problem, progress
// and abort reaching into the core. These tests do not depend on the
// segmentation's quality (they stop before segment_surface or abort at its
// first step). Also: a box segmented into six planes, a flat tet without a
// crash, the input untouched.
#include "../test_meshes.h"
#include "filters_test_utils.h"
#include "vtkFEMorphSegment.h"

#include "vtkCallbackCommand.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkXMLDataElement.h"
#include "vtkXMLUtilities.h"

#include "segment/segmentation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>


using femorph_test::MakeGrid;
using femorph_test::MessageRecorder;

namespace
{
// The cube [0, 1]^3 in n^3 cells of 6 tets (Core tests' mesh), as a grid.
vtkSmartPointer<vtkUnstructuredGrid> MakeCube(int n)
{
  const femorph::testing::TestMesh cube = femorph::testing::make_cube_mesh(n, 0.0, 1);
  std::vector<std::array<double, 3>> points;
  for (const femorph::Vec3& p : cube.points)
  {
    points.push_back({ p.x(), p.y(), p.z() });
  }
  std::vector<std::pair<int, std::vector<vtkIdType>>> cells;
  for (const femorph::Tet& t : cube.tets)
  {
    cells.push_back({ VTK_TETRA, { t[0], t[1], t[2], t[3] } });
  }
  return MakeGrid(points, cells);
}

// Runs the filter; returns the executive's status (1 success, 0 failure).
int RunSegment(vtkFEMorphSegment* segment, vtkDataObject* input, MessageRecorder* messages)
{
  messages->Observe(segment);
  segment->SetInputData(input);
  return segment->GetExecutive()->Update();
}

void ExpectEmptyOutputs(vtkFEMorphSegment* segment)
{
  ASSERT_NE(segment->GetMeshOutput(), nullptr);
  ASSERT_NE(segment->GetSurfaceOutput(), nullptr);
  ASSERT_NE(segment->GetRegionTableOutput(), nullptr);
  EXPECT_EQ(segment->GetMeshOutput()->GetNumberOfCells(), 0);
  EXPECT_EQ(segment->GetSurfaceOutput()->GetNumberOfCells(), 0);
  EXPECT_EQ(segment->GetRegionTableOutput()->GetNumberOfRows(), 0);
  EXPECT_EQ(segment->GetMeshOutput()->GetCellData()->GetArray("FaceRegion"), nullptr);
}

// Aborts the algorithm when its progress text names `step`.
struct AbortAt
{
  std::string Step;
  std::vector<std::string> Texts;
  std::vector<double> Values;
};

void ObserveAndAbortAt(vtkFEMorphSegment* segment, AbortAt* abortAt, vtkCallbackCommand* command)
{
  command->SetClientData(abortAt);
  command->SetCallback([](vtkObject* caller, unsigned long, void* client, void* call) {
    auto* self = static_cast<AbortAt*>(client);
    auto* algorithm = static_cast<vtkAlgorithm*>(caller);
    const char* text = algorithm->GetProgressText();
    self->Texts.push_back(text ? text : "");
    self->Values.push_back(*static_cast<double*>(call));
    if (!self->Step.empty() && text && self->Step == text)
    {
      algorithm->SetAbortExecute(1);
    }
  });
  segment->AddObserver(vtkCommand::ProgressEvent, command);
}
} // namespace

TEST(Segment, DefaultsAreTheCoreDefaultsAndClamped)
{
  const femorph::SegmentationParams core;
  vtkNew<vtkFEMorphSegment> segment;
  EXPECT_EQ(segment->GetSharpAngle(), core.sharp_angle_deg);
  EXPECT_EQ(segment->GetCylinderAngleTolerance(), core.cylinder_angle_tolerance_deg);
  EXPECT_EQ(segment->GetConeAngleTolerance(), core.cone_angle_tolerance_deg);
  EXPECT_EQ(segment->GetSphereDirectionAngle(), core.sphere_direction_angle_deg);
  EXPECT_EQ(segment->GetDistanceTolerance(), core.distance_tolerance);
  EXPECT_EQ(segment->GetRansacIterations(), core.ransac_iterations);
  EXPECT_EQ(static_cast<std::uint64_t>(segment->GetRandomSeed()), core.random_seed);
  EXPECT_EQ(segment->GetRefineFits() != 0, core.refine_fits);
  EXPECT_EQ(segment->GetAdaptiveTolerance() != 0, core.adaptive_tolerance);
  // Thesis ranges (2.4.3.2) hold for the defaults.
  EXPECT_GE(segment->GetCylinderAngleTolerance(), 1.0);
  EXPECT_LE(segment->GetCylinderAngleTolerance(), 1.5);
  EXPECT_GE(segment->GetConeAngleTolerance(), 0.4);
  EXPECT_LE(segment->GetConeAngleTolerance(), 0.8);
  EXPECT_EQ(segment->GetSphereDirectionAngle(), 60.0);

  segment->SetSharpAngle(500);
  EXPECT_EQ(segment->GetSharpAngle(), 180);
  segment->SetConeAngleTolerance(-1);
  EXPECT_EQ(segment->GetConeAngleTolerance(), 0);
  segment->SetDistanceTolerance(3);
  EXPECT_EQ(segment->GetDistanceTolerance(), 1);
  segment->SetRansacIterations(0);
  EXPECT_EQ(segment->GetRansacIterations(), 1);
  segment->SetRandomSeed(-5);
  EXPECT_EQ(segment->GetRandomSeed(), 0);
  segment->RefineFitsOff();
  EXPECT_EQ(segment->GetRefineFits(), 0);
}

TEST(Segment, PrintSelfListsEveryProperty)
{
  vtkNew<vtkFEMorphSegment> segment;
  segment->SetSharpAngle(31.5);
  segment->SetCylinderAngleTolerance(1.25);
  segment->SetConeAngleTolerance(0.5);
  segment->SetSphereDirectionAngle(55);
  segment->SetDistanceTolerance(0.0625);
  segment->SetRansacIterations(321);
  segment->SetRandomSeed(7);
  segment->RefineFitsOff();
  segment->AdaptiveToleranceOff();
  std::ostringstream os;
  segment->PrintSelf(os, vtkIndent());
  for (const char* name : { "SharpAngle: 31.5", "CylinderAngleTolerance: 1.25",
         "ConeAngleTolerance: 0.5", "SphereDirectionAngle: 55", "DistanceTolerance: 0.0625",
         "RansacIterations: 321", "RandomSeed: 7", "RefineFits: Off",
         "AdaptiveTolerance: Off" })
  {
    EXPECT_NE(os.str().find(name), std::string::npos) << name << " not in\n" << os.str();
  }
}

TEST(Segment, RefusesOtherCellTypes)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
                         { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } },
    { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } } });
  vtkNew<vtkFEMorphSegment> segment;
  vtkNew<MessageRecorder> messages;
  EXPECT_EQ(RunSegment(segment, grid, messages), 0);
  ASSERT_EQ(messages->Errors.size(), 1u) << messages->AllErrors();
  const std::string& error = messages->Errors[0];
  EXPECT_NE(error.find("FEMorph Segment: the input has 1 VTK_HEXAHEDRON cell; this filter reads tetrahedra only"), std::string::npos) << error;
  EXPECT_NE(error.find("1 VTK_HEXAHEDRON cell"), std::string::npos) << error;
  EXPECT_NE(error.find("Tetrahedralize"), std::string::npos) << error;
  ExpectEmptyOutputs(segment);
}

// Two tets sharing one edge (or one vertex) only: the boundary is not a
// manifold surface. TetMesh::build refuses; its message reaches the user.
TEST(Segment, RefusesNonManifoldBoundary)
{
  struct Case
  {
    const char* Name;
    std::vector<std::array<double, 3>> Points;
    std::vector<std::pair<int, std::vector<vtkIdType>>> Cells;
    std::vector<const char*> Expected;
  };
  const std::vector<Case> cases = {
    { "edge",
      { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0, -1, 0 }, { 0, 0, -1 } },
      { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 0, 1, 4, 5 } } },
      { "FEMorph Segment", "not manifold", "touching at a vertex or an edge" } },
    { "vertex",
      { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { -1, 0, 0 }, { 0, -1, 0 },
        { 0, 0, -1 } },
      { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 0, 4, 6, 5 } } },
      { "FEMorph Segment", "not manifold", "touching at a vertex or an edge" } },
  };
  for (const Case& c : cases)
  {
    auto grid = MakeGrid(c.Points, c.Cells);
    vtkNew<vtkFEMorphSegment> segment;
    vtkNew<MessageRecorder> messages;
    EXPECT_EQ(RunSegment(segment, grid, messages), 0) << c.Name;
    ASSERT_EQ(messages->Errors.size(), 1u) << c.Name << ": " << messages->AllErrors();
    for (const char* word : c.Expected)
    {
      EXPECT_NE(messages->Errors[0].find(word), std::string::npos)
        << c.Name << ": " << messages->Errors[0];
    }
    ExpectEmptyOutputs(segment);
  }
}

TEST(Segment, RefusesMixedOrientation)
{
  // femorph_test::MakeTwoTets with the second tet's order reversed.
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 1, 2, 3 } } });
  vtkNew<vtkFEMorphSegment> segment;
  vtkNew<MessageRecorder> messages;
  EXPECT_EQ(RunSegment(segment, grid, messages), 0);
  ASSERT_EQ(messages->Errors.size(), 1u) << messages->AllErrors();
  EXPECT_NE(messages->Errors[0].find("mixed orientation"), std::string::npos)
    << messages->Errors[0];
}

TEST(Segment, RefusesBadProperties)
{
  auto grid = femorph_test::MakeTwoTets();
  {
    vtkNew<vtkFEMorphSegment> segment;
    vtkNew<MessageRecorder> messages;
    segment->SetSharpAngle(std::numeric_limits<double>::quiet_NaN());
    EXPECT_EQ(RunSegment(segment, grid, messages), 0);
    EXPECT_NE(messages->AllErrors().find("SharpAngle must be a number in [0, 180]"), std::string::npos)
      << messages->AllErrors();
  }
  {
    vtkNew<vtkFEMorphSegment> segment;
    vtkNew<MessageRecorder> messages;
    segment->SetDistanceTolerance(0);
    EXPECT_EQ(RunSegment(segment, grid, messages), 0);
    EXPECT_NE(messages->AllErrors().find("DistanceTolerance must be in (0, 1]"), std::string::npos)
      << messages->AllErrors();
    ExpectEmptyOutputs(segment);
  }
}

// The progress callback reaches the core: aborting at its first step (by
// the step's name) stops the run with empty outputs and no error.
TEST(Segment, ProgressAndAbortReachTheCore)
{
  auto cube = MakeCube(2);
  vtkNew<vtkFEMorphSegment> segment;
  vtkNew<MessageRecorder> messages;
  AbortAt abortAt{ "sharp edges", {}, {} };
  vtkNew<vtkCallbackCommand> command;
  ObserveAndAbortAt(segment, &abortAt, command);
  EXPECT_EQ(RunSegment(segment, cube, messages), 1);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  ExpectEmptyOutputs(segment);
  // The filter's steps in order (the executive adds events of its own, at 0
  // and 1, without a text); nothing after the abort.
  const auto& texts = abortAt.Texts;
  const auto converting = std::find(texts.begin(), texts.end(), "converting the mesh");
  const auto extracting = std::find(texts.begin(), texts.end(), "extracting the boundary surface");
  const auto sharp = std::find(texts.begin(), texts.end(), "sharp edges");
  ASSERT_TRUE(converting < extracting && extracting < sharp && sharp != texts.end())
    << "progress texts out of order";
  for (auto it = sharp; it != texts.end(); ++it)
  {
    EXPECT_TRUE(*it == "sharp edges" || it->empty()) << "after the abort: " << *it;
  }
  // The segmentation's 0 maps to 0.1 of the filter's progress.
  EXPECT_NEAR(abortAt.Values[sharp - texts.begin()], 0.1, 1e-12);
  for (std::size_t i = converting - texts.begin() + 1; i <= std::size_t(sharp - texts.begin()); ++i)
  {
    EXPECT_GE(abortAt.Values[i], abortAt.Values[i - 1]);
  }
  EXPECT_EQ(segment->GetProgressText(), nullptr);
}

// A flat tet: its collinear face is a degenerate boundary triangle. Both are
// reported before the segmentation starts (aborted here: the run itself is
// the pipeline's test below).
TEST(Segment, WarnsAboutZeroVolumeAndDegenerateTriangles)
{
  auto flat = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 }, { 0, 1, 0 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } } });
  vtkNew<vtkFEMorphSegment> segment;
  vtkNew<MessageRecorder> messages;
  EXPECT_EQ(RunSegment(segment, flat, messages), 1);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  const std::string warnings = messages->AllWarnings();
  EXPECT_NE(warnings.find("1 tetrahedron has zero volume"), std::string::npos) << warnings;
  // Issue 29: Improve accepts such a mesh and repairs it (it is built with
  // allow_degenerate); only Deform refuses it. The message must not say
  // that Improve refuses.
  EXPECT_NE(warnings.find("FEMorph Improve accepts the mesh and removes them"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("FEMorph Deform refuses"), std::string::npos) << warnings;
  EXPECT_EQ(warnings.find("Improve will refuse"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("1 boundary triangle is degenerate"), std::string::npos) << warnings;
}

TEST(Segment, WarnsAboutUnusedPoints)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 5, 5, 5 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } } });
  vtkNew<vtkFEMorphSegment> segment;
  vtkNew<MessageRecorder> messages;
  AbortAt abortAt{ "sharp edges", {}, {} };
  vtkNew<vtkCallbackCommand> command;
  ObserveAndAbortAt(segment, &abortAt, command);
  EXPECT_EQ(RunSegment(segment, grid, messages), 1);
  EXPECT_NE(messages->AllWarnings().find("1 point is not used by any tetrahedron"),
    std::string::npos)
    << messages->AllWarnings();
}

// Issue 29: an unmerged seam (two cubes meshed apart, their common face's
// four points written twice) became many regions with no warning. The
// warning names the count of coincident boundary points and what to do.
TEST(Segment, WarnsAboutCoincidentBoundaryPoints)
{
  std::vector<std::array<double, 3>> points;
  std::vector<std::pair<int, std::vector<vtkIdType>>> cells;
  // Kuhn's six tets of the unit cube, positively oriented.
  const int kuhn[6][4] = { { 0, 1, 3, 7 }, { 0, 1, 7, 5 }, { 0, 2, 7, 3 }, { 0, 2, 6, 7 },
    { 0, 4, 5, 7 }, { 0, 4, 7, 6 } };
  for (int cube = 0; cube < 2; ++cube)
  {
    const vtkIdType first = static_cast<vtkIdType>(points.size());
    for (int k = 0; k < 8; ++k)
    {
      points.push_back({ double(cube + (k & 1)), double((k >> 1) & 1), double((k >> 2) & 1) });
    }
    for (const auto& t : kuhn)
    {
      cells.push_back({ VTK_TETRA, { first + t[0], first + t[1], first + t[2], first + t[3] } });
    }
  }
  vtkNew<vtkFEMorphSegment> segment;
  vtkNew<MessageRecorder> messages;
  EXPECT_EQ(RunSegment(segment, MakeGrid(points, cells), messages), 1);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  const std::string warnings = messages->AllWarnings();
  EXPECT_NE(warnings.find("8 boundary points lie on top of other boundary points"), std::string::npos)
    << warnings;
  EXPECT_NE(warnings.find("Merge coincident points first"), std::string::npos) << warnings;
}

// The ParaView property defaults and ranges (Plugin/FEMorphFilters.xml) equal
// the C++ defaults and clamps; the advanced ones are marked; the output
// ports are named.
TEST(Segment, XmlDefaultsEqualCxxDefaults)
{
  vtkSmartPointer<vtkXMLDataElement> root;
  vtkXMLDataElement* proxy = femorph_test::FindFilterProxy(
    FEMORPH_PLUGIN_XML, "vtkFEMorphSegment", "FEMorphSegment", "FEMorph Segment", root);
  ASSERT_NE(proxy, nullptr);

  vtkNew<vtkFEMorphSegment> d;
  const std::map<std::string, femorph_test::XmlProperty> expected = {
    { "SetSharpAngle",
      { d->GetSharpAngle(), d->GetSharpAngleMinValue(), d->GetSharpAngleMaxValue(), false } },
    { "SetCylinderAngleTolerance",
      { d->GetCylinderAngleTolerance(), d->GetCylinderAngleToleranceMinValue(),
        d->GetCylinderAngleToleranceMaxValue(), false } },
    { "SetConeAngleTolerance",
      { d->GetConeAngleTolerance(), d->GetConeAngleToleranceMinValue(),
        d->GetConeAngleToleranceMaxValue(), false } },
    { "SetSphereDirectionAngle",
      { d->GetSphereDirectionAngle(), d->GetSphereDirectionAngleMinValue(),
        d->GetSphereDirectionAngleMaxValue(), true } },
    { "SetDistanceTolerance",
      { d->GetDistanceTolerance(), d->GetDistanceToleranceMinValue(),
        d->GetDistanceToleranceMaxValue(), false } },
    { "SetRansacIterations",
      { double(d->GetRansacIterations()), double(d->GetRansacIterationsMinValue()),
        double(d->GetRansacIterationsMaxValue()), true, /*Entry=*/true } },
    { "SetRandomSeed",
      { double(d->GetRandomSeed()), double(d->GetRandomSeedMinValue()),
        double(d->GetRandomSeedMaxValue()), true, /*Entry=*/true } },
    { "SetRefineFits", { double(d->GetRefineFits()), 0, 1, true } },
    { "SetAdaptiveTolerance", { double(d->GetAdaptiveTolerance()), 0, 1, true } },
  };
  femorph_test::CheckFilterProperties(proxy, expected);

  // Three named output ports.
  const char* ports[] = { "Mesh", "Surface", "Regions" };
  for (int p = 0; p < 3; ++p)
  {
    vtkXMLDataElement* port = proxy->FindNestedElementWithNameAndAttribute(
      "OutputPort", "index", std::to_string(p).c_str());
    ASSERT_NE(port, nullptr) << "output port " << p;
    EXPECT_STREQ(port->GetAttribute("name"), ports[p]);
  }

  // The help names the outputs' arrays and the table's columns.
  vtkXMLDataElement* doc = proxy->FindNestedElementWithName("Documentation");
  ASSERT_NE(doc, nullptr);
  const std::string help = doc->GetCharacterData() ? doc->GetCharacterData() : "";
  for (const char* name : { "FaceRegion", "VertexClass", "RegionType", "RegionParameters",
         "RegionConvexity", "CurveType", "CurveParameters", "CurveVertices", "CurveOffsets",
         "RegionId", "CurveId", "MeshPointId", "TypeName", "Radius", "MajorRadius", "MinorRadius",
         "HalfAngle", "Axis", "Center", "Apex", "Normal", "Point", "Area", "Convexity",
         "TriangleCount", "FitResidual", "Neighbors" })
  {
    EXPECT_NE(help.find(name), std::string::npos) << "the help does not name " << name;
  }
}

// A box has no curvature anywhere: six planes, twelve straight curves.
TEST(SegmentPipeline, BoxIsSixPlanes)
{
  auto cube = MakeCube(3);
  vtkNew<vtkFEMorphSegment> segment;
  vtkNew<MessageRecorder> messages;
  EXPECT_EQ(RunSegment(segment, cube, messages), 1);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_TRUE(messages->Warnings.empty()) << messages->AllWarnings();
  EXPECT_EQ(cube->GetCellData()->GetArray("FaceRegion"), nullptr) << "the input was modified";
  EXPECT_EQ(cube->GetFieldData()->GetNumberOfArrays(), 0) << "the input was modified";

  vtkTable* table = segment->GetRegionTableOutput();
  ASSERT_EQ(table->GetNumberOfRows(), 6);
  auto* typeName = vtkStringArray::SafeDownCast(table->GetColumnByName("TypeName"));
  auto* area = vtkDataArray::SafeDownCast(table->GetColumnByName("Area"));
  auto* normal = vtkDataArray::SafeDownCast(table->GetColumnByName("Normal"));
  auto* neighbors = vtkStringArray::SafeDownCast(table->GetColumnByName("Neighbors"));
  ASSERT_TRUE(typeName && area && normal && neighbors);
  std::set<int> axes;
  for (vtkIdType r = 0; r < 6; ++r)
  {
    EXPECT_EQ(typeName->GetValue(r), "plane");
    EXPECT_NEAR(area->GetComponent(r, 0), 1.0, 1e-9);
    for (int k = 0; k < 3; ++k)
    {
      if (std::fabs(normal->GetComponent(r, k)) > 0.999)
      {
        axes.insert(k);
      }
    }
    EXPECT_EQ(std::count(neighbors->GetValue(r).begin(), neighbors->GetValue(r).end(), ' '), 3)
      << "region " << r << " neighbours: " << neighbors->GetValue(r);
  }
  EXPECT_EQ(axes.size(), 3u);

  vtkUnstructuredGrid* mesh = segment->GetMeshOutput();
  ASSERT_NE(mesh->GetCellData()->GetArray("FaceRegion"), nullptr);
  vtkDataArray* vertexClass = mesh->GetPointData()->GetArray("VertexClass");
  ASSERT_NE(vertexClass, nullptr);
  int corners = 0;
  for (vtkIdType i = 0; i < vertexClass->GetNumberOfTuples(); ++i)
  {
    corners += vertexClass->GetComponent(i, 0) == 3;
  }
  EXPECT_EQ(corners, 8);
  vtkDataArray* curveType = mesh->GetFieldData()->GetArray("CurveType");
  ASSERT_NE(curveType, nullptr);
  EXPECT_EQ(curveType->GetNumberOfTuples(), 12);
  for (vtkIdType c = 0; c < curveType->GetNumberOfTuples(); ++c)
  {
    EXPECT_EQ(curveType->GetComponent(c, 0), static_cast<int>(femorph::CurveType::Line));
  }
  vtkPolyData* surface = segment->GetSurfaceOutput();
  EXPECT_EQ(surface->GetNumberOfPolys(), 6 * 2 * 9);
  EXPECT_EQ(surface->GetNumberOfLines(), 12);
}

// A flat tet (a degenerate boundary triangle) runs to the end: a result or
// a message, no crash.
TEST(SegmentPipeline, FlatTetDoesNotCrash)
{
  auto flat = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 }, { 0, 1, 0 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } } });
  vtkNew<vtkFEMorphSegment> segment;
  vtkNew<MessageRecorder> messages;
  const int status = RunSegment(segment, flat, messages);
  if (status == 1)
  {
    EXPECT_EQ(segment->GetSurfaceOutput()->GetNumberOfPolys(), 4);
    EXPECT_GE(segment->GetRegionTableOutput()->GetNumberOfRows(), 1);
  }
  else
  {
    ASSERT_FALSE(messages->Errors.empty());
  }
}


