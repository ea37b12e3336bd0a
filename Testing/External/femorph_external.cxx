// A VTK program that uses FEMorph's filters from an installed FEMorph
// (Testing/External/CMakeLists.txt): reads a tet mesh, runs
// vtkFEMorphMeshQuality and vtkFEMorphSegment and checks their arrays.
// Usage: femorph_external part.vtu   (exit status 0 when every check holds)
#include "vtkFEMorphMeshQuality.h"
#include "vtkFEMorphSegment.h"

#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkTable.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cstdio>
#include <set>

namespace
{
int failures = 0;

void check(bool ok, const char* what)
{
  if (!ok)
  {
    std::fprintf(stderr, "FAILED: %s\n", what);
    ++failures;
  }
}

double field_value(vtkFieldData* fd, const char* name)
{
  vtkDataArray* array = fd ? fd->GetArray(name) : nullptr;
  check(array != nullptr && array->GetNumberOfTuples() == 1, name);
  return array && array->GetNumberOfTuples() == 1 ? array->GetTuple1(0) : -1.0;
}
}

int main(int argc, char* argv[])
{
  if (argc != 2)
  {
    std::fprintf(stderr, "usage: %s part.vtu\n", argv[0]);
    return 2;
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(argv[1]);
  reader->Update();
  const vtkIdType cells = reader->GetOutput()->GetNumberOfCells();
  const vtkIdType points = reader->GetOutput()->GetNumberOfPoints();
  if (cells == 0)
  {
    std::fprintf(stderr, "FAILED: %s has no cells\n", argv[1]);
    return 1;
  }

  // Mesh Quality: a Stretch per cell, in (0, 1] on a valid part, and the summary.
  vtkNew<vtkFEMorphMeshQuality> quality;
  quality->SetInputConnection(reader->GetOutputPort());
  quality->Update();
  vtkDataArray* stretch = quality->GetOutput()->GetCellData()->GetArray("Stretch");
  vtkUnstructuredGrid* q = quality->GetOutput();
  check(stretch != nullptr, "cell array Stretch");
  if (stretch)
  {
    check(stretch->GetNumberOfTuples() == cells, "one Stretch per cell");
    double range[2];
    stretch->GetRange(range);
    check(range[0] > 0.0 && range[1] <= 1.0 + 1e-12, "Stretch in (0, 1]");
    check(field_value(q->GetFieldData(), "StretchMin") == range[0], "StretchMin = min Stretch");
  }
  check(field_value(q->GetFieldData(), "TetraCount") == static_cast<double>(cells), "TetraCount");
  check(field_value(q->GetFieldData(), "InvertedCount") == 0.0, "InvertedCount 0");

  // Segment: FaceRegion (4 per tet) and VertexClass, as many regions as the
  // Regions table has rows, each used by some boundary face.
  vtkNew<vtkFEMorphSegment> segment;
  segment->SetInputConnection(reader->GetOutputPort());
  segment->Update();
  vtkUnstructuredGrid* mesh = segment->GetOutput();
  vtkDataArray* faceRegion = mesh->GetCellData()->GetArray("FaceRegion");
  vtkDataArray* vertexClass = mesh->GetPointData()->GetArray("VertexClass");
  auto* regions = vtkTable::SafeDownCast(segment->GetOutputDataObject(2));
  check(faceRegion != nullptr && faceRegion->GetNumberOfComponents() == 4 &&
      faceRegion->GetNumberOfTuples() == cells,
    "cell array FaceRegion, 4 components");
  check(vertexClass != nullptr && vertexClass->GetNumberOfTuples() == points,
    "point array VertexClass");
  check(regions != nullptr && regions->GetNumberOfRows() > 0, "Regions table rows > 0");
  if (faceRegion && regions)
  {
    std::set<int> used;
    vtkIdType boundaryFaces = 0;
    for (vtkIdType t = 0; t < cells; ++t)
    {
      for (int f = 0; f < 4; ++f)
      {
        const int r = static_cast<int>(faceRegion->GetComponent(t, f));
        if (r >= 0)
        {
          used.insert(r);
          ++boundaryFaces;
        }
      }
    }
    check(boundaryFaces > 0, "boundary faces with a region");
    check(static_cast<vtkIdType>(used.size()) == regions->GetNumberOfRows() &&
        !used.empty() && *used.rbegin() == regions->GetNumberOfRows() - 1,
      "FaceRegion uses regions 0 .. rows-1");
    std::printf("%s: %lld tets, %lld boundary faces in %lld regions\n", argv[1],
      static_cast<long long>(cells), static_cast<long long>(boundaryFaces),
      static_cast<long long>(regions->GetNumberOfRows()));
  }
  if (failures == 0)
  {
    std::printf("OK: FEMorph from the installed tree\n");
  }
  return failures == 0 ? 0 : 1;
}
