// vtkFEMorphMeshQuality on hand-built cells with closed-form answers, on bad
// input, on a Data/ part; the input is never modified; XML defaults equal the
// C++ defaults.
#include "filters_test_utils.h"
#include "vtkFEMorphHexToTet.h"
#include "vtkFEMorphMeshQuality.h"

#include "vtkCallbackCommand.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkXMLDataElement.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtkXMLUtilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

using femorph_test::MakeGrid;
using femorph_test::Snapshot;
using femorph_test::MessageRecorder;

namespace
{
const double Sqrt2Over2 = std::sqrt(2.0) / 2;
const double RegularDihedral = vtkMath::DegreesFromRadians(std::acos(1.0 / 3.0)); // 70.5288 degrees
const double CornerTetStretch = std::sqrt(3.0) / (1.5 + std::sqrt(3.0) / 2);
const double PyramidJacobian = 1.0 / std::sqrt(1.5); // base corner, apex height 1
constexpr double Tol = 1e-12;

// Cell ids of the mixed grid.
enum MixedCell
{
  RegularTet,
  UnitHex,
  RightWedge,
  SquarePyramid,
  InvertedTet,
  FlatTet,
  CornerTet,
  UnitVoxel,
  NumMixedCells
};

// One cell of each kind, each with its own points, in VTK's positive node
// orders (vtkCellType.h, VTK's cell documentation).
vtkSmartPointer<vtkUnstructuredGrid> MakeMixedGrid()
{
  std::vector<std::array<double, 3>> pts;
  std::vector<std::pair<int, std::vector<vtkIdType>>> cells;
  auto add = [&](int type, std::vector<std::array<double, 3>> corners) {
    std::vector<vtkIdType> ids;
    for (const auto& p : corners)
    {
      ids.push_back(static_cast<vtkIdType>(pts.size()));
      pts.push_back(p);
    }
    cells.emplace_back(type, ids);
  };
  // Regular tet (edge 2 sqrt 2), positive.
  add(VTK_TETRA, { { 1, 1, 1 }, { -1, 1, -1 }, { 1, -1, -1 }, { -1, -1, 1 } });
  add(VTK_HEXAHEDRON,
    { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 },
      { 0, 1, 1 } });
  // Right prism over the right isosceles triangle; (0, 1, 2)'s normal points
  // away from (3, 4, 5).
  add(VTK_WEDGE, { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 1 }, { 1, 0, 1 } });
  // Base normal towards the apex.
  add(VTK_PYRAMID, { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0.5, 0.5, 1 } });
  // The regular tet with two vertices swapped.
  add(VTK_TETRA, { { 1, 1, 1 }, { 1, -1, -1 }, { -1, 1, -1 }, { -1, -1, 1 } });
  // Four coplanar points.
  add(VTK_TETRA, { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 } });
  // The corner of the unit cube.
  add(VTK_TETRA, { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } });
  add(VTK_VOXEL,
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 },
      { 1, 1, 1 } });
  return MakeGrid(pts, cells);
}

double Field(vtkDataSet* data, const char* name)
{
  vtkAbstractArray* a = data->GetFieldData()->GetAbstractArray(name);
  EXPECT_NE(a, nullptr) << "field data " << name;
  vtkDataArray* d = vtkDataArray::SafeDownCast(a);
  return d && d->GetNumberOfTuples() == 1 ? d->GetComponent(0, 0)
                                          : std::numeric_limits<double>::quiet_NaN();
}

vtkDataArray* CellArray(vtkDataSet* data, const char* name)
{
  vtkDataArray* a = data->GetCellData()->GetArray(name);
  EXPECT_NE(a, nullptr) << "cell array " << name;
  return a;
}

void ExpectNear(double actual, double expected, const char* what, int cell)
{
  if (std::isnan(expected))
  {
    EXPECT_TRUE(std::isnan(actual)) << what << " of cell " << cell << " is " << actual;
  }
  else
  {
    EXPECT_NEAR(actual, expected, Tol) << what << " of cell " << cell;
  }
}



} // namespace

TEST(MeshQuality, MixedCellsMatchClosedForms)
{
  auto input = MakeMixedGrid();
  vtkNew<vtkFEMorphMeshQuality> quality;
  vtkNew<MessageRecorder> messages;
  messages->Observe(quality);
  quality->SetInputData(input);
  quality->Update();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  EXPECT_TRUE(messages->Warnings.empty()) << messages->AllWarnings();
  vtkUnstructuredGrid* out = quality->GetOutput();
  ASSERT_EQ(out->GetNumberOfCells(), NumMixedCells);
  ASSERT_EQ(out->GetNumberOfPoints(), input->GetNumberOfPoints());

  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Expected
  {
    double Stretch, Jacobian, MinAngle, MaxAngle;
    int Inverted;
  };
  const Expected expected[NumMixedCells] = {
    { 1, Sqrt2Over2, RegularDihedral, RegularDihedral, 0 }, // RegularTet
    { nan, 1, nan, nan, 0 },                                // UnitHex
    { nan, Sqrt2Over2, nan, nan, 0 },                       // RightWedge: 45-degree corners
    { nan, PyramidJacobian, nan, nan, 0 },                  // SquarePyramid: base corners
    { -1, -Sqrt2Over2, RegularDihedral, RegularDihedral, 1 }, // InvertedTet: mirror angles
    { 0, 0, 0, 180, 0 },                                    // FlatTet
    { CornerTetStretch, 0.5, 54.735610317245346, 90, 0 },   // CornerTet
    { nan, 1, nan, nan, 0 },                                // UnitVoxel, as a hexahedron
  };
  vtkDataArray* stretch = CellArray(out, "Stretch");
  vtkDataArray* jacobian = CellArray(out, "ScaledJacobian");
  vtkDataArray* minAngle = CellArray(out, "MinDihedralAngle");
  vtkDataArray* maxAngle = CellArray(out, "MaxDihedralAngle");
  vtkDataArray* inverted = CellArray(out, "Inverted");
  ASSERT_TRUE(stretch && jacobian && minAngle && maxAngle && inverted);
  EXPECT_EQ(inverted->GetDataType(), VTK_UNSIGNED_CHAR);
  for (int c = 0; c < NumMixedCells; ++c)
  {
    ExpectNear(stretch->GetComponent(c, 0), expected[c].Stretch, "Stretch", c);
    ExpectNear(jacobian->GetComponent(c, 0), expected[c].Jacobian, "ScaledJacobian", c);
    ExpectNear(minAngle->GetComponent(c, 0), expected[c].MinAngle, "MinDihedralAngle", c);
    ExpectNear(maxAngle->GetComponent(c, 0), expected[c].MaxAngle, "MaxDihedralAngle", c);
    EXPECT_EQ(inverted->GetComponent(c, 0), expected[c].Inverted) << "Inverted of cell " << c;
  }
  EXPECT_STREQ(out->GetCellData()->GetScalars()->GetName(), "Stretch");

  // Summary.
  EXPECT_NEAR(Field(out, "StretchMin"), -1, Tol);
  EXPECT_NEAR(Field(out, "StretchMax"), 1, Tol);
  EXPECT_NEAR(Field(out, "StretchMean"), (1 - 1 + 0 + CornerTetStretch) / 4, Tol);
  EXPECT_NEAR(Field(out, "ScaledJacobianMin"), -Sqrt2Over2, Tol);
  EXPECT_NEAR(Field(out, "ScaledJacobianMax"), 1, Tol);
  EXPECT_NEAR(Field(out, "ScaledJacobianMean"),
    (Sqrt2Over2 + 1 + Sqrt2Over2 + PyramidJacobian - Sqrt2Over2 + 0 + 0.5 + 1) / 8, Tol);
  EXPECT_NEAR(Field(out, "MinDihedralAngleMin"), 0, Tol);
  EXPECT_NEAR(Field(out, "MaxDihedralAngleMax"), 180, Tol);
  EXPECT_NEAR(Field(out, "MinDihedralAngleMean"),
    (2 * RegularDihedral + 0 + 54.735610317245346) / 4, Tol);
  EXPECT_NEAR(Field(out, "MaxDihedralAngleMean"), (2 * RegularDihedral + 180 + 90) / 4, Tol);
  EXPECT_EQ(Field(out, "StretchThreshold"), 0.05);
  EXPECT_EQ(Field(out, "InvertedCount"), 1);
  EXPECT_EQ(Field(out, "ZeroVolumeCount"), 1);
  EXPECT_EQ(Field(out, "BelowThresholdCount"), 2); // the inverted and the flat tet
  EXPECT_EQ(Field(out, "TetraCount"), 4);
  EXPECT_EQ(Field(out, "HexahedronCount"), 2);
  EXPECT_EQ(Field(out, "WedgeCount"), 1);
  EXPECT_EQ(Field(out, "PyramidCount"), 1);
  EXPECT_EQ(Field(out, "SkippedCellCount"), 0);
  EXPECT_TRUE(vtkIdTypeArray::SafeDownCast(out->GetFieldData()->GetArray("InvertedCount")));

  // A higher threshold also counts the corner tet (0.732).
  quality->SetStretchThreshold(0.8);
  quality->Update();
  EXPECT_EQ(Field(quality->GetOutput(), "BelowThresholdCount"), 3);
  EXPECT_EQ(Field(quality->GetOutput(), "StretchThreshold"), 0.8);
}

TEST(MeshQuality, InvertedCornersOfOtherCells)
{
  // The unit hex with its top and bottom faces swapped: every corner inverted.
  auto grid = MakeGrid({ { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 }, { 0, 0, 0 },
                         { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } },
    { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } } });
  vtkNew<vtkFEMorphMeshQuality> quality;
  quality->SetInputData(grid);
  quality->Update();
  vtkUnstructuredGrid* out = quality->GetOutput();
  EXPECT_NEAR(CellArray(out, "ScaledJacobian")->GetComponent(0, 0), -1, Tol);
  EXPECT_EQ(CellArray(out, "Inverted")->GetComponent(0, 0), 1);
  EXPECT_EQ(Field(out, "InvertedCount"), 1);
  EXPECT_TRUE(std::isnan(Field(out, "StretchMin"))); // no tets
}

// Issue 29: one definition of a valid cell (Core/quality/is_valid_cell.h),
// shared with Hex To Tet. The unit hex with its top face turned by 90
// degrees has ScaledJacobian sqrt(2)/2 at every corner (Verdict's value) and
// no inverted corner, but Hex To Tet splits it into an inverted tet: Invalid.
// The mixed grid's good cells are valid; its inverted and flat tets are not.
TEST(MeshQuality, InvalidFlagsCellsHexToTetRefuses)
{
  auto twisted = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 1, 0, 1 },
                            { 1, 1, 1 }, { 0, 1, 1 }, { 0, 0, 1 } },
    { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } } });
  vtkNew<vtkFEMorphMeshQuality> quality;
  quality->SetInputData(twisted);
  quality->Update();
  vtkUnstructuredGrid* out = quality->GetOutput();
  EXPECT_NEAR(CellArray(out, "ScaledJacobian")->GetComponent(0, 0), Sqrt2Over2, Tol);
  EXPECT_EQ(CellArray(out, "Inverted")->GetComponent(0, 0), 0);
  EXPECT_EQ(CellArray(out, "Invalid")->GetComponent(0, 0), 1);
  EXPECT_EQ(Field(out, "InvalidCount"), 1);

  vtkNew<vtkFEMorphHexToTet> split;
  split->SetInputData(twisted);
  split->AllowInvertedOn();
  split->Update();
  vtkAbstractArray* count = split->GetOutput()->GetFieldData()->GetAbstractArray("InvertedCellCount");
  ASSERT_NE(count, nullptr);
  EXPECT_EQ(vtkDataArray::SafeDownCast(count)->GetComponent(0, 0), 1);

  vtkNew<vtkFEMorphMeshQuality> mixed;
  mixed->SetInputData(MakeMixedGrid());
  mixed->Update();
  vtkDataArray* invalid = CellArray(mixed->GetOutput(), "Invalid");
  for (int c = 0; c < NumMixedCells; ++c)
  {
    EXPECT_EQ(invalid->GetComponent(c, 0), c == InvertedTet || c == FlatTet ? 1 : 0) << c;
  }
  EXPECT_EQ(Field(mixed->GetOutput(), "InvalidCount"), 2);
}

// Issue 29: with coordinates at 1e-300 or 1e300 every tet came out with zero
// volume and Stretch 0 (products of lengths under- and overflowed), with no
// warning. The measures and counts are now the same at every scale; 1e-12
// and 1e12 were already right and stay so.
TEST(MeshQuality, SameResultsFrom1eMinus300To1e300)
{
  vtkNew<vtkFEMorphMeshQuality> reference;
  reference->SetInputData(MakeMixedGrid());
  reference->Update();
  vtkUnstructuredGrid* ref = reference->GetOutput();
  for (const double scale : { 1e-300, 1e300, 1e-12, 1e12 })
  {
    auto grid = MakeMixedGrid();
    vtkPoints* points = grid->GetPoints();
    for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
    {
      double x[3];
      points->GetPoint(i, x);
      points->SetPoint(i, scale * x[0], scale * x[1], scale * x[2]);
    }
    vtkNew<vtkFEMorphMeshQuality> quality;
    vtkNew<MessageRecorder> messages;
    quality->AddObserver(vtkCommand::WarningEvent, messages);
    quality->AddObserver(vtkCommand::ErrorEvent, messages);
    quality->SetInputData(grid);
    quality->Update();
    vtkUnstructuredGrid* out = quality->GetOutput();
    EXPECT_TRUE(messages->Errors.empty()) << scale << ": " << messages->AllErrors();
    for (const char* name : { "ZeroVolumeCount", "InvertedCount", "InvalidCount", "BelowThresholdCount" })
    {
      EXPECT_EQ(Field(out, name), Field(ref, name)) << name << " at " << scale;
    }
    for (const char* name : { "Stretch", "ScaledJacobian", "MinDihedralAngle", "MaxDihedralAngle" })
    {
      for (int c = 0; c < NumMixedCells; ++c)
      {
        const double expected = CellArray(ref, name)->GetComponent(c, 0);
        const double actual = CellArray(out, name)->GetComponent(c, 0);
        if (std::isnan(expected))
        {
          EXPECT_TRUE(std::isnan(actual)) << name << " of cell " << c << " at " << scale;
        }
        else
        {
          EXPECT_NEAR(actual, expected, 1e-9 * std::max(1.0, std::abs(expected)))
            << name << " of cell " << c << " at " << scale;
        }
      }
    }
  }
}

TEST(MeshQuality, InputUntouched)
{
  auto input = MakeMixedGrid();
  vtkNew<vtkIntArray> material;
  material->SetName("Material");
  for (int c = 0; c < NumMixedCells; ++c)
  {
    material->InsertNextValue(c);
  }
  input->GetCellData()->AddArray(material);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("Temperature");
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    temperature->InsertNextValue(0.5 * i);
  }
  input->GetPointData()->AddArray(temperature);
  vtkNew<vtkIntArray> note;
  note->SetName("Note");
  note->InsertNextValue(42);
  input->GetFieldData()->AddArray(note);
  const Snapshot before(input);

  vtkNew<vtkFEMorphMeshQuality> quality;
  quality->SetInputData(input);
  quality->Update();
  EXPECT_TRUE(Snapshot(input) == before) << "the input was modified";
  EXPECT_EQ(input->GetCellData()->GetArray("Stretch"), nullptr);
  EXPECT_EQ(input->GetFieldData()->GetArray("StretchMin"), nullptr);
  EXPECT_EQ(input->GetCellData()->GetScalars(), nullptr);

  // Passed through: the same arrays (shallow copies) plus the quality arrays.
  vtkUnstructuredGrid* out = quality->GetOutput();
  EXPECT_EQ(out->GetCellData()->GetArray("Material"), material.Get());
  EXPECT_EQ(out->GetPointData()->GetArray("Temperature"), temperature.Get());
  EXPECT_EQ(out->GetFieldData()->GetArray("Note"), note.Get());
  EXPECT_EQ(out->GetPoints(), input->GetPoints());
  EXPECT_EQ(out->GetCellData()->GetNumberOfArrays(), 7);  // Material + 6 quality arrays
}

TEST(MeshQuality, WarnsAndSkipsCellsItCannotEvaluate)
{
  std::vector<std::array<double, 3>> pts = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 },
    { 0, 0, 1 }, { 0.5, 0, 0 }, { 0.5, 0.5, 0 }, { 0, 0.5, 0 }, { 0, 0, 0.5 }, { 0.5, 0, 0.5 },
    { 0, 0.5, 0.5 } };
  auto grid = MakeGrid(pts,
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TRIANGLE, { 0, 1, 2 } },
      { VTK_QUADRATIC_TETRA, { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 } }, { VTK_TRIANGLE, { 0, 2, 3 } } });
  vtkNew<vtkFEMorphMeshQuality> quality;
  vtkNew<MessageRecorder> messages;
  messages->Observe(quality);
  quality->SetInputData(grid);
  quality->Update();
  EXPECT_TRUE(messages->Errors.empty()) << messages->AllErrors();
  ASSERT_EQ(messages->Warnings.size(), 1u);
  EXPECT_NE(messages->Warnings[0].find("2 VTK_TRIANGLE and 1 VTK_QUADRATIC_TETRA cells get NaN"),
    std::string::npos)
    << messages->Warnings[0];
  vtkUnstructuredGrid* out = quality->GetOutput();
  ASSERT_EQ(out->GetNumberOfCells(), 4);
  EXPECT_NEAR(CellArray(out, "Stretch")->GetComponent(0, 0), CornerTetStretch, Tol);
  for (int c = 1; c < 4; ++c)
  {
    for (const char* name : { "Stretch", "ScaledJacobian", "MinDihedralAngle", "MaxDihedralAngle" })
    {
      EXPECT_TRUE(std::isnan(CellArray(out, name)->GetComponent(c, 0))) << name << " " << c;
    }
    EXPECT_EQ(CellArray(out, "Inverted")->GetComponent(c, 0), 0);
  }
  EXPECT_EQ(Field(out, "SkippedCellCount"), 3);
  EXPECT_EQ(Field(out, "TetraCount"), 1);
}

TEST(MeshQuality, WarnsWhenEveryTetIsInverted)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 } },
    { { VTK_TETRA, { 0, 2, 1, 3 } }, { VTK_TETRA, { 4, 1, 2, 3 } } });
  vtkNew<vtkFEMorphMeshQuality> quality;
  vtkNew<MessageRecorder> messages;
  messages->Observe(quality);
  quality->SetInputData(grid);
  quality->Update();
  ASSERT_EQ(messages->Warnings.size(), 1u);
  EXPECT_NE(messages->Warnings[0].find("opposite vertex order"), std::string::npos);
  EXPECT_EQ(Field(quality->GetOutput(), "InvertedCount"), 2);
}

TEST(MeshQuality, NonFiniteCoordinatesAreAnError)
{
  auto grid = MakeMixedGrid();
  grid->GetPoints()->SetPoint(3, 0, std::numeric_limits<double>::quiet_NaN(), 0);
  grid->GetPoints()->SetPoint(7, std::numeric_limits<double>::infinity(), 0, 0);
  vtkNew<vtkFEMorphMeshQuality> quality;
  vtkNew<MessageRecorder> messages;
  messages->Observe(quality);
  quality->SetInputData(grid);
  messages->Observe(quality->GetExecutive()); // its "returned failure" error
  quality->Update();
  ASSERT_FALSE(messages->Errors.empty());
  EXPECT_NE(messages->AllErrors().find("2 points of the input have NaN or infinite coordinates"),
    std::string::npos)
    << messages->AllErrors();
  EXPECT_EQ(quality->GetOutput()->GetNumberOfCells(), 0);
}

TEST(MeshQuality, StretchThresholdIsClamped)
{
  vtkNew<vtkFEMorphMeshQuality> quality;
  EXPECT_EQ(quality->GetStretchThreshold(), 0.05);
  quality->SetStretchThreshold(2);
  EXPECT_EQ(quality->GetStretchThreshold(), 1);
  quality->SetStretchThreshold(-1);
  EXPECT_EQ(quality->GetStretchThreshold(), 0);
  // NaN passes the clamp macro: RequestData refuses it.
  quality->SetStretchThreshold(std::numeric_limits<double>::quiet_NaN());
  vtkNew<MessageRecorder> messages;
  messages->Observe(quality);
  messages->Observe(quality->GetExecutive());
  quality->SetInputData(MakeMixedGrid());
  quality->Update();
  EXPECT_NE(messages->AllErrors().find("StretchThreshold"), std::string::npos);

  std::ostringstream os;
  quality->PrintSelf(os, vtkIndent());
  EXPECT_NE(os.str().find("StretchThreshold: "), std::string::npos);
}

TEST(MeshQuality, DataPartProgressAndAbort)
{
  auto input = femorph_test::ReadPart("boss_block.vtu");
  if (!input)
  {
    GTEST_SKIP() << "Data/boss_block.vtu not found";
  }
  vtkNew<vtkFEMorphMeshQuality> quality;
  quality->SetInputData(input);
  std::vector<double> progress;
  vtkNew<vtkCallbackCommand> onProgress;
  onProgress->SetClientData(&progress);
  onProgress->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
    static_cast<std::vector<double>*>(client)->push_back(*static_cast<double*>(call));
  });
  quality->AddObserver(vtkCommand::ProgressEvent, onProgress);
  quality->Update();
  vtkUnstructuredGrid* out = quality->GetOutput();
  const vtkIdType tets = input->GetNumberOfCells();
  EXPECT_EQ(Field(out, "TetraCount"), tets);
  EXPECT_EQ(Field(out, "InvertedCount"), 0); // Gmsh's tets are all positive (Data/README.md)
  EXPECT_EQ(Field(out, "ZeroVolumeCount"), 0);
  EXPECT_GT(Field(out, "StretchMin"), 0);
  EXPECT_LE(Field(out, "StretchMax"), 1 + Tol);
  EXPECT_GE(progress.size(), 2u);
  EXPECT_EQ(progress.back(), 1.0);

  // Abort after the first chunk (the part has more cells than one chunk).
  if (tets > (1 << 15))
  {
    vtkNew<vtkCallbackCommand> abortAtFirstProgress;
    abortAtFirstProgress->SetCallback([](vtkObject* caller, unsigned long, void*, void* call) {
      const double value = *static_cast<double*>(call);
      if (value > 0 && value < 1)
      {
        static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
      }
    });
    quality->AddObserver(vtkCommand::ProgressEvent, abortAtFirstProgress);
    quality->Modified();
    quality->Update();
    EXPECT_EQ(quality->GetOutput()->GetCellData()->GetArray("Stretch"), nullptr);
  }
}

// The ParaView property defaults and ranges (Plugin/FEMorphFilters.xml) equal
// the C++ defaults and clamps.
TEST(MeshQuality, XmlDefaultsEqualCxxDefaults)
{
  vtkSmartPointer<vtkXMLDataElement> root;
  vtkXMLDataElement* proxy = femorph_test::FindFilterProxy(
    FEMORPH_PLUGIN_XML, "vtkFEMorphMeshQuality", "FEMorphMeshQuality", "FEMorph Mesh Quality", root);
  ASSERT_NE(proxy, nullptr);

  vtkNew<vtkFEMorphMeshQuality> defaults;
  vtkXMLDataElement* property =
    proxy->FindNestedElementWithNameAndAttribute("DoubleVectorProperty", "command", "SetStretchThreshold");
  ASSERT_NE(property, nullptr);
  EXPECT_EQ(std::stod(property->GetAttribute("default_values")), defaults->GetStretchThreshold());
  vtkXMLDataElement* range = property->FindNestedElementWithName("DoubleRangeDomain");
  ASSERT_NE(range, nullptr);
  EXPECT_EQ(std::stod(range->GetAttribute("min")), defaults->GetStretchThresholdMinValue());
  EXPECT_EQ(std::stod(range->GetAttribute("max")), defaults->GetStretchThresholdMaxValue());

  // Every Set... command of the proxy is one this test knows, so a new
  // property cannot be added without its default being checked here.
  int checked = 0;
  for (int i = 0; i < proxy->GetNumberOfNestedElements(); ++i)
  {
    vtkXMLDataElement* e = proxy->GetNestedElement(i);
    const char* command = e->GetAttribute("command");
    if (!command || std::string(e->GetName()) == "InputProperty")
    {
      continue;
    }
    EXPECT_STREQ(command, "SetStretchThreshold") << "add a default check for " << command;
    ++checked;
  }
  EXPECT_EQ(checked, 1);
}
