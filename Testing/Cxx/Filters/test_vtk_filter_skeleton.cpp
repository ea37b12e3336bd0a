// Every FEMorph filter through the same skeleton (vtkFEMorphAlgorithm): one
// parameterised test per behaviour, so a new filter joins by one row of the
// table below.
#include "filters_test_utils.h"

#include "vtkFEMorphAdapt.h"
#include "vtkFEMorphAlgorithm.h"
#include "vtkFEMorphHexToTet.h"
#include "vtkFEMorphDeform.h"
#include "vtkFEMorphImprove.h"
#include "vtkFEMorphMeshQuality.h"
#include "vtkFEMorphSegment.h"
#include "vtkFEMorphTetToHex.h"

#include "vtkDataSet.h"
#include "vtkExecutive.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

using femorph_test::MakeGrid;
using femorph_test::MakeTwoTets;
using femorph_test::MessageRecorder;
using femorph_test::Snapshot;

namespace
{

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

struct FilterCase
{
  const char* Name;
  std::function<vtkSmartPointer<vtkFEMorphAlgorithm>()> Make;
  /// Sets a floating-point property to NaN; empty for a filter without one
  /// (FilterProperties leaves it out).
  std::function<void(vtkFEMorphAlgorithm*)> SetNaNProperty;
  const char* NaNProperty;
  /// Whether a VTK_TRIANGLE next to the tets is an error (otherwise a
  /// warning: the filter skips cells it does not evaluate).
  bool RefusesTriangles;
};

// gtest prints a parameter in the test's name (ctest lists it): the row's.
void PrintTo(const FilterCase& c, std::ostream* os)
{
  *os << c.Name;
}

template <class T>
vtkSmartPointer<vtkFEMorphAlgorithm> Make()
{
  return vtkSmartPointer<T>::New();
}

/// Deform needs a control region: region 0, measuring only.
vtkSmartPointer<vtkFEMorphAlgorithm> MakeDeform()
{
  auto filter = vtkSmartPointer<vtkFEMorphDeform>::New();
  filter->SetControlRegion(0);
  return filter;
}

const FilterCase Filters[] = {
  { "MeshQuality", Make<vtkFEMorphMeshQuality>,
    [](vtkFEMorphAlgorithm* f) { vtkFEMorphMeshQuality::SafeDownCast(f)->SetStretchThreshold(NaN); },
    "StretchThreshold", false },
  { "Segment", Make<vtkFEMorphSegment>,
    [](vtkFEMorphAlgorithm* f) { vtkFEMorphSegment::SafeDownCast(f)->SetSharpAngle(NaN); },
    "SharpAngle", true },
  { "Improve", Make<vtkFEMorphImprove>,
    [](vtkFEMorphAlgorithm* f) { vtkFEMorphImprove::SafeDownCast(f)->SetQualityFloor(NaN); },
    "QualityFloor", true },
  { "Deform", MakeDeform,
    [](vtkFEMorphAlgorithm* f) { vtkFEMorphDeform::SafeDownCast(f)->SetTargetValue(NaN); },
    "TargetValue", true },
  { "Adapt", Make<vtkFEMorphAdapt>,
    [](vtkFEMorphAlgorithm* f) { vtkFEMorphAdapt::SafeDownCast(f)->SetDistanceThreshold(NaN); },
    "DistanceThreshold", true },
  { "HexToTet", Make<vtkFEMorphHexToTet>, {}, nullptr, true },
  { "TetToHex", Make<vtkFEMorphTetToHex>,
    [](vtkFEMorphAlgorithm* f) { vtkFEMorphTetToHex::SafeDownCast(f)->SetMinScaledJacobian(NaN); },
    "MinScaledJacobian", true },
};

class FilterSkeleton : public ::testing::TestWithParam<FilterCase>
{
protected:
  /// Runs a new filter of this row on `input` (null: no input connected);
  /// returns the executive's result.
  int Run(vtkDataObject* input, const std::function<void(vtkFEMorphAlgorithm*)>& set = {})
  {
    this->Filter = GetParam().Make();
    this->Messages->Observe(this->Filter);
    this->PipelineMessages->Observe(this->Filter->GetExecutive());
    if (set)
    {
      set(this->Filter);
    }
    if (input)
    {
      this->Filter->SetInputDataObject(0, input);
    }
    return this->Filter->GetExecutive()->Update();
  }

  /// Every output port holds an empty data object.
  void ExpectEmptyOutputs()
  {
    for (int port = 0; port < this->Filter->GetNumberOfOutputPorts(); ++port)
    {
      vtkDataObject* output = this->Filter->GetOutputDataObject(port);
      ASSERT_NE(output, nullptr) << "port " << port;
      if (auto* data = vtkDataSet::SafeDownCast(output))
      {
        EXPECT_EQ(data->GetNumberOfPoints(), 0) << "port " << port;
        EXPECT_EQ(data->GetNumberOfCells(), 0) << "port " << port;
      }
      else if (auto* table = vtkTable::SafeDownCast(output))
      {
        EXPECT_EQ(table->GetNumberOfRows(), 0) << "port " << port;
      }
    }
  }

  /// One error, starting with the filter's label, containing `words`.
  void ExpectOneError(const std::string& words)
  {
    ASSERT_EQ(this->Messages->Errors.size(), 1u) << this->Messages->AllErrors();
    const std::string& error = this->Messages->Errors[0];
    EXPECT_NE(error.find(std::string(this->Filter->GetFilterLabel()) + ": "), std::string::npos)
      << error;
    EXPECT_NE(error.find(words), std::string::npos) << error;
  }

  vtkSmartPointer<vtkFEMorphAlgorithm> Filter;
  vtkNew<MessageRecorder> Messages;
  vtkNew<MessageRecorder> PipelineMessages;
};

} // namespace

TEST_P(FilterSkeleton, EmptyInputGivesEmptyOutputsAndAWarning)
{
  vtkNew<vtkUnstructuredGrid> empty;
  auto pointsOnly = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 } }, {});
  for (vtkUnstructuredGrid* input : { static_cast<vtkUnstructuredGrid*>(empty), pointsOnly.Get() })
  {
    this->Messages->Errors.clear();
    this->Messages->Warnings.clear();
    const Snapshot before(input);
    EXPECT_EQ(this->Run(input), 1);
    EXPECT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();
    ASSERT_EQ(this->Messages->Warnings.size(), 1u) << this->Messages->AllWarnings();
    EXPECT_NE(this->Messages->Warnings[0].find("the input has no cells"), std::string::npos)
      << this->Messages->Warnings[0];
    EXPECT_NE(this->Messages->Warnings[0].find("the output is empty"), std::string::npos);
    this->ExpectEmptyOutputs();
    EXPECT_TRUE(Snapshot(input) == before) << "the input was modified";
  }
}

TEST_P(FilterSkeleton, NaNCoordinatesAreAnError)
{
  auto grid = MakeTwoTets();
  grid->GetPoints()->SetPoint(4, NaN, 1, 1);
  const Snapshot before(grid);
  EXPECT_EQ(this->Run(grid), 0);
  this->ExpectOneError("1 point of the input has NaN or infinite coordinates");
  this->ExpectEmptyOutputs();
  EXPECT_TRUE(Snapshot(grid) == before) << "the input was modified";
}

TEST_P(FilterSkeleton, PointIdOutOfRangeIsAnError)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 1, 2, 3, 9 } } });
  EXPECT_EQ(this->Run(grid), 0);
  this->ExpectOneError("cell 1 of the input refers to point 9, but there are 4 points");
  this->ExpectEmptyOutputs();
}

TEST_P(FilterSkeleton, TetWithThreePointsIsAnError)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 1, 2, 3 } } });
  EXPECT_EQ(this->Run(grid), 0);
  this->ExpectOneError("cell 1 of the input is a VTK_TETRA with 3 points instead of 4");
  this->ExpectEmptyOutputs();
}

// A point or cell array of another length than the points or cells: a short
// one would be read past its end, a long one passed on to a mesh it does not
// fit.
TEST_P(FilterSkeleton, AttributeArrayOfTheWrongLengthIsAnError)
{
  for (const vtkIdType tuples : { 1, 7 })
  {
    for (const bool onPoints : { true, false })
    {
      this->Messages->Errors.clear();
      auto grid = MakeTwoTets();
      vtkNew<vtkDoubleArray> array;
      array->SetName("Temperature");
      array->SetNumberOfTuples(tuples);
      array->Fill(20);
      if (onPoints)
      {
        grid->GetPointData()->AddArray(array);
      }
      else
      {
        grid->GetCellData()->AddArray(array);
      }
      EXPECT_EQ(this->Run(grid), 0);
      const std::string values = tuples == 1 ? "1 value" : "7 values";
      this->ExpectOneError(onPoints
          ? "the point array 'Temperature' of the input has " + values + " for 5 points"
          : "the cell array 'Temperature' of the input has " + values + " for 2 cells");
      this->ExpectEmptyOutputs();
    }
  }
}

// The filters with a floating-point property (Hex To Tet has none).
class FilterProperties : public FilterSkeleton
{
};

TEST_P(FilterProperties, NaNPropertyIsAnError)
{
  EXPECT_EQ(this->Run(MakeTwoTets(), GetParam().SetNaNProperty), 0);
  this->ExpectOneError(std::string(GetParam().NaNProperty) + " must be a number in [");
  this->ExpectEmptyOutputs();
}

TEST_P(FilterSkeleton, MissingInputIsAnErrorNotACrash)
{
  EXPECT_EQ(this->Run(nullptr), 0);
  EXPECT_FALSE(this->Messages->Errors.empty() && this->PipelineMessages->Errors.empty());
}

TEST_P(FilterSkeleton, CellsItDoesNotReadAreNamed)
{
  auto grid = MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TRIANGLE, { 0, 1, 2 } } });
  if (GetParam().RefusesTriangles)
  {
    EXPECT_EQ(this->Run(grid), 0);
    this->ExpectOneError("the input has 1 VTK_TRIANGLE cell; this filter reads");
    this->ExpectEmptyOutputs();
  }
  else
  {
    EXPECT_EQ(this->Run(grid), 1);
    EXPECT_TRUE(this->Messages->Errors.empty()) << this->Messages->AllErrors();
    EXPECT_NE(this->Messages->AllWarnings().find("1 VTK_TRIANGLE cell"), std::string::npos)
      << this->Messages->AllWarnings();
  }
}

const auto RowName = [](const ::testing::TestParamInfo<FilterCase>& info) {
  return std::string(info.param.Name);
};
INSTANTIATE_TEST_SUITE_P(AllFilters, FilterSkeleton, ::testing::ValuesIn(Filters), RowName);

std::vector<FilterCase> FiltersWithFloatProperties()
{
  std::vector<FilterCase> rows;
  for (const FilterCase& row : Filters)
  {
    if (row.SetNaNProperty)
    {
      rows.push_back(row);
    }
  }
  return rows;
}
INSTANTIATE_TEST_SUITE_P(
  AllFilters, FilterProperties, ::testing::ValuesIn(FiltersWithFloatProperties()), RowName);
