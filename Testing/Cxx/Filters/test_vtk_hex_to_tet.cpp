// vtkFEMorphHexToTet: defaults equal the core's and the XML's; the arrays
// (input cell data copied to every child, point data passed, SourceCell,
// DecompositionType, Inverted); voxels; bad input refused with messages
// naming the problem; the input untouched; and the unstructured hex part
// Data/hex/hex_block.vtu split conformingly (checked by check_validity and a
// boundary volume computed here) and by every fixed type (conflicts counted
// exactly).
#include "filters_test_utils.h"
#include "vtkFEMorphHexToTet.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSignedCharArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkXMLDataElement.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtkXMLUtilities.h"

#include "hex/hex_to_tet.h"
#include "quality/check_validity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using femorph_test::MakeGrid;
using femorph_test::MessageRecorder;

namespace
{
// Runs the filter; returns the executive's status (1 success, 0 failure).
int RunFilter(vtkFEMorphHexToTet* filter, vtkDataObject* input, MessageRecorder* messages)
{
  messages->Observe(filter);
  filter->SetInputData(input);
  return filter->GetExecutive()->Update();
}

// Unit cube corners 0..7 (VTK hexahedron order), a second cube 8..11 to its
// right (x in [1, 2]), an apex 12 under the bottom, a point 13 left of x = 0.
std::vector<std::array<double, 3>> MixedPoints()
{
  return { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 },
    { 1, 1, 1 }, { 0, 1, 1 }, { 2, 0, 0 }, { 2, 1, 0 }, { 2, 0, 1 }, { 2, 1, 1 },
    { 0.5, 0.5, -1 }, { -1, 0, 0 } };
}

// A conforming mixed mesh: a hexahedron (cell 0); the cube to its right as
// two wedges split through the diagonal quad 1-9-11-5 (cells 1, 2); a
// pyramid under the hexahedron's bottom (3); a tet on a side triangle of the
// pyramid (4).
vtkSmartPointer<vtkUnstructuredGrid> MakeMixedGrid()
{
  return MakeGrid(MixedPoints(),
    { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } },
      // Bottom triangles turning about -z, away from the top ones.
      { VTK_WEDGE, { 1, 9, 8, 5, 11, 10 } }, { VTK_WEDGE, { 1, 2, 9, 5, 6, 11 } },
      // The base is the cube's bottom turned towards the apex below.
      { VTK_PYRAMID, { 0, 3, 2, 1, 12 } },
      // A tet on the pyramid's triangle (0, 3, 12), on the other side.
      { VTK_TETRA, { 0, 3, 12, 13 } } });
}

double Volume(const double a[3], const double b[3], const double c[3], const double d[3])
{
  double u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k)
  {
    u[k] = b[k] - a[k];
    v[k] = c[k] - a[k];
    w[k] = d[k] - a[k];
  }
  return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0])) /
    6.0;
}

// The output as core arrays, for check_validity.
void ToCore(vtkUnstructuredGrid* grid, std::vector<femorph::Vec3>& points,
  std::vector<femorph::Tet>& tets)
{
  points.resize(grid->GetNumberOfPoints());
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    grid->GetPoint(i, points[i].data());
  }
  tets.clear();
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(grid->GetCellType(c), VTK_TETRA);
    grid->GetCellPoints(c, ids);
    tets.push_back({ { static_cast<femorph::index_t>(ids->GetId(0)),
      static_cast<femorph::index_t>(ids->GetId(1)), static_cast<femorph::index_t>(ids->GetId(2)),
      static_cast<femorph::index_t>(ids->GetId(3)) } });
  }
}

double TotalVolume(vtkUnstructuredGrid* grid)
{
  double total = 0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    double p[4][3];
    for (int k = 0; k < 4; ++k)
    {
      grid->GetPoint(ids->GetId(k), p[k]);
    }
    total += Volume(p[0], p[1], p[2], p[3]);
  }
  return total;
}

vtkIdType FieldCount(vtkUnstructuredGrid* grid, const char* name)
{
  vtkDataArray* a = grid->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  return a ? static_cast<vtkIdType>(a->GetTuple1(0)) : -1;
}

// What a grid holds, to see that the filter leaves its input alone.
std::string Fingerprint(vtkUnstructuredGrid* grid)
{
  std::ostringstream os;
  os << grid->GetMTime() << " " << grid->GetNumberOfPoints() << " " << grid->GetNumberOfCells();
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    os << " " << grid->GetCellType(c) << ":";
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      os << ids->GetId(k) << ",";
    }
  }
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    double p[3];
    grid->GetPoint(i, p);
    os << " " << p[0] << "," << p[1] << "," << p[2];
  }
  for (vtkFieldData* fd : { static_cast<vtkFieldData*>(grid->GetPointData()),
         static_cast<vtkFieldData*>(grid->GetCellData()), grid->GetFieldData() })
  {
    os << "|";
    for (int a = 0; a < fd->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* array = fd->GetAbstractArray(a);
      os << array->GetName() << ":" << array->GetNumberOfTuples() << ":" << array->GetMTime()
         << ",";
    }
  }
  return os.str();
}

} // namespace

TEST(HexToTet, DefaultsAreTheCoreDefaultsAndClamped)
{
  const femorph::HexToTetParams core;
  vtkNew<vtkFEMorphHexToTet> filter;
  EXPECT_EQ(filter->GetConforming() != 0, core.conforming);
  EXPECT_EQ(filter->GetDecompositionType(), static_cast<int>(core.type));
  EXPECT_EQ(filter->GetMirrored() != 0, core.mirrored);
  EXPECT_EQ(filter->GetAllowInverted(), 0);
  // The thesis' default type (4.4): C+.
  EXPECT_EQ(filter->GetDecompositionType(), vtkFEMorphHexToTet::TYPE_C);
  EXPECT_EQ(filter->GetMirrored(), 0);
  filter->SetDecompositionType(9);
  EXPECT_EQ(filter->GetDecompositionType(), vtkFEMorphHexToTet::TYPE_F);
  filter->SetDecompositionType(-3);
  EXPECT_EQ(filter->GetDecompositionType(), vtkFEMorphHexToTet::TYPE_A);
  EXPECT_EQ(filter->GetDecompositionTypeMinValue(), 0);
  EXPECT_EQ(filter->GetDecompositionTypeMaxValue(), femorph::kHexDecompositionTypes - 1);

  filter->ConformingOff();
  filter->SetDecompositionType(vtkFEMorphHexToTet::TYPE_E);
  filter->MirroredOn();
  filter->AllowInvertedOn();
  std::ostringstream os;
  filter->PrintSelf(os, vtkIndent());
  for (const char* text :
    { "Conforming: Off", "DecompositionType: 4 (E)", "Mirrored: On", "AllowInverted: On" })
  {
    EXPECT_NE(os.str().find(text), std::string::npos) << text << " not in\n" << os.str();
  }
}

// Input cell data reaches every child, point data and field data pass, the
// points are the input's; SourceCell, DecompositionType and Inverted hold
// what they say.
TEST(HexToTet, ArraysAreCarried)
{
  auto input = MakeMixedGrid();
  vtkNew<vtkDoubleArray> pressure; // a point array
  pressure->SetName("Pressure");
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    pressure->InsertNextValue(0.5 * i);
  }
  input->GetPointData()->AddArray(pressure);
  vtkNew<vtkDoubleArray> stress; // a 3-component cell array
  stress->SetName("Stress");
  stress->SetNumberOfComponents(3);
  vtkNew<vtkIntArray> material;
  material->SetName("Material");
  vtkNew<vtkIdTypeArray> globalIds;
  globalIds->SetName("CellIds");
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    stress->InsertNextTuple3(c, 10.0 * c, -1.0 * c);
    material->InsertNextValue(static_cast<int>(100 + c));
    globalIds->InsertNextValue(1000 + c);
  }
  input->GetCellData()->AddArray(stress);
  input->GetCellData()->AddArray(material);
  input->GetCellData()->SetGlobalIds(globalIds);
  vtkNew<vtkIntArray> tag;
  tag->SetName("Tag");
  tag->InsertNextValue(7);
  input->GetFieldData()->AddArray(tag);
  const std::string before = Fingerprint(input);

  vtkNew<vtkFEMorphHexToTet> filter;
  vtkNew<MessageRecorder> messages;
  ASSERT_EQ(RunFilter(filter, input, messages), 1) << messages->AllErrors();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_TRUE(messages->Warnings.empty()) << messages->AllWarnings();
  EXPECT_EQ(Fingerprint(input), before) << "the input was modified";

  vtkUnstructuredGrid* out = filter->GetOutput();
  // The hex gives 5 or 6, the wedges 3 each, the pyramid 2, the tet 1.
  const vtkIdType n = out->GetNumberOfCells();
  EXPECT_TRUE(n == 5 + 6 + 2 + 1 || n == 6 + 6 + 2 + 1) << n;
  EXPECT_EQ(out->GetPoints(), input->GetPoints());
  EXPECT_EQ(out->GetPointData()->GetArray("Pressure"), pressure.GetPointer());
  EXPECT_NE(out->GetFieldData()->GetArray("Tag"), nullptr);
  EXPECT_EQ(FieldCount(out, "NonConformingFaceCount"), 0);
  EXPECT_EQ(FieldCount(out, "InvertedCellCount"), 0);

  auto* source = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("SourceCell"));
  auto* type = vtkSignedCharArray::SafeDownCast(out->GetCellData()->GetArray("DecompositionType"));
  auto* inverted = vtkUnsignedCharArray::SafeDownCast(out->GetCellData()->GetArray("Inverted"));
  auto* outStress = vtkDoubleArray::SafeDownCast(out->GetCellData()->GetArray("Stress"));
  auto* outMaterial = vtkIntArray::SafeDownCast(out->GetCellData()->GetArray("Material"));
  ASSERT_TRUE(source && type && inverted && outStress && outMaterial);
  // GlobalIds would repeat on the children: not copied.
  EXPECT_EQ(out->GetCellData()->GetGlobalIds(), nullptr);
  EXPECT_EQ(out->GetCellData()->GetArray("CellIds"), nullptr);

  std::map<vtkIdType, int> children;
  vtkNew<vtkIdList> tetIds, cellIds;
  for (vtkIdType t = 0; t < n; ++t)
  {
    const vtkIdType c = source->GetValue(t);
    ASSERT_GE(c, 0);
    ASSERT_LT(c, input->GetNumberOfCells());
    ++children[c];
    out->GetCellPoints(t, tetIds);
    input->GetCellPoints(c, cellIds);
    for (vtkIdType k = 0; k < 4; ++k)
    {
      EXPECT_GE(cellIds->IsId(tetIds->GetId(k)), 0) << "tet " << t << " is not in cell " << c;
    }
    double s[3];
    outStress->GetTypedTuple(t, s);
    EXPECT_EQ(s[0], c);
    EXPECT_EQ(s[1], 10.0 * c);
    EXPECT_EQ(s[2], -1.0 * c);
    EXPECT_EQ(outMaterial->GetValue(t), 100 + c);
    EXPECT_EQ(inverted->GetValue(t), 0);
    const bool hex = input->GetCellType(c) == VTK_HEXAHEDRON;
    if (hex)
    {
      EXPECT_GE(type->GetValue(t), 0);
      EXPECT_LT(type->GetValue(t), 6);
    }
    else
    {
      EXPECT_EQ(type->GetValue(t), -1);
    }
  }
  EXPECT_EQ(children[1], 3);
  EXPECT_EQ(children[2], 3);
  EXPECT_EQ(children[3], 2);
  EXPECT_EQ(children[4], 1);
  // The mixed grid is conforming, so is the result; volumes add up: the two
  // cubes, the pyramid (1/3) and the tet (0, 3, 12, 13).
  std::vector<femorph::Vec3> points;
  std::vector<femorph::Tet> tets;
  ToCore(out, points, tets);
  const femorph::ValidityReport check = femorph::check_validity(points, tets);
  EXPECT_TRUE(check.ok()) << check.summary();
  const auto p = MixedPoints();
  const double tet = Volume(p[0].data(), p[3].data(), p[12].data(), p[13].data());
  EXPECT_GT(tet, 0);
  EXPECT_NEAR(TotalVolume(out), 2.0 + 1.0 / 3.0 + tet, 1e-14);

  // Fixed type E- in the hex: DecompositionType 4 + 6.
  filter->ConformingOff();
  filter->SetDecompositionType(vtkFEMorphHexToTet::TYPE_E);
  filter->MirroredOn();
  ASSERT_EQ(filter->GetExecutive()->Update(), 1) << messages->AllErrors();
  out = filter->GetOutput();
  type = vtkSignedCharArray::SafeDownCast(out->GetCellData()->GetArray("DecompositionType"));
  source = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("SourceCell"));
  ASSERT_TRUE(type && source);
  for (vtkIdType t = 0; t < out->GetNumberOfCells(); ++t)
  {
    EXPECT_EQ(type->GetValue(t), source->GetValue(t) == 0 ? 10 : -1) << t;
  }
  EXPECT_EQ(Fingerprint(input), before) << "the input was modified";
}

// A voxel is taken in hexahedron order: a valid split of its box.
TEST(HexToTet, VoxelsAreHexahedra)
{
  auto grid = MakeGrid(
    { { 0, 0, 0 }, { 2, 0, 0 }, { 0, 1, 0 }, { 2, 1, 0 }, { 0, 0, 3 }, { 2, 0, 3 }, { 0, 1, 3 },
      { 2, 1, 3 } },
    { { VTK_VOXEL, { 0, 1, 2, 3, 4, 5, 6, 7 } } });
  for (int conforming = 0; conforming < 2; ++conforming)
  {
    vtkNew<vtkFEMorphHexToTet> filter;
    filter->SetConforming(conforming);
    vtkNew<MessageRecorder> messages;
    ASSERT_EQ(RunFilter(filter, grid, messages), 1) << messages->AllErrors();
    vtkUnstructuredGrid* out = filter->GetOutput();
    EXPECT_EQ(out->GetNumberOfCells(), 6);
    EXPECT_NEAR(TotalVolume(out), 6.0, 1e-14);
    std::vector<femorph::Vec3> points;
    std::vector<femorph::Tet> tets;
    ToCore(out, points, tets);
    const femorph::ValidityReport check = femorph::check_validity(points, tets);
    EXPECT_TRUE(check.ok()) << check.summary();
  }
}

TEST(HexToTet, RefusesOtherCellTypes)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
                         { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 }, { 0.5, 0, 0 }, { 0.5, 0.5, 0 },
                         { 0, 0.5, 0 }, { 0, 0, 0.5 }, { 0.5, 0, 0.5 }, { 0, 0.5, 0.5 } },
    { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } }, { VTK_TRIANGLE, { 0, 1, 2 } },
      { VTK_TRIANGLE, { 0, 2, 3 } },
      { VTK_QUADRATIC_TETRA, { 0, 1, 3, 4, 8, 9, 10, 11, 12, 13 } } });
  vtkNew<vtkFEMorphHexToTet> filter;
  vtkNew<MessageRecorder> messages;
  EXPECT_EQ(RunFilter(filter, grid, messages), 0);
  ASSERT_EQ(messages->Errors.size(), 1u) << messages->AllErrors();
  const std::string& error = messages->Errors[0];
  for (const char* words : { "FEMorph Hex To Tet: the input has",
         "this filter reads linear hexahedra, voxels, wedges, pyramids and tetrahedra only",
         "2 VTK_TRIANGLE and 1 VTK_QUADRATIC_TETRA cells" })
  {
    EXPECT_NE(error.find(words), std::string::npos) << error;
  }
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
}

TEST(HexToTet, RefusesNanAndCollapsedInput)
{
  struct Case
  {
    const char* Name;
    vtkSmartPointer<vtkUnstructuredGrid> Grid;
    const char* Expected;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Case> cases = {
    { "nan",
      MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 },
                 { 1, nan, 1 }, { 0, 1, 1 } },
        { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } } }),
      "FEMorph Hex To Tet: 1 point of the input has NaN or infinite coordinates" },
    { "collapsed",
      MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 },
                 { 1, 1, 1 } },
        { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 6 } } }),
      "FEMorph Hex To Tet: cell 0 (hexahedron) uses point 6 twice" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkFEMorphHexToTet> filter;
    vtkNew<MessageRecorder> messages;
    EXPECT_EQ(RunFilter(filter, c.Grid, messages), 0) << c.Name;
    ASSERT_EQ(messages->Errors.size(), 1u) << c.Name << ": " << messages->AllErrors();
    EXPECT_NE(messages->Errors[0].find(c.Expected), std::string::npos)
      << c.Name << ": " << messages->Errors[0];
    EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0) << c.Name;
  }
}

// An upside-down hexahedron next to a good one: an error and no output by
// default; with AllowInverted a warning and its tets marked.
TEST(HexToTet, InvertedCells)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
                         { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 }, { 2, 0, 0 }, { 2, 1, 0 },
                         { 2, 0, 1 }, { 2, 1, 1 } },
    { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } },
      { VTK_HEXAHEDRON, { 5, 10, 11, 6, 1, 8, 9, 2 } } });
  for (int conforming = 0; conforming < 2; ++conforming)
  {
    vtkNew<vtkFEMorphHexToTet> filter;
    filter->SetConforming(conforming);
    vtkNew<MessageRecorder> messages;
    EXPECT_EQ(RunFilter(filter, grid, messages), 0);
    ASSERT_EQ(messages->Errors.size(), 1u) << messages->AllErrors();
    const std::string& error = messages->Errors[0];
    for (const char* words : { "1 input cell gives tetrahedra of zero or negative volume (cells 1)",
           "turn on AllowInverted" })
    {
      EXPECT_NE(error.find(words), std::string::npos) << error;
    }
    EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);

    filter->AllowInvertedOn();
    messages->Errors.clear();
    EXPECT_EQ(filter->GetExecutive()->Update(), 1);
    EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
    EXPECT_NE(messages->AllWarnings().find("marked in the Inverted array"), std::string::npos)
      << messages->AllWarnings();
    vtkUnstructuredGrid* out = filter->GetOutput();
    EXPECT_EQ(FieldCount(out, "InvertedCellCount"), 1);
    auto* source = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("SourceCell"));
    auto* inverted = vtkUnsignedCharArray::SafeDownCast(out->GetCellData()->GetArray("Inverted"));
    ASSERT_TRUE(source && inverted);
    vtkNew<vtkIdList> ids;
    for (vtkIdType t = 0; t < out->GetNumberOfCells(); ++t)
    {
      out->GetCellPoints(t, ids);
      double p[4][3];
      for (int k = 0; k < 4; ++k)
      {
        out->GetPoint(ids->GetId(k), p[k]);
      }
      const bool negative = Volume(p[0], p[1], p[2], p[3]) <= 0;
      EXPECT_EQ(inverted->GetValue(t) == 1, negative) << t;
      EXPECT_EQ(negative, source->GetValue(t) == 1) << t;
    }
  }
}

// Fixed A+ on a row of cubes: each inner quad is split both ways (thesis
// Fig. 4.6(a)), counted and reported.
TEST(HexToTet, FixedTypeConflictsAreReported)
{
  std::vector<std::array<double, 3>> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 4; ++i)
        points.push_back({ double(i), double(j), double(k) });
  auto id = [](int i, int j, int k) { return vtkIdType(i + 4 * (j + 2 * k)); };
  std::vector<std::pair<int, std::vector<vtkIdType>>> cells;
  for (int i = 0; i < 3; ++i)
  {
    cells.push_back({ VTK_HEXAHEDRON,
      { id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 1, 0), id(i, 1, 0), id(i, 0, 1), id(i + 1, 0, 1),
        id(i + 1, 1, 1), id(i, 1, 1) } });
  }
  auto grid = MakeGrid(points, cells);
  vtkNew<vtkFEMorphHexToTet> filter;
  filter->ConformingOff();
  filter->SetDecompositionType(vtkFEMorphHexToTet::TYPE_A);
  vtkNew<MessageRecorder> messages;
  ASSERT_EQ(RunFilter(filter, grid, messages), 1) << messages->AllErrors();
  ASSERT_EQ(messages->Warnings.size(), 1u) << messages->AllWarnings();
  EXPECT_NE(messages->Warnings[0].find("2 quad faces are split along different diagonals on "
                                       "their two sides by the fixed type A+"),
    std::string::npos)
    << messages->Warnings[0];
  EXPECT_EQ(FieldCount(filter->GetOutput(), "NonConformingFaceCount"), 2);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 15);

  // C+ conforms on the same grid: no warning.
  filter->SetDecompositionType(vtkFEMorphHexToTet::TYPE_C);
  messages->Warnings.clear();
  ASSERT_EQ(filter->GetExecutive()->Update(), 1);
  EXPECT_TRUE(messages->Warnings.empty()) << messages->AllWarnings();
  EXPECT_EQ(FieldCount(filter->GetOutput(), "NonConformingFaceCount"), 0);
}

// The unstructured hex part: conforming by default; every fixed type's
// conflicts are what the output shows (each conflicting quad leaves four
// triangles of one tet each inside the mesh), and a type conforms exactly
// when it has none.
TEST(HexToTetPart, UnstructuredHexBlock)
{
  auto input = femorph_test::ReadPart("hex/hex_block.vtu");
  if (!input)
  {
    GTEST_SKIP() << "Data/hex/hex_block.vtu not found";
  }
  ASSERT_GT(input->GetNumberOfCells(), 1000);
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(input->GetCellType(c), VTK_HEXAHEDRON);
  }
  const std::string before = Fingerprint(input);

  // The boundary quads (faces of one hexahedron) and the volume they
  // enclose when split along their smallest-id diagonal.
  static const int faces[6][4] = { { 0, 4, 7, 3 }, { 1, 2, 6, 5 }, { 0, 1, 5, 4 },
    { 3, 7, 6, 2 }, { 0, 3, 2, 1 }, { 4, 5, 6, 7 } };
  std::map<std::array<vtkIdType, 4>, std::vector<std::array<vtkIdType, 4>>> quads;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    input->GetCellPoints(c, ids);
    for (const auto& f : faces)
    {
      std::array<vtkIdType, 4> g = { ids->GetId(f[0]), ids->GetId(f[1]), ids->GetId(f[2]),
        ids->GetId(f[3]) };
      auto key = g;
      std::sort(key.begin(), key.end());
      quads[key].push_back(g);
    }
  }
  std::size_t boundaryQuads = 0;
  double volume = 0;
  for (const auto& entry : quads)
  {
    ASSERT_LE(entry.second.size(), 2u);
    if (entry.second.size() != 1)
    {
      continue;
    }
    ++boundaryQuads;
    const auto& g = entry.second[0];
    const int d = static_cast<int>(std::min_element(g.begin(), g.end()) - g.begin()) & 1;
    double o[3] = { 0, 0, 0 }, p[4][3];
    for (int k = 0; k < 4; ++k)
    {
      input->GetPoint(g[k], p[k]);
    }
    volume += d == 0 ? Volume(o, p[0], p[1], p[2]) + Volume(o, p[0], p[2], p[3])
                     : Volume(o, p[0], p[1], p[3]) + Volume(o, p[1], p[2], p[3]);
  }

  // Conforming, on the part as it is and with its point ids shuffled (the
  // smallest-id diagonals, and so the types, change; Gmsh numbers the
  // subdivided mesh's tet corners first, which leaves few patterns).
  auto shuffled = vtkSmartPointer<vtkUnstructuredGrid>::New();
  {
    std::vector<vtkIdType> perm(input->GetNumberOfPoints());
    for (std::size_t i = 0; i < perm.size(); ++i)
    {
      perm[i] = static_cast<vtkIdType>(i);
    }
    std::mt19937_64 rng(3);
    std::shuffle(perm.begin(), perm.end(), rng);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(input->GetNumberOfPoints());
    for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
    {
      points->SetPoint(perm[i], input->GetPoint(i));
    }
    shuffled->SetPoints(points);
    shuffled->AllocateExact(input->GetNumberOfCells(), 8);
    for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
    {
      input->GetCellPoints(c, ids);
      vtkIdType v[8];
      for (int k = 0; k < 8; ++k)
      {
        v[k] = perm[ids->GetId(k)];
      }
      shuffled->InsertNextCell(VTK_HEXAHEDRON, 8, v);
    }
  }
  for (vtkUnstructuredGrid* grid : { input.GetPointer(), shuffled.GetPointer() })
  {
    const bool isShuffled = grid == shuffled.GetPointer();
    vtkNew<vtkFEMorphHexToTet> filter;
    vtkNew<MessageRecorder> messages;
    ASSERT_EQ(RunFilter(filter, grid, messages), 1) << messages->AllErrors();
    EXPECT_TRUE(messages->Warnings.empty()) << messages->AllWarnings();
    vtkUnstructuredGrid* out = filter->GetOutput();
    std::vector<femorph::Vec3> points;
    std::vector<femorph::Tet> tets;
    ToCore(out, points, tets);
    const femorph::ValidityReport check = femorph::check_validity(points, tets);
    EXPECT_TRUE(check.ok()) << check.summary();
    EXPECT_EQ(check.boundary_faces, 2 * boundaryQuads);
    if (!isShuffled)
    {
      EXPECT_NEAR(TotalVolume(out), volume, 1e-10 * volume);
    }
    EXPECT_EQ(FieldCount(out, "NonConformingFaceCount"), 0);
    EXPECT_EQ(FieldCount(out, "InvertedCellCount"), 0);
    // 5 tets for type A, 6 for the others.
    auto* type = vtkSignedCharArray::SafeDownCast(out->GetCellData()->GetArray("DecompositionType"));
    auto* source = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("SourceCell"));
    ASSERT_TRUE(type && source);
    std::vector<int> children(grid->GetNumberOfCells(), 0), cellType(grid->GetNumberOfCells(), -1);
    for (vtkIdType t = 0; t < out->GetNumberOfCells(); ++t)
    {
      ++children[source->GetValue(t)];
      cellType[source->GetValue(t)] = type->GetValue(t);
    }
    std::set<int> typesUsed;
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      EXPECT_EQ(children[c], cellType[c] == 0 ? 5 : 6) << c;
      typesUsed.insert(cellType[c]);
    }
    EXPECT_GE(typesUsed.size(), isShuffled ? 4u : 2u);
    if (!isShuffled)
    {
      // The input's arrays reach the tets.
      EXPECT_NE(out->GetCellData()->GetArray("CADFace"), nullptr);
      EXPECT_NE(out->GetPointData()->GetArray("CADEntityDim"), nullptr);
    }
  }

  for (int t = 0; t < femorph::kHexDecompositionTypes; ++t)
  {
    for (int mirrored = 0; mirrored < 2; ++mirrored)
    {
      vtkNew<vtkFEMorphHexToTet> filter;
      filter->ConformingOff();
      filter->SetDecompositionType(t);
      filter->SetMirrored(mirrored);
      filter->AllowInvertedOn(); // a fixed type may not suit a distorted cell
      vtkNew<MessageRecorder> messages;
      ASSERT_EQ(RunFilter(filter, input, messages), 1) << messages->AllErrors();
      vtkUnstructuredGrid* out = filter->GetOutput();
      const vtkIdType conflicts = FieldCount(out, "NonConformingFaceCount");
      const vtkIdType inverted = FieldCount(out, "InvertedCellCount");
      std::vector<femorph::Vec3> points;
      std::vector<femorph::Tet> tets;
      ToCore(out, points, tets);
      femorph::ValidityOptions options;
      options.require_positive = false; // the conflicts alone
      const femorph::ValidityReport check = femorph::check_validity(points, tets, options);
      const std::string name = std::string("ABCDEF").substr(t, 1) + (mirrored ? "-" : "+");
      EXPECT_EQ(check.boundary_faces, 2 * boundaryQuads + 4 * static_cast<std::size_t>(conflicts))
        << name;
      EXPECT_EQ(check.ok(), conflicts == 0) << name << ": " << check.summary();
      EXPECT_EQ(femorph::check_validity(points, tets).ok(), conflicts == 0 && inverted == 0)
        << name;
      EXPECT_EQ(messages->Warnings.empty(), conflicts == 0 && inverted == 0)
        << name << ": " << messages->AllWarnings();
      // Node orders of a subdivided tet mesh are not aligned: every type
      // conflicts somewhere.
      EXPECT_GT(conflicts, 0) << name;
      EXPECT_EQ(out->GetNumberOfCells(), input->GetNumberOfCells() * (t == 0 ? 5 : 6)) << name;
    }
  }
  EXPECT_EQ(Fingerprint(input), before) << "the input was modified";
}

// The ParaView property defaults and domains (Plugin/FEMorphFilters.xml)
// equal the C++ defaults and clamps; every property is documented; the
// type and mirror are shown only when Conforming is off.
TEST(HexToTet, XmlDefaultsEqualCxxDefaults)
{
  vtkSmartPointer<vtkXMLDataElement> root;
  vtkXMLDataElement* proxy = femorph_test::FindFilterProxy(
    FEMORPH_PLUGIN_XML, "vtkFEMorphHexToTet", "FEMorphHexToTet", "FEMorph Hex To Tet", root);
  ASSERT_NE(proxy, nullptr);

  vtkNew<vtkFEMorphHexToTet> d;
  const std::map<std::string, femorph_test::XmlProperty> expected = {
    { "SetConforming", { double(d->GetConforming()), 0, 1, false } },
    { "SetDecompositionType",
      { double(d->GetDecompositionType()), double(d->GetDecompositionTypeMinValue()),
        double(d->GetDecompositionTypeMaxValue()), false } },
    { "SetMirrored", { double(d->GetMirrored()), 0, 1, false } },
    { "SetAllowInverted", { double(d->GetAllowInverted()), 0, 1, true } },
  };
  const std::set<std::string> onlyWhenFixed = { "SetDecompositionType", "SetMirrored" };
  femorph_test::CheckFilterProperties(proxy, expected,
    [&](const std::string& command, vtkXMLDataElement* e)
    {
      EXPECT_STREQ(e->GetName(), "IntVectorProperty") << command;
      vtkXMLDataElement* decorator = nullptr;
      if (vtkXMLDataElement* h = e->FindNestedElementWithName("Hints"))
      {
        decorator = h->FindNestedElementWithName("PropertyWidgetDecorator");
      }
      EXPECT_EQ(decorator != nullptr, onlyWhenFixed.count(command) == 1) << command;
      if (decorator)
      {
        EXPECT_STREQ(decorator->GetAttribute("property"), "Conforming");
        EXPECT_STREQ(decorator->GetAttribute("value"), "0");
      }
      if (command == "SetDecompositionType")
      {
        // One entry per type, A..F, covering the clamp range exactly.
        vtkXMLDataElement* domain = e->FindNestedElementWithName("EnumerationDomain");
        ASSERT_NE(domain, nullptr);
        ASSERT_EQ(domain->GetNumberOfNestedElements(), femorph::kHexDecompositionTypes);
        for (int k = 0; k < domain->GetNumberOfNestedElements(); ++k)
        {
          vtkXMLDataElement* entry = domain->GetNestedElement(k);
          EXPECT_EQ(std::stoi(entry->GetAttribute("value")), d->GetDecompositionTypeMinValue() + k);
          EXPECT_STREQ(entry->GetAttribute("text"),
            femorph::to_string(static_cast<femorph::HexDecompositionType>(k)));
        }
        EXPECT_EQ(d->GetDecompositionTypeMaxValue(), femorph::kHexDecompositionTypes - 1);
      }
    });

  vtkXMLDataElement* doc = proxy->FindNestedElementWithName("Documentation");
  ASSERT_NE(doc, nullptr);
  const std::string help = doc->GetCharacterData() ? doc->GetCharacterData() : "";
  for (const char* name : { "SourceCell", "DecompositionType", "Inverted",
         "NonConformingFaceCount", "InvertedCellCount" })
  {
    EXPECT_NE(help.find(name), std::string::npos) << "the help does not name " << name;
  }
}
