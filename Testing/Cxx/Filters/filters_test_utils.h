// Helpers shared by the filter tests: hand-built grids and a recorder of the
// errors and warnings a VTK object reports.
#pragma once

#include "vtkCellType.h"
#include "vtkCommand.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

#include <array>
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

} // namespace femorph_test
