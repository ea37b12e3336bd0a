// Helpers shared by the filter tests: hand-built grids and a recorder of the
// errors and warnings a VTK object reports.
#pragma once

#include "vtkAbstractArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkCommand.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLDataElement.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtkXMLUtilities.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace femorph_test
{

/// A grid from points and (type, point ids) cells.
inline vtkSmartPointer<vtkUnstructuredGrid> MakeGrid(
  const std::vector<std::array<double, 3>>& points,
  const std::vector<std::pair<int, std::vector<vtkIdType>>>& cells)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (const auto& p : points)
  {
    pts->InsertNextPoint(p.data());
  }
  grid->SetPoints(pts);
  grid->AllocateExact(static_cast<vtkIdType>(cells.size()), 8);
  for (const auto& cell : cells)
  {
    grid->InsertNextCell(
      cell.first, static_cast<vtkIdType>(cell.second.size()), cell.second.data());
  }
  return grid;
}

/// Two positive tets sharing the face (1, 2, 3): apexes 0 (below) and 4
/// (above the face's plane x + y + z = 1).
inline vtkSmartPointer<vtkUnstructuredGrid> MakeTwoTets()
{
  return MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 } },
    { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 1, 3, 2 } } });
}

/// Records the messages of the ErrorEvent and WarningEvent of the objects it
/// observes (and keeps them off the output window).
class MessageRecorder : public vtkCommand
{
public:
  static MessageRecorder* New() { return new MessageRecorder; }

  void Observe(vtkObject* object)
  {
    object->AddObserver(vtkCommand::ErrorEvent, this);
    object->AddObserver(vtkCommand::WarningEvent, this);
  }

  void Execute(vtkObject*, unsigned long event, void* callData) override
  {
    const std::string text = callData ? static_cast<const char*>(callData) : "";
    (event == vtkCommand::ErrorEvent ? this->Errors : this->Warnings).push_back(text);
  }

  std::string AllErrors() const { return Join(this->Errors); }
  std::string AllWarnings() const { return Join(this->Warnings); }

  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;

private:
  static std::string Join(const std::vector<std::string>& list)
  {
    std::string all;
    for (const auto& s : list)
    {
      all += s + "\n";
    }
    return all;
  }
};


/// The SourceProxy of class `className` in the plugin's XML at `path`
/// (root keeps the document alive), after checking its name, label and
/// menu category (FEMorph); null, with test failures, when it is not there.
inline vtkXMLDataElement* FindFilterProxy(const std::string& path, const char* className,
  const char* name, const char* label, vtkSmartPointer<vtkXMLDataElement>& root)
{
  root.TakeReference(vtkXMLUtilities::ReadElementFromFile(path.c_str()));
  vtkXMLDataElement* group = root ? root->LookupElementWithName("ProxyGroup") : nullptr;
  vtkXMLDataElement* proxy =
    group ? group->FindNestedElementWithNameAndAttribute("SourceProxy", "class", className) : nullptr;
  if (!proxy)
  {
    ADD_FAILURE() << "no SourceProxy of class " << className << " in " << path;
    return nullptr;
  }
  EXPECT_STREQ(proxy->GetAttribute("name"), name);
  EXPECT_STREQ(proxy->GetAttribute("label"), label);
  vtkXMLDataElement* hints = proxy->FindNestedElementWithName("Hints");
  vtkXMLDataElement* menu = hints ? hints->FindNestedElementWithName("ShowInMenu") : nullptr;
  EXPECT_TRUE(menu && std::string(menu->GetAttribute("category") ? menu->GetAttribute("category") : "") == "FEMorph")
    << className << " is not in the FEMorph menu";
  return proxy;
}


/// What a filter property of the plugin's XML must say: its default, its
/// range (checked when it has a range domain) and whether it is advanced.
struct XmlProperty
{
  double Default = 0;
  double Min = 0, Max = 0;
  bool Advanced = false;
  /// A plain entry in ParaView's panel, not a slider: ParaView draws a
  /// slider for an IntRangeDomain with both a min and a max
  /// (pqIntVectorPropertyWidget), so the domain gives the min only and the
  /// documentation states the max (issue 29: seeds and iteration counts).
  bool Entry = false;
};

/// Every property of `proxy` that has a command (inputs aside) is in
/// `expected` by command and vice versa; each has the expected default
/// (default_values), visibility, range (a Double/IntRangeDomain, else a
/// Boolean or Enumeration domain) and a Documentation. `extra` checks more
/// of each property. String properties are in `strings` with their
/// default (a StringVectorProperty needs no domain).
inline void CheckFilterProperties(vtkXMLDataElement* proxy,
  const std::map<std::string, XmlProperty>& expected,
  const std::function<void(const std::string&, vtkXMLDataElement*)>& extra = {},
  const std::map<std::string, std::string>& strings = {})
{
  std::set<std::string> seen;
  for (int i = 0; i < proxy->GetNumberOfNestedElements(); ++i)
  {
    vtkXMLDataElement* e = proxy->GetNestedElement(i);
    const char* command = e->GetAttribute("command");
    if (!command || std::string(e->GetName()) == "InputProperty")
    {
      continue;
    }
    const auto text = strings.find(command);
    if (text != strings.end())
    {
      const char* value = e->GetAttribute("default_values");
      EXPECT_EQ(std::string(value ? value : ""), text->second) << command;
      EXPECT_EQ(std::string(e->GetName()), "StringVectorProperty") << command;
      EXPECT_NE(e->FindNestedElementWithName("Documentation"), nullptr) << command;
      seen.insert(command);
      continue;
    }
    auto it = expected.find(command);
    if (it == expected.end())
    {
      ADD_FAILURE() << "add a default check for " << command;
      continue;
    }
    seen.insert(command);
    const XmlProperty& x = it->second;
    const char* value = e->GetAttribute("default_values");
    EXPECT_TRUE(value && std::stod(value) == x.Default)
      << command << ": default " << (value ? value : "missing") << ", C++ " << x.Default;
    const char* visibility = e->GetAttribute("panel_visibility");
    EXPECT_EQ(visibility && std::string(visibility) == "advanced", x.Advanced) << command;
    vtkXMLDataElement* range = e->FindNestedElementWithName("DoubleRangeDomain");
    if (!range)
    {
      range = e->FindNestedElementWithName("IntRangeDomain");
    }
    if (range)
    {
      EXPECT_EQ(std::stod(range->GetAttribute("min")), x.Min) << command;
      const char* max = range->GetAttribute("max");
      if (x.Entry)
      {
        EXPECT_EQ(max, nullptr) << command << ": a max makes ParaView draw a slider";
        vtkXMLDataElement* doc = e->FindNestedElementWithName("Documentation");
        const char* text = doc ? doc->GetCharacterData() : nullptr;
        const std::string maxText = std::to_string(static_cast<long long>(x.Max));
        EXPECT_TRUE(text && std::string(text).find(maxText) != std::string::npos)
          << command << ": the documentation should state the maximum " << maxText;
      }
      else
      {
        EXPECT_TRUE(max && std::stod(max) == x.Max) << command;
      }
    }
    else
    {
      EXPECT_TRUE(e->FindNestedElementWithName("BooleanDomain") ||
        e->FindNestedElementWithName("EnumerationDomain"))
        << command << " has no domain";
    }
    EXPECT_NE(e->FindNestedElementWithName("Documentation"), nullptr) << command;
    if (extra)
    {
      extra(command, e);
    }
  }
  EXPECT_EQ(seen.size(), expected.size() + strings.size());
}


/// A grid's points, connectivity, arrays (names, sizes, modification times)
/// and modification time, to check that a filter left its input as it was.
struct Snapshot
{
  std::vector<double> Coordinates;
  std::vector<vtkIdType> Connectivity;
  std::vector<std::string> Arrays;
  vtkMTimeType MTime = 0;

  explicit Snapshot(vtkUnstructuredGrid* grid)
  {
    for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
    {
      double p[3];
      grid->GetPoint(i, p);
      this->Coordinates.insert(this->Coordinates.end(), p, p + 3);
    }
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      grid->GetCellPoints(c, ids);
      this->Connectivity.push_back(grid->GetCellType(c));
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        this->Connectivity.push_back(ids->GetId(k));
      }
    }
    for (vtkFieldData* fd : { static_cast<vtkFieldData*>(grid->GetPointData()),
           static_cast<vtkFieldData*>(grid->GetCellData()), grid->GetFieldData() })
    {
      this->Arrays.push_back("|");
      for (int a = 0; a < fd->GetNumberOfArrays(); ++a)
      {
        vtkAbstractArray* array = fd->GetAbstractArray(a);
        this->Arrays.push_back(std::string(array->GetName() ? array->GetName() : "") + ":" +
          std::to_string(array->GetNumberOfTuples()) + ":" + std::to_string(array->GetMTime()));
      }
    }
    this->MTime = grid->GetMTime();
  }

  bool operator==(const Snapshot& o) const
  {
    // NaN coordinates compare by bits.
    if (this->Coordinates.size() != o.Coordinates.size())
    {
      return false;
    }
    for (std::size_t i = 0; i < this->Coordinates.size(); ++i)
    {
      const double a = this->Coordinates[i], b = o.Coordinates[i];
      if (!(a == b || (std::isnan(a) && std::isnan(b))))
      {
        return false;
      }
    }
    return this->Connectivity == o.Connectivity && this->Arrays == o.Arrays &&
      this->MTime == o.MTime;
  }
};

/// The segmentation arrays of FEMorph Segment for `faceRegions` (per cell,
/// the region of the face opposite local vertex i, -1 interior): every
/// region of unknown type (nothing fitted), no curves. For tests that need
/// regions but not their fits.
inline void AddUnknownSegmentation(
  vtkUnstructuredGrid* grid, const std::vector<std::array<int, 4>>& faceRegions)
{
  int numRegions = 0;
  vtkNew<vtkIntArray> faceRegion;
  faceRegion->SetName("FaceRegion");
  faceRegion->SetNumberOfComponents(4);
  for (const auto& regions : faceRegions)
  {
    faceRegion->InsertNextTypedTuple(regions.data());
    for (int r : regions)
    {
      numRegions = std::max(numRegions, r + 1);
    }
  }
  grid->GetCellData()->AddArray(faceRegion);
  vtkFieldData* fd = grid->GetFieldData();
  auto add = [fd](vtkDataArray* a, const char* name, int components, vtkIdType tuples) {
    a->SetName(name);
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(tuples);
    a->Fill(0);
    fd->AddArray(a);
  };
  vtkNew<vtkIntArray> regionType, regionConvexity, curveType;
  vtkNew<vtkDoubleArray> regionParameters, curveParameters;
  vtkNew<vtkUnsignedCharArray> curveClosed;
  vtkNew<vtkIdTypeArray> curveVertices, curveOffsets;
  add(regionType, "RegionType", 1, numRegions);
  regionType->Fill(5); // unknown
  add(regionParameters, "RegionParameters", 12, numRegions);
  add(regionConvexity, "RegionConvexity", 1, numRegions);
  add(curveType, "CurveType", 1, 0);
  add(curveParameters, "CurveParameters", 20, 0);
  add(curveClosed, "CurveClosed", 1, 0);
  add(curveVertices, "CurveVertices", 1, 0);
  add(curveOffsets, "CurveOffsets", 1, 1);
}

/// A .vtu of Data/ by its path relative to Data/; null when it is missing.
inline vtkSmartPointer<vtkUnstructuredGrid> ReadPart(const std::string& name)
{
  const std::string path = std::string(FEMORPH_DATA_DIR) + "/" + name;
  if (!std::ifstream(path).good())
  {
    return nullptr;
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

} // namespace femorph_test
