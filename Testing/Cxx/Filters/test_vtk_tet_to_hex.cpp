// vtkFEMorphTetToHex: a block of boxes decomposed into tets comes back as
// VTK_HEXAHEDRON cells of positive volume; a wedge and a pyramid come back as
// VTK_WEDGE and VTK_PYRAMID; the arrays and field data; bad input refused
// with messages; the input untouched; XML defaults equal the C++ ones.
#include "filters_test_utils.h"
#include "vtkFEMorphTetToHex.h"

#include "vtkCallbackCommand.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkXMLDataElement.h"
#include "vtkXMLUtilities.h"

#include "hex/hex_decomposition_types.h"
#include "hex/tet_to_hex.h"
#include "quality/tet_quality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using femorph_test::MakeGrid;
using femorph_test::Snapshot;
using femorph_test::MessageRecorder;

namespace
{
using CellList = std::vector<std::pair<int, std::vector<vtkIdType>>>;

// nx x ny x nz unit boxes split by Type C+ (thesis Fig. 4.5), with a cell
// array "TetId" (the tet's id) and a point array "Height" (z).
vtkSmartPointer<vtkUnstructuredGrid> MakeBlock(int nx, int ny, int nz)
{
  std::vector<std::array<double, 3>> points;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        points.push_back({ double(i), double(j), double(k) });
  auto id = [&](int i, int j, int k) { return vtkIdType((k * (ny + 1) + j) * (nx + 1) + i); };
  const femorph::HexDecomposition& d =
    femorph::hex_decomposition(femorph::HexDecompositionType::C, false);
  CellList cells;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
      {
        const vtkIdType h[8] = { id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k),
          id(i, j + 1, k), id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1),
          id(i, j + 1, k + 1) };
        for (const femorph::LocalTet& t : d.tets)
        {
          cells.push_back({ VTK_TETRA, { h[t[0]], h[t[1]], h[t[2]], h[t[3]] } });
        }
      }
  auto grid = MakeGrid(points, cells);
  vtkNew<vtkIntArray> tetId;
  tetId->SetName("TetId");
  tetId->SetNumberOfTuples(grid->GetNumberOfCells());
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    tetId->SetValue(c, static_cast<int>(c));
  }
  grid->GetCellData()->AddArray(tetId);
  vtkNew<vtkDoubleArray> height;
  height->SetName("Height");
  height->SetNumberOfTuples(grid->GetNumberOfPoints());
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    height->SetValue(p, grid->GetPoint(p)[2]);
  }
  grid->GetPointData()->AddArray(height);
  vtkNew<vtkDoubleArray> note;
  note->SetName("InputNote");
  note->InsertNextValue(42);
  grid->GetFieldData()->AddArray(note);
  return grid;
}

int RunFilter(vtkFEMorphTetToHex* filter, vtkDataObject* input, MessageRecorder* messages)
{
  messages->Observe(filter);
  filter->SetInputData(input);
  return filter->GetExecutive()->Update();
}

femorph::CellKind KindOf(int type)
{
  switch (type)
  {
    case VTK_HEXAHEDRON: return femorph::CellKind::Hexahedron;
    case VTK_WEDGE: return femorph::CellKind::Wedge;
    case VTK_PYRAMID: return femorph::CellKind::Pyramid;
    default: return femorph::CellKind::Tetra;
  }
}

// Every cell of positive volume in its VTK node order: all corner Jacobians
// (Eq. 4.2) positive, and the volume of a split by the tables positive.
void ExpectPositiveCells(vtkUnstructuredGrid* out)
{
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    vtkIdType npts = 0;
    const vtkIdType* pts = nullptr;
    out->GetCellPoints(c, npts, pts);
    const femorph::CellKind kind = KindOf(out->GetCellType(c));
    ASSERT_EQ(npts, femorph::cell_node_count(kind)) << "cell " << c;
    femorph::Vec3 x[8];
    for (vtkIdType k = 0; k < npts; ++k)
    {
      out->GetPoint(pts[k], x[k].data());
    }
    double corners[8];
    const int n = femorph::scaled_jacobian_corners(kind, x, corners);
    for (int k = 0; k < n; ++k)
    {
      EXPECT_GT(corners[k], 0) << "cell " << c << " corner " << k;
    }
  }
}

const vtkDataArray* FieldArray(vtkUnstructuredGrid* out, const char* name)
{
  return out->GetFieldData()->GetArray(name);
}

double FieldValue(vtkUnstructuredGrid* out, const char* name, int component = 0)
{
  vtkDataArray* a = out->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  return a ? a->GetComponent(0, component) : std::numeric_limits<double>::quiet_NaN();
}

} // namespace

TEST(TetToHex, DefaultsAreTheCoreDefaultsAndClamped)
{
  const femorph::TetToHexParams core;
  vtkNew<vtkFEMorphTetToHex> f;
  EXPECT_EQ(f->GetQuadAngle(), core.quad_angle_deg);
  EXPECT_EQ(f->GetMinScaledJacobian(), core.min_scaled_jacobian);
  EXPECT_EQ(f->GetHexahedra() != 0, core.hexahedra);
  EXPECT_EQ(f->GetPrisms() != 0, core.prisms);
  EXPECT_EQ(f->GetPyramids() != 0, core.pyramids);
  EXPECT_EQ(f->GetRefuseNonConformal() != 0, core.refuse_nonconformal);
  f->SetQuadAngle(200);
  EXPECT_EQ(f->GetQuadAngle(), 180);
  f->SetMinScaledJacobian(-3);
  EXPECT_EQ(f->GetMinScaledJacobian(), -1);

  f->SetQuadAngle(12.5);
  f->PyramidsOff();
  f->RefuseNonConformalOn();
  std::ostringstream os;
  f->PrintSelf(os, vtkIndent());
  for (const char* text : { "QuadAngle: 12.5", "MinScaledJacobian: -1", "Hexahedra: On",
         "Prisms: On", "Pyramids: Off", "RefuseNonConformal: On" })
  {
    EXPECT_NE(os.str().find(text), std::string::npos) << text << " not in\n" << os.str();
  }
}

// Thesis Fig. 4.13's block size (60 boxes): 60 hexahedra, the arrays and the
// field data of Table 4.3; point data passed, cell data from the first
// source tet; progress reported; the input untouched.
TEST(TetToHex, BlockBecomesHexahedra)
{
  auto input = MakeBlock(10, 2, 3);
  ASSERT_EQ(input->GetNumberOfPoints(), 132);
  ASSERT_EQ(input->GetNumberOfCells(), 360);
  const Snapshot before(input);
  vtkNew<vtkFEMorphTetToHex> f;
  vtkNew<MessageRecorder> messages;
  std::vector<double> progress;
  vtkNew<vtkCallbackCommand> command;
  command->SetClientData(&progress);
  command->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    static_cast<std::vector<double>*>(client)->push_back(*static_cast<double*>(call));
  });
  f->AddObserver(vtkCommand::ProgressEvent, command);
  ASSERT_EQ(RunFilter(f, input, messages), 1);
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_TRUE(messages->Warnings.empty()) << messages->AllWarnings();
  EXPECT_TRUE(Snapshot(input) == before) << "the input was modified";

  vtkUnstructuredGrid* out = f->GetOutput();
  ASSERT_EQ(out->GetNumberOfCells(), 60);
  EXPECT_EQ(out->GetPoints(), input->GetPoints());
  for (vtkIdType c = 0; c < 60; ++c)
  {
    EXPECT_EQ(out->GetCellType(c), VTK_HEXAHEDRON);
  }
  ExpectPositiveCells(out);

  vtkDataArray* sj = out->GetCellData()->GetArray("ScaledJacobian");
  vtkDataArray* sources = out->GetCellData()->GetArray("SourceTets");
  vtkDataArray* tetId = out->GetCellData()->GetArray("TetId");
  ASSERT_NE(sj, nullptr);
  ASSERT_NE(sources, nullptr);
  ASSERT_NE(tetId, nullptr);
  EXPECT_EQ(out->GetCellData()->GetScalars(), sj);
  for (vtkIdType c = 0; c < 60; ++c)
  {
    EXPECT_NEAR(sj->GetTuple1(c), 1.0, 1e-12);
    EXPECT_EQ(sources->GetTuple1(c), 6);
    // Hexahedron c is box c: its first (smallest) source tet is 6 c.
    EXPECT_EQ(tetId->GetTuple1(c), 6 * c);
  }
  EXPECT_EQ(out->GetPointData()->GetArray("Height"), input->GetPointData()->GetArray("Height"));

  EXPECT_EQ(FieldValue(out, "HexCount"), 60);
  EXPECT_EQ(FieldValue(out, "PrismCount"), 0);
  EXPECT_EQ(FieldValue(out, "PyramidCount"), 0);
  EXPECT_EQ(FieldValue(out, "TetCount"), 0);
  EXPECT_DOUBLE_EQ(FieldValue(out, "HexCountRatio"), 1.0);
  EXPECT_NEAR(FieldValue(out, "HexVolume"), 60.0, 1e-9);
  EXPECT_NEAR(FieldValue(out, "HexVolumeRatio"), 1.0, 1e-12);
  EXPECT_EQ(FieldValue(out, "TetVolumeRatio"), 0.0);
  EXPECT_NEAR(FieldValue(out, "TotalVolume"), 60.0, 1e-9);
  EXPECT_GE(FieldValue(out, "CandidateCounts", 0), 60);
  EXPECT_GE(FieldValue(out, "AdmissibleCandidateCounts", 0), 60);
  EXPECT_EQ(FieldArray(out, "CandidateCounts")->GetNumberOfComponents(), 3);
  EXPECT_EQ(FieldValue(out, "NonConformalInterfaces"), 0);
  EXPECT_EQ(FieldValue(out, "DissolvedNonConformal"), 0);
  ASSERT_NE(FieldArray(out, "TetToHexTimes"), nullptr);
  EXPECT_EQ(FieldArray(out, "TetToHexTimes")->GetNumberOfComponents(), 4);
  EXPECT_GE(FieldValue(out, "TetToHexTimes", 3), 0.0);
  EXPECT_EQ(FieldValue(out, "InputNote"), 42);

  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), 1.0);
  EXPECT_EQ(f->GetProgressText(), nullptr);
}

// A wedge split into 3 tets and a pyramid split into 2, side by side with a
// lone tet: VTK_WEDGE, VTK_PYRAMID, VTK_TETRA in this order, positive.
TEST(TetToHex, WedgePyramidAndTet)
{
  const std::vector<std::array<double, 3>> points = {
    // wedge 0-5
    { 0, 0, 0 }, { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 1 }, { 1, 0, 1 },
    // pyramid 6-10
    { 3, 0, 0 }, { 4, 0, 0 }, { 4, 1, 0 }, { 3, 1, 0 }, { 3.5, 0.5, 1 },
    // tet 11-14
    { 6, 0, 0 }, { 7, 0, 0 }, { 6, 1, 0 }, { 6, 0, 1 } };
  CellList cells;
  std::array<femorph::LocalTet, 3> wedge;
  ASSERT_TRUE(femorph::wedge_decomposition(0, wedge) || femorph::wedge_decomposition(1, wedge));
  for (const auto& t : wedge)
  {
    cells.push_back({ VTK_TETRA, { t[0], t[1], t[2], t[3] } });
  }
  for (const auto& t : femorph::pyramid_decomposition(1))
  {
    cells.push_back({ VTK_TETRA, { 6 + t[0], 6 + t[1], 6 + t[2], 6 + t[3] } });
  }
  cells.push_back({ VTK_TETRA, { 11, 12, 13, 14 } });
  auto input = MakeGrid(points, cells);
  vtkNew<vtkFEMorphTetToHex> f;
  vtkNew<MessageRecorder> messages;
  ASSERT_EQ(RunFilter(f, input, messages), 1) << messages->AllErrors();
  vtkUnstructuredGrid* out = f->GetOutput();
  ASSERT_EQ(out->GetNumberOfCells(), 3);
  EXPECT_EQ(out->GetCellType(0), VTK_WEDGE);
  EXPECT_EQ(out->GetCellType(1), VTK_PYRAMID);
  EXPECT_EQ(out->GetCellType(2), VTK_TETRA);
  ExpectPositiveCells(out);
  vtkDataArray* sources = out->GetCellData()->GetArray("SourceTets");
  EXPECT_EQ(sources->GetTuple1(0), 3);
  EXPECT_EQ(sources->GetTuple1(1), 2);
  EXPECT_EQ(sources->GetTuple1(2), 1);
  EXPECT_EQ(FieldValue(out, "PrismCount"), 1);
  EXPECT_EQ(FieldValue(out, "PyramidCount"), 1);
  EXPECT_EQ(FieldValue(out, "TetCount"), 1);
  EXPECT_NEAR(FieldValue(out, "PrismVolume"), 0.5, 1e-12);
  EXPECT_NEAR(FieldValue(out, "PyramidVolume"), 1.0 / 3, 1e-12);
  EXPECT_NEAR(FieldValue(out, "TetVolumeRatio"), (1.0 / 6) / (0.5 + 1.0 / 3 + 1.0 / 6), 1e-12);

  // Prisms and pyramids off: the tets stay.
  f->PrismsOff();
  f->PyramidsOff();
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 6);
  EXPECT_EQ(FieldValue(f->GetOutput(), "TetCount"), 6);
}

TEST(TetToHex, RefusesBadInput)
{
  struct Case
  {
    const char* Name;
    vtkSmartPointer<vtkUnstructuredGrid> Grid;
    std::vector<const char*> Expected;
  };
  auto nan = femorph_test::MakeTwoTets();
  nan->GetPoints()->SetPoint(4, std::numeric_limits<double>::quiet_NaN(), 0, 0);
  const std::vector<Case> cases = {
    { "hexahedron",
      MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 },
                 { 1, 1, 1 }, { 0, 1, 1 }, { 2, 0, 0 } },
        { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } }, { VTK_TETRA, { 1, 8, 2, 5 } },
          { VTK_TRIANGLE, { 0, 1, 2 } } }),
      { "FEMorph Tet To Hex: the input has", "reads tetrahedra only", "1 VTK_TRIANGLE", "1 VTK_HEXAHEDRON",
        "Tetrahedralize" } },
    { "NaN", nan, { "FEMorph Tet To Hex", "1 point of the input has NaN or infinite coordinates" } },
    { "inverted",
      MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
        { { VTK_TETRA, { 0, 2, 1, 3 } } }),
      { "FEMorph Tet To Hex", "1 tetrahedron is inverted or flat (the first is 0)",
        "Mesh Quality" } },
    { "non-manifold",
      MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 }, { 2, 2, 2 } },
        { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 1, 3, 2 } },
          { VTK_TETRA, { 5, 1, 3, 2 } } }),
      { "FEMorph Tet To Hex", "shared by more than two tetrahedra" } },
  };
  for (const Case& c : cases)
  {
    const Snapshot before(c.Grid);
    vtkNew<vtkFEMorphTetToHex> f;
    vtkNew<MessageRecorder> messages;
    EXPECT_EQ(RunFilter(f, c.Grid, messages), 0) << c.Name;
    ASSERT_EQ(messages->Errors.size(), 1u) << c.Name << ": " << messages->AllErrors();
    for (const char* word : c.Expected)
    {
      EXPECT_NE(messages->Errors[0].find(word), std::string::npos)
        << c.Name << ": " << messages->Errors[0];
    }
    EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 0) << c.Name;
    EXPECT_TRUE(Snapshot(c.Grid) == before) << c.Name << ": the input was modified";
  }

  vtkNew<vtkFEMorphTetToHex> f;
  vtkNew<MessageRecorder> messages;
  f->SetQuadAngle(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(RunFilter(f, femorph_test::MakeTwoTets(), messages), 0);
  EXPECT_NE(messages->AllErrors().find("QuadAngle must be a number in [0, 180]"), std::string::npos)
    << messages->AllErrors();
}

// Refusing non-conformal interfaces through the filter: a box next to a
// distorted one, prisms and pyramids off.
TEST(TetToHex, RefuseNonConformal)
{
  auto input = MakeBlock(2, 1, 1);
  input->GetPoints()->SetPoint(11, 2.4, 1.3, 1.5);  // node (2, 1, 1), of the right box only
  vtkNew<vtkFEMorphTetToHex> f;
  vtkNew<MessageRecorder> messages;
  f->PrismsOff();
  f->PyramidsOff();
  ASSERT_EQ(RunFilter(f, input, messages), 1) << messages->AllErrors();
  EXPECT_EQ(FieldValue(f->GetOutput(), "HexCount"), 1);
  EXPECT_EQ(FieldValue(f->GetOutput(), "NonConformalInterfaces"), 1);
  f->RefuseNonConformalOn();
  f->Update();
  EXPECT_EQ(FieldValue(f->GetOutput(), "HexCount"), 0);
  EXPECT_EQ(FieldValue(f->GetOutput(), "NonConformalInterfaces"), 0);
  EXPECT_EQ(FieldValue(f->GetOutput(), "DissolvedNonConformal"), 1);
}

// The ParaView property defaults and ranges (Plugin/FEMorphFilters.xml)
// equal the C++ defaults and clamps.
TEST(TetToHex, XmlDefaultsEqualCxxDefaults)
{
  vtkSmartPointer<vtkXMLDataElement> root;
  vtkXMLDataElement* proxy = femorph_test::FindFilterProxy(
    FEMORPH_PLUGIN_XML, "vtkFEMorphTetToHex", "FEMorphTetToHex", "FEMorph Tet To Hex", root);
  ASSERT_NE(proxy, nullptr);

  vtkNew<vtkFEMorphTetToHex> d;
  const std::map<std::string, femorph_test::XmlProperty> expected = {
    { "SetQuadAngle", { d->GetQuadAngle(), d->GetQuadAngleMinValue(), d->GetQuadAngleMaxValue() } },
    { "SetMinScaledJacobian",
      { d->GetMinScaledJacobian(), d->GetMinScaledJacobianMinValue(),
        d->GetMinScaledJacobianMaxValue() } },
    { "SetHexahedra", { double(d->GetHexahedra()), 0, 1 } },
    { "SetPrisms", { double(d->GetPrisms()), 0, 1 } },
    { "SetPyramids", { double(d->GetPyramids()), 0, 1 } },
    { "SetRefuseNonConformal", { double(d->GetRefuseNonConformal()), 0, 1 } },
  };
  femorph_test::CheckFilterProperties(proxy, expected);

  // The help names the output's arrays.
  vtkXMLDataElement* doc = proxy->FindNestedElementWithName("Documentation");
  ASSERT_NE(doc, nullptr);
  const std::string help = doc->GetCharacterData() ? doc->GetCharacterData() : "";
  for (const char* name : { "ScaledJacobian", "SourceTets", "HexCount", "PrismCount",
         "PyramidCount", "TetCount", "HexVolumeRatio", "TotalVolume", "CandidateCounts",
         "NonConformalInterfaces", "TetToHexTimes" })
  {
    EXPECT_NE(help.find(name), std::string::npos) << "the help does not name " << name;
  }
}
