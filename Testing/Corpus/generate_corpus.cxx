// generate_corpus: writes the malformed-input corpus into a folder:
// a few hundred .vtu files, each a valid base part with one fault, and
// manifest.tsv (corpus_manifest.h) saying how run_corpus judges each case.
//
// Usage: generate_corpus --data <Data folder> --out <folder> [--big-cells N]
//
// Bases (each written as a valid case too): two hand-made tetrahedra; a
// 4 x 4 x 4 block of 6-tet cubes (384 tets); Data/boss_block.vtu (38,482
// tets); a jittered 27^3 lattice (118,098 tets: over-reads of short arrays
// only crash on large ones); Data/hex/hex_block.vtu (hexahedra). FEMorph
// Segment runs once on each tetrahedral base, so the bases carry the
// segmentation arrays it writes (FaceRegion, VertexClass and the region and
// curve field arrays), and the cases damage those.
#include "corpus_manifest.h"

#include "vtkFEMorphSegment.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkLongLongArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkShortArray.h"
#include "vtkSignedCharArray.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedIntArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtkXMLUnstructuredGridWriter.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using femorph_corpus::CaseEntry;

namespace
{
using Grid = vtkSmartPointer<vtkUnstructuredGrid>;

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();
constexpr double Inf = std::numeric_limits<double>::infinity();
constexpr int IntMax = std::numeric_limits<int>::max();
constexpr int IntMin = std::numeric_limits<int>::min();

// The arrays FEMorph Segment writes into field data (DESIGN.md).
const char* const FieldArrays[] = { "RegionType", "RegionParameters", "RegionConvexity",
  "CurveType", "CurveParameters", "CurveClosed", "CurveVertices", "CurveOffsets" };

Grid Copy(vtkUnstructuredGrid* grid)
{
  Grid copy = Grid::New();
  copy->DeepCopy(grid);
  return copy;
}

/// A copy of `grid`'s points in their own precision (vtkPoints::DeepCopy into
/// a new vtkPoints would convert them to float and lose 1e-300 and 1e300).
vtkSmartPointer<vtkPoints> CopyPoints(vtkUnstructuredGrid* grid)
{
  auto copy = vtkSmartPointer<vtkPoints>::New();
  copy->SetDataType(grid->GetPoints()->GetDataType());
  copy->DeepCopy(grid->GetPoints());
  if (copy->GetDataType() != VTK_DOUBLE)
  {
    std::cerr << "generate_corpus: the bases' points must be double\n";
    std::exit(1);
  }
  return copy;
}

Grid MakeGrid(const std::vector<std::array<double, 3>>& points,
  const std::vector<std::pair<int, std::vector<vtkIdType>>>& cells)
{
  Grid grid = Grid::New();
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
    grid->InsertNextCell(cell.first, static_cast<vtkIdType>(cell.second.size()), cell.second.data());
  }
  return grid;
}

double Orient(const double* a, const double* b, const double* c, const double* d)
{
  const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const double w[3] = { d[0] - a[0], d[1] - a[1], d[2] - a[2] };
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
    u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/// An n x n x n block of unit cubes, each split into the 6 tetrahedra around
/// its main diagonal (conforming), positively oriented; interior points moved
/// by up to `jitter` (fraction of the spacing) in each coordinate.
Grid MakeLattice(int n, double jitter, unsigned seed)
{
  const int m = n + 1;
  auto id = [m](int i, int j, int k) { return static_cast<vtkIdType>((k * m + j) * m + i); };
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> offset(-jitter, jitter);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(m) * m * m);
  for (int k = 0; k < m; ++k)
  {
    for (int j = 0; j < m; ++j)
    {
      for (int i = 0; i < m; ++i)
      {
        double p[3] = { double(i), double(j), double(k) };
        const bool interior = i > 0 && j > 0 && k > 0 && i < n && j < n && k < n;
        if (interior && jitter > 0)
        {
          for (double& x : p)
          {
            x += offset(random);
          }
        }
        points->SetPoint(id(i, j, k), p);
      }
    }
  }
  Grid grid = Grid::New();
  grid->SetPoints(points);
  grid->AllocateExact(6 * static_cast<vtkIdType>(n) * n * n, 4);
  // Kuhn's subdivision: the paths from corner 0 to corner 7 along the axes.
  const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 },
    { 2, 1, 0 } };
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        for (const auto& perm : perms)
        {
          int c[3] = { i, j, k };
          vtkIdType tet[4];
          tet[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s)
          {
            ++c[perm[s]];
            tet[s + 1] = id(c[0], c[1], c[2]);
          }
          double p[4][3];
          for (int v = 0; v < 4; ++v)
          {
            points->GetPoint(tet[v], p[v]);
          }
          if (Orient(p[0], p[1], p[2], p[3]) < 0)
          {
            std::swap(tet[2], tet[3]);
          }
          grid->InsertNextCell(VTK_TETRA, 4, tet);
        }
      }
    }
  }
  return grid;
}

/// `grid` with FEMorph Segment's arrays (Segment's first output, copied).
Grid Segmented(vtkUnstructuredGrid* grid, const std::string& name)
{
  vtkNew<vtkFEMorphSegment> segment;
  segment->SetInputData(grid);
  segment->Update();
  Grid out = Copy(segment->GetMeshOutput());
  if (!out->GetFieldData()->GetArray("RegionType") || !out->GetCellData()->GetArray("FaceRegion"))
  {
    std::cerr << "generate_corpus: FEMorph Segment gave no segmentation arrays on the base " << name
              << "\n";
    std::exit(1);
  }
  out->GetFieldData()->RemoveArray("SegmentationTimes");
  return out;
}

Grid ReadVtu(const std::string& path)
{
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  if (reader->GetErrorCode() != 0 || reader->GetOutput()->GetNumberOfCells() == 0)
  {
    std::cerr << "generate_corpus: cannot read " << path << "\n";
    std::exit(1);
  }
  return Copy(reader->GetOutput());
}

/// Rebuilds the cells of `grid`: `edit` sees each cell (its type and point
/// ids, which it may change) and returns false to drop it. Cell data follows
/// the kept cells. Polyhedra are not supported (the bases have none).
void EditCells(vtkUnstructuredGrid* grid,
  const std::function<bool(vtkIdType, int&, std::vector<vtkIdType>&)>& edit)
{
  vtkNew<vtkCellArray> cells;
  std::vector<int> types;
  std::vector<vtkIdType> kept;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    std::vector<vtkIdType> pts(ids->begin(), ids->end());
    int type = grid->GetCellType(c);
    if (!edit(c, type, pts))
    {
      continue;
    }
    cells->InsertNextCell(static_cast<vtkIdType>(pts.size()), pts.data());
    types.push_back(type);
    kept.push_back(c);
  }
  if (static_cast<vtkIdType>(kept.size()) != grid->GetNumberOfCells())
  {
    vtkNew<vtkCellData> data;
    data->CopyAllocate(grid->GetCellData(), static_cast<vtkIdType>(kept.size()));
    for (std::size_t i = 0; i < kept.size(); ++i)
    {
      data->CopyData(grid->GetCellData(), kept[i], static_cast<vtkIdType>(i));
    }
    grid->GetCellData()->ShallowCopy(data);
  }
  grid->SetCells(types.data(), cells);
}

/// Appends a cell; every cell array gets a copy of tuple 0 for it (FaceRegion
/// gets -1: no region).
void AppendCell(vtkUnstructuredGrid* grid, int type, const std::vector<vtkIdType>& pts)
{
  grid->InsertNextCell(type, static_cast<vtkIdType>(pts.size()), pts.data());
  vtkCellData* cd = grid->GetCellData();
  for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = cd->GetAbstractArray(a);
    array->InsertNextTuple(0, array);
    if (array->GetName() && std::string(array->GetName()) == "FaceRegion")
    {
      if (vtkDataArray* d = vtkDataArray::SafeDownCast(array))
      {
        for (int k = 0; k < d->GetNumberOfComponents(); ++k)
        {
          d->SetComponent(d->GetNumberOfTuples() - 1, k, -1);
        }
      }
    }
  }
}

/// Appends points; every point array gets copies of tuple 0.
vtkIdType AppendPoints(vtkUnstructuredGrid* grid, const std::vector<std::array<double, 3>>& points)
{
  const vtkIdType first = grid->GetNumberOfPoints();
  for (const auto& p : points)
  {
    grid->GetPoints()->InsertNextPoint(p.data());
  }
  vtkPointData* pd = grid->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = pd->GetAbstractArray(a);
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      array->InsertNextTuple(0, array);
    }
  }
  return first;
}

/// A numeric copy of `source` as VTK type `type` (e.g. VTK_FLOAT), same name.
vtkSmartPointer<vtkDataArray> Converted(vtkDataArray* source, int type)
{
  vtkSmartPointer<vtkDataArray> out;
  out.TakeReference(vtkDataArray::CreateDataArray(type));
  out->SetName(source->GetName());
  out->SetNumberOfComponents(source->GetNumberOfComponents());
  out->SetNumberOfTuples(source->GetNumberOfTuples());
  for (vtkIdType i = 0; i < source->GetNumberOfTuples(); ++i)
  {
    for (int k = 0; k < source->GetNumberOfComponents(); ++k)
    {
      out->SetComponent(i, k, source->GetComponent(i, k));
    }
  }
  return out;
}

/// A copy of `source` with `components` components: the first ones kept,
/// new ones 0.
vtkSmartPointer<vtkDataArray> Reshaped(vtkDataArray* source, int components)
{
  vtkSmartPointer<vtkDataArray> out;
  out.TakeReference(source->NewInstance());
  out->SetName(source->GetName());
  out->SetNumberOfComponents(components);
  out->SetNumberOfTuples(source->GetNumberOfTuples());
  for (vtkIdType i = 0; i < source->GetNumberOfTuples(); ++i)
  {
    for (int k = 0; k < components; ++k)
    {
      out->SetComponent(i, k, k < source->GetNumberOfComponents() ? source->GetComponent(i, k) : 0);
    }
  }
  return out;
}

/// A copy of `source` with `tuples` tuples: the first ones kept, new ones
/// copies of the last.
vtkSmartPointer<vtkAbstractArray> Resized(vtkAbstractArray* source, vtkIdType tuples)
{
  vtkSmartPointer<vtkAbstractArray> out;
  out.TakeReference(source->NewInstance());
  out->SetName(source->GetName());
  out->SetNumberOfComponents(source->GetNumberOfComponents());
  out->SetNumberOfTuples(tuples);
  for (vtkIdType i = 0; i < tuples; ++i)
  {
    const vtkIdType from = std::min(i, source->GetNumberOfTuples() - 1);
    if (from >= 0)
    {
      out->SetTuple(i, from, source);
    }
  }
  return out;
}

/// The same values as strings ("3", "-1", ...).
vtkSmartPointer<vtkStringArray> AsStrings(vtkDataArray* source)
{
  auto out = vtkSmartPointer<vtkStringArray>::New();
  out->SetName(source->GetName());
  out->SetNumberOfComponents(source->GetNumberOfComponents());
  out->SetNumberOfTuples(source->GetNumberOfTuples());
  for (vtkIdType i = 0; i < source->GetNumberOfTuples(); ++i)
  {
    for (int k = 0; k < source->GetNumberOfComponents(); ++k)
    {
      std::ostringstream text;
      text << source->GetComponent(i, k);
      out->SetValue(i * source->GetNumberOfComponents() + k, text.str());
    }
  }
  return out;
}

/// A cell and face of `grid` whose FaceRegion is a region (>= 0), searched
/// from the middle of the cell list (so that a truncated copy ends before it).
std::pair<vtkIdType, int> BoundaryFace(vtkUnstructuredGrid* grid)
{
  vtkDataArray* regions = grid->GetCellData()->GetArray("FaceRegion");
  const vtkIdType n = grid->GetNumberOfCells();
  for (vtkIdType step = 0; step < n; ++step)
  {
    const vtkIdType c = (n / 2 + step) % n;
    for (int f = 0; f < 4; ++f)
    {
      if (regions->GetComponent(c, f) >= 0)
      {
        return { c, f };
      }
    }
  }
  return { 0, 0 };
}

/// A cell and face whose FaceRegion is -1 (an interior face).
std::pair<vtkIdType, int> InteriorFace(vtkUnstructuredGrid* grid)
{
  vtkDataArray* regions = grid->GetCellData()->GetArray("FaceRegion");
  const vtkIdType n = grid->GetNumberOfCells();
  for (vtkIdType step = 0; step < n; ++step)
  {
    const vtkIdType c = (n / 2 + step) % n;
    for (int f = 0; f < 4; ++f)
    {
      if (regions->GetComponent(c, f) < 0)
      {
        return { c, f };
      }
    }
  }
  return { 0, 0 };
}

/// A point used by cells that lies inside the part (VertexClass 0), from
/// the middle of the point list; the first point when there is none.
vtkIdType InnerPoint(vtkUnstructuredGrid* grid)
{
  vtkDataArray* classes = grid->GetPointData()->GetArray("VertexClass");
  const vtkIdType n = grid->GetNumberOfPoints();
  for (vtkIdType step = 0; classes && step < n; ++step)
  {
    const vtkIdType p = (n / 2 + step) % n;
    if (classes->GetComponent(p, 0) == 0)
    {
      return p;
    }
  }
  return 0;
}

/// "1e+30" style, for case names: letters and digits only.
std::string Tag(double value)
{
  if (std::isnan(value))
  {
    return "nan";
  }
  if (std::isinf(value))
  {
    return value > 0 ? "inf" : "neginf";
  }
  if (value == IntMax)
  {
    return "intmax";
  }
  if (value == IntMax - 1.0)
  {
    return "intmax1";
  }
  if (value == IntMin)
  {
    return "intmin";
  }
  std::ostringstream text;
  text << value;
  std::string tag;
  for (char ch : text.str())
  {
    tag += ch == '-' ? 'm' : ch == '.' ? 'p' : ch == '+' ? 'p' : ch;
  }
  return tag;
}

std::string Text(double value)
{
  std::ostringstream text;
  text << value;
  return text.str();
}

struct Base
{
  std::string Name;
  Grid Mesh;
  int Timeout = 20;
  vtkIdType Regions = 0; // RegionType tuples (0 without segmentation)
};

class Corpus
{
public:
  explicit Corpus(std::string folder)
    : Folder(std::move(folder))
  {
  }

  /// Writes `grid` as <name>.vtu and records the case.
  void Add(CaseEntry c, vtkUnstructuredGrid* grid)
  {
    for (char& ch : c.Name)
    {
      // Names are file names and single tokens of the report.
      if (ch == ' ' || ch == '/' || ch == '\t')
      {
        ch = '_';
      }
    }
    c.File = c.Name + ".vtu";
    this->Write(grid, c.File);
    for (const CaseEntry& other : this->Cases)
    {
      if (other.Name == c.Name)
      {
        std::cerr << "generate_corpus: two cases named " << c.Name << "\n";
        std::exit(1);
      }
    }
    this->Cases.push_back(c);
  }

  /// Writes a Reference input once; returns its file name.
  std::string AddReference(const std::string& name, vtkUnstructuredGrid* grid)
  {
    const std::string file = "reference_" + name + ".vtu";
    this->Write(grid, file);
    return file;
  }

  void WriteManifest() const
  {
    std::ofstream out(this->Folder + "/manifest.tsv");
    femorph_corpus::WriteManifestHeader(out);
    for (const CaseEntry& c : this->Cases)
    {
      femorph_corpus::WriteManifestLine(out, c);
    }
  }

  std::size_t Size() const { return this->Cases.size(); }

private:
  void Write(vtkUnstructuredGrid* grid, const std::string& file)
  {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetInputData(grid);
    writer->SetFileName((this->Folder + "/" + file).c_str());
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressionLevel(1);
    if (!writer->Write())
    {
      std::cerr << "generate_corpus: cannot write " << file << "\n";
      std::exit(1);
    }
  }

  std::string Folder;
  std::vector<CaseEntry> Cases;
};

/// A case on `base`: name "<base>.<what>", the base's timeout.
CaseEntry On(const Base& base, const std::string& what, const std::string& description)
{
  CaseEntry c;
  c.Name = base.Name + "." + what;
  c.Timeout = base.Timeout;
  c.Description = description;
  return c;
}

// Who reads what (keep in step with the filters): FaceRegion, VertexClass,
// the region and curve field arrays, RegionArrayName and the Reference:
// Improve (vtkFEMorphSegmentationArrays::ReadFromMesh). Segment does not
// read the input's FaceRegion: it writes its own.
const char* const FaceRegionReaders = "Improve";
const char* const SegmentationReaders = "Improve";

//------------------------------------------------------------------------------
// FaceRegion: values, types, shapes, lengths.
void FaceRegionCases(Corpus& corpus, const Base& base, bool full)
{
  const auto face = BoundaryFace(base.Mesh);
  const double nr = static_cast<double>(base.Regions);
  auto withValue = [&](int type, double value, const std::string& what, bool everywhere) {
    Grid g = Copy(base.Mesh);
    vtkSmartPointer<vtkDataArray> regions =
      Converted(g->GetCellData()->GetArray("FaceRegion"), type);
    if (everywhere)
    {
      for (vtkIdType c = 0; c < regions->GetNumberOfTuples(); ++c)
      {
        for (int f = 0; f < 4; ++f)
        {
          if (regions->GetComponent(c, f) >= 0)
          {
            regions->SetComponent(c, f, value);
          }
        }
      }
    }
    else
    {
      regions->SetComponent(face.first, face.second, value);
    }
    g->GetCellData()->AddArray(regions);
    CaseEntry c = On(base, "FaceRegion." + what, "FaceRegion (" +
        std::string(regions->GetDataTypeAsString()) + ") " + Text(value) +
        (everywhere ? " on every boundary face" : " on one boundary face") + " (" +
        Text(nr) + " regions)" +
        (type == VTK_UNSIGNED_INT || type == VTK_UNSIGNED_CHAR
            ? "; unsigned, so every interior -1 reads as the type's maximum too"
            : ""));
    c.ReportOn = FaceRegionReaders;
    c.Expect = "FaceRegion";
    corpus.Add(c, g);
  };

  // Integer values that name no region, as int (FEMorph Segment's type).
  const double intValues[] = { double(IntMax), double(IntMax) - 1, double(IntMin), 99999, -2, nr };
  for (double v : intValues)
  {
    if (full || v == IntMax)
    {
      withValue(VTK_INT, v, "int." + Tag(v), false);
    }
  }
  if (!full)
  {
    return;
  }
  // The same and non-integers as float and double.
  const double realValues[] = { double(IntMax), double(IntMin), 99999, -2, nr, NaN, 1e30, -1e30,
    Inf, -Inf, 0.5, -0.5 };
  for (double v : realValues)
  {
    withValue(VTK_DOUBLE, v, "double." + Tag(v), false);
  }
  for (double v : { double(IntMax), 99999.0, -2.0, NaN, 1e30, Inf, 0.5 })
  {
    withValue(VTK_FLOAT, v, "float." + Tag(v), false);
  }
  // Other integer types: a value out of int's range, negative via unsigned.
  withValue(VTK_LONG_LONG, 1e12, "longlong.1e12", false);
  withValue(VTK_LONG_LONG, 4294967296.0 + 1, "longlong.2pow32p1", false);
  withValue(VTK_UNSIGNED_INT, 4294967295.0, "uint.4294967295", false);
  withValue(VTK_ID_TYPE, 99999, "idtype.99999", false);
  withValue(VTK_SHORT, 32767, "short.32767", false);
  withValue(VTK_SIGNED_CHAR, -2, "schar.m2", false);
  withValue(VTK_UNSIGNED_CHAR, 255, "uchar.255", false);
  withValue(VTK_INT, IntMax, "int.intmax.everywhere", true);
  withValue(VTK_DOUBLE, NaN, "double.nan.everywhere", true);

  // Valid values in other numeric types: accepted (a converter may read
  // them), no fault.
  for (int type : { VTK_DOUBLE, VTK_FLOAT, VTK_ID_TYPE, VTK_SHORT })
  {
    Grid g = Copy(base.Mesh);
    vtkSmartPointer<vtkDataArray> regions = Converted(g->GetCellData()->GetArray("FaceRegion"), type);
    g->GetCellData()->AddArray(regions);
    CaseEntry c = On(base, std::string("FaceRegion.valid.") + regions->GetDataTypeAsString(),
      std::string("FaceRegion with valid values as ") + regions->GetDataTypeAsString() +
        " (no fault)");
    c.ValidOn = "all";
    corpus.Add(c, g);
  }

  // Not a number array.
  {
    Grid g = Copy(base.Mesh);
    g->GetCellData()->RemoveArray("FaceRegion");
    g->GetCellData()->AddArray(AsStrings(base.Mesh->GetCellData()->GetArray("FaceRegion")));
    CaseEntry c = On(base, "FaceRegion.string", "FaceRegion as a string array (valid values as text)");
    c.ReportOn = FaceRegionReaders;
    c.Expect = "FaceRegion";
    corpus.Add(c, g);
  }
  // Component counts.
  for (int components : { 1, 3, 5, 8 })
  {
    Grid g = Copy(base.Mesh);
    g->GetCellData()->AddArray(Reshaped(g->GetCellData()->GetArray("FaceRegion"), components));
    CaseEntry c = On(base, "FaceRegion.components" + std::to_string(components),
      "FaceRegion with " + std::to_string(components) + " components instead of 4");
    c.ReportOn = FaceRegionReaders;
    c.Expect = "FaceRegion";
    corpus.Add(c, g);
  }
  // Consistency: a region on an interior face, -1 on a boundary face. Not
  // asserted (the docs do not say), only no crash and a valid output.
  {
    Grid g = Copy(base.Mesh);
    const auto inner = InteriorFace(g);
    g->GetCellData()->GetArray("FaceRegion")->SetComponent(inner.first, inner.second, 0);
    corpus.Add(On(base, "FaceRegion.region_on_interior_face",
                 "region 0 on an interior face (informational: no message required)"),
      g);
  }
  {
    Grid g = Copy(base.Mesh);
    g->GetCellData()->GetArray("FaceRegion")->SetComponent(face.first, face.second, -1);
    corpus.Add(On(base, "FaceRegion.boundary_face_without_region",
                 "-1 on a boundary face (informational: no message required)"),
      g);
  }
  // In the wrong place: point data, field data (informational).
  {
    Grid g = Copy(base.Mesh);
    vtkSmartPointer<vtkAbstractArray> regions =
      Resized(g->GetCellData()->GetArray("FaceRegion"), g->GetNumberOfPoints());
    g->GetCellData()->RemoveArray("FaceRegion");
    g->GetPointData()->AddArray(regions);
    CaseEntry c = On(base, "FaceRegion.as_point_data",
      "FaceRegion is a point array (no cell array; informational)");
    corpus.Add(c, g);
  }
}

/// FaceRegion lengths: in memory (the reader refuses them) and on disk.
void FaceRegionLengthCases(Corpus& corpus, const Base& base, bool full)
{
  const vtkIdType n = base.Mesh->GetNumberOfCells();
  auto memory = [&](const std::string& what, const std::string& recipe, const std::string& text) {
    CaseEntry c = On(base, "FaceRegion." + what, text + " (made in memory after reading)");
    c.Damage = recipe;
    c.ReportOn = FaceRegionReaders;
    c.Expect = "FaceRegion";
    corpus.Add(c, base.Mesh);
  };
  memory("short1", "truncate cell FaceRegion 1", "FaceRegion with 1 tuple for " +
      std::to_string(n) + " cells");
  memory("short_half", "truncate cell FaceRegion " + std::to_string(n / 2),
    "FaceRegion with half as many tuples as cells");
  if (!full)
  {
    return;
  }
  memory("short_by1", "truncate cell FaceRegion " + std::to_string(n - 1),
    "FaceRegion one tuple short");
  memory("empty", "truncate cell FaceRegion 0", "FaceRegion with 0 tuples");
  {
    CaseEntry c = On(base, "FaceRegion.long", "FaceRegion with 1000 tuples more than cells "
                                               "(made in memory after reading)");
    c.Damage = "extend cell FaceRegion 1000";
    c.ReportOn = FaceRegionReaders;
    c.Expect = "FaceRegion";
    corpus.Add(c, base.Mesh);
  }
  // On disk: the XML reader refuses a short cell array (error, empty
  // output) and reads only as many tuples of a long one as there are cells.
  {
    Grid g = Copy(base.Mesh);
    g->GetCellData()->AddArray(Resized(g->GetCellData()->GetArray("FaceRegion"), n / 2));
    CaseEntry c = On(base, "FaceRegion.short_on_disk",
      "FaceRegion with half the tuples in the file: the reader refuses it");
    c.Reader = "may-fail";
    corpus.Add(c, g);
  }
  {
    Grid g = Copy(base.Mesh);
    g->GetCellData()->AddArray(Resized(g->GetCellData()->GetArray("FaceRegion"), n + 10));
    CaseEntry c = On(base, "FaceRegion.long_on_disk",
      "FaceRegion with 10 tuples more in the file: the reader keeps one per cell (no fault)");
    c.ValidOn = "all";
    corpus.Add(c, g);
  }
}

//------------------------------------------------------------------------------
void VertexClassCases(Corpus& corpus, const Base& base, bool full)
{
  const vtkIdType p = InnerPoint(base.Mesh);
  auto withValue = [&](int type, double value) {
    Grid g = Copy(base.Mesh);
    vtkSmartPointer<vtkDataArray> classes =
      Converted(g->GetPointData()->GetArray("VertexClass"), type);
    classes->SetComponent(p, 0, value);
    g->GetPointData()->AddArray(classes);
    CaseEntry c = On(base, std::string("VertexClass.") + classes->GetDataTypeAsString() + "." + Tag(value),
      "VertexClass (" + std::string(classes->GetDataTypeAsString()) + ") " + Text(value) +
        " at one point (classes are 0..3)");
    c.ReportOn = SegmentationReaders;
    c.Expect = "VertexClass";
    corpus.Add(c, g);
  };
  if (full)
  {
    withValue(VTK_UNSIGNED_CHAR, 4);
    withValue(VTK_UNSIGNED_CHAR, 255);
    withValue(VTK_SIGNED_CHAR, -1);
    withValue(VTK_INT, IntMax);
    withValue(VTK_DOUBLE, NaN);
    withValue(VTK_DOUBLE, 1e30);
    withValue(VTK_FLOAT, 1.5);
    {
      Grid g = Copy(base.Mesh);
      g->GetPointData()->AddArray(Reshaped(g->GetPointData()->GetArray("VertexClass"), 2));
      CaseEntry c = On(base, "VertexClass.components2", "VertexClass with 2 components");
      c.ReportOn = SegmentationReaders;
      c.Expect = "VertexClass";
      corpus.Add(c, g);
    }
    {
      Grid g = Copy(base.Mesh);
      vtkSmartPointer<vtkStringArray> text = AsStrings(g->GetPointData()->GetArray("VertexClass"));
      g->GetPointData()->RemoveArray("VertexClass");
      g->GetPointData()->AddArray(text);
      CaseEntry c = On(base, "VertexClass.string", "VertexClass as a string array");
      c.ReportOn = SegmentationReaders;
      c.Expect = "VertexClass";
      corpus.Add(c, g);
    }
    {
      Grid g = Copy(base.Mesh);
      g->GetPointData()->RemoveArray("VertexClass");
      CaseEntry c = On(base, "VertexClass.missing",
        "no VertexClass (optional: recomputed from FaceRegion; no fault)");
      c.ValidOn = "all";
      corpus.Add(c, g);
    }
    {
      Grid g = Copy(base.Mesh);
      vtkDataArray* classes = g->GetPointData()->GetArray("VertexClass");
      for (vtkIdType i = 0; i < classes->GetNumberOfTuples(); ++i)
      {
        classes->SetComponent(i, 0, 0);
      }
      corpus.Add(On(base, "VertexClass.all_inner",
                   "VertexClass 0 (inner) everywhere, boundary points included (informational)"),
        g);
    }
    {
      CaseEntry c = On(base, "VertexClass.long", "VertexClass with 1000 tuples more than points "
                                                  "(made in memory)");
      c.Damage = "extend point VertexClass 1000";
      c.ReportOn = SegmentationReaders;
      c.Expect = "VertexClass";
      corpus.Add(c, base.Mesh);
    }
    {
      CaseEntry c = On(base, "VertexClass.empty", "VertexClass with 0 tuples (made in memory)");
      c.Damage = "truncate point VertexClass 0";
      c.ReportOn = SegmentationReaders;
      c.Expect = "VertexClass";
      corpus.Add(c, base.Mesh);
    }
  }
  CaseEntry c = On(base, "VertexClass.short1", "VertexClass with 1 tuple (made in memory)");
  c.Damage = "truncate point VertexClass 1";
  c.ReportOn = SegmentationReaders;
  c.Expect = "VertexClass";
  corpus.Add(c, base.Mesh);
}

//------------------------------------------------------------------------------
// The region and curve field arrays.
void FieldArrayCases(Corpus& corpus, const Base& base, bool full)
{
  auto add = [&](const std::string& array, const std::string& what, const std::string& text,
               const std::function<void(vtkFieldData*)>& damage) {
    Grid g = Copy(base.Mesh);
    damage(g->GetFieldData());
    CaseEntry c = On(base, array + "." + what, array + ": " + text);
    c.ReportOn = SegmentationReaders;
    c.Expect = array;
    corpus.Add(c, g);
  };
  auto field = [](vtkFieldData* fd, const std::string& name) {
    return fd->GetArray(name.c_str());
  };

  if (full)
  {
    for (const char* name : FieldArrays)
    {
      const std::string array = name;
      add(array, "missing", "missing", [&](vtkFieldData* fd) { fd->RemoveArray(name); });
      add(array, "empty", "0 tuples", [&](vtkFieldData* fd) {
        fd->AddArray(Resized(field(fd, array), 0));
      });
      add(array, "short", "one tuple short", [&](vtkFieldData* fd) {
        fd->AddArray(Resized(field(fd, array), field(fd, array)->GetNumberOfTuples() - 1));
      });
      add(array, "long", "one tuple more", [&](vtkFieldData* fd) {
        fd->AddArray(Resized(field(fd, array), field(fd, array)->GetNumberOfTuples() + 1));
      });
      add(array, "width", "one component more", [&](vtkFieldData* fd) {
        fd->AddArray(Reshaped(field(fd, array), field(fd, array)->GetNumberOfComponents() + 1));
      });
      add(array, "string", "a string array of the same values", [&](vtkFieldData* fd) {
        vtkSmartPointer<vtkStringArray> text = AsStrings(field(fd, array));
        fd->RemoveArray(name);
        fd->AddArray(text);
      });
    }
  }

  auto setValue = [&](const std::string& array, const std::string& what, int type, vtkIdType tuple,
                    int component, double value) {
    add(array, what, "value " + Text(value) + " at tuple " + std::to_string(tuple) +
        (component ? ", component " + std::to_string(component) : std::string()),
      [&](vtkFieldData* fd) {
        vtkSmartPointer<vtkDataArray> a =
          type >= 0 ? Converted(field(fd, array), type) : vtkSmartPointer<vtkDataArray>(field(fd, array));
        const vtkIdType t = tuple < 0 ? a->GetNumberOfTuples() + tuple : tuple;
        a->SetComponent(t, component, value);
        fd->AddArray(a);
      });
  };
  vtkFieldData* fd = base.Mesh->GetFieldData();
  const vtkIdType numPoints = base.Mesh->GetNumberOfPoints();
  const vtkIdType numCurveVertices = fd->GetArray("CurveVertices")->GetNumberOfTuples();
  // Codes out of range.
  if (full)
  {
    for (double v : { -1.0, 6.0, 99.0, double(IntMax) })
    {
      setValue("RegionType", Tag(v), -1, 0, 0, v);
    }
    setValue("RegionType", "double.nan", VTK_DOUBLE, 0, 0, NaN);
    setValue("RegionType", "double.2p5", VTK_DOUBLE, 0, 0, 2.5);
    for (double v : { -1.0, 3.0 })
    {
      setValue("RegionConvexity", Tag(v), -1, 0, 0, v);
    }
    for (double v : { -1.0, 8.0, double(IntMax) })
    {
      setValue("CurveType", Tag(v), -1, 0, 0, v);
    }
    setValue("CurveClosed", "2", VTK_INT, 0, 0, 2);
    setValue("CurveClosed", "m1", VTK_INT, 0, 0, -1);
    // Offsets: decreasing, past the end, not starting at 0, huge.
    setValue("CurveOffsets", "first1", -1, 0, 0, 1);
    setValue("CurveOffsets", "negative", -1, 1, 0, -5);
    setValue("CurveOffsets", "intmax", -1, 1, 0, IntMax);
    setValue("CurveOffsets", "last_short", -1, -1, 0, double(numCurveVertices - 1));
    add("CurveOffsets", "decreasing", "offsets 1 and 2 swapped (decreasing)", [&](vtkFieldData* f) {
      vtkDataArray* a = field(f, "CurveOffsets");
      const double o1 = a->GetComponent(1, 0), o2 = a->GetComponent(2, 0);
      a->SetComponent(1, 0, o2);
      a->SetComponent(2, 0, o1);
    });
    // Vertices out of range.
    setValue("CurveVertices", "m1", -1, 0, 0, -1);
    setValue("CurveVertices", "npoints", -1, 0, 0, double(numPoints));
    setValue("CurveVertices", "1e9", -1, 0, 0, 1e9);
    setValue("CurveVertices", "double.nan", VTK_DOUBLE, 0, 0, NaN);
    setValue("CurveVertices", "double.1e30", VTK_DOUBLE, 0, 0, 1e30);
    // Parameters: NaN, Inf, huge, in one tuple (region or curve 0).
    setValue("RegionParameters", "nan", -1, 0, 0, NaN);
    setValue("RegionParameters", "inf", -1, 0, 3, Inf);
    setValue("RegionParameters", "nan_last", -1, -1, 11, NaN);
    setValue("CurveParameters", "nan", -1, 0, 0, NaN);
    setValue("CurveParameters", "inf", -1, 0, 9, Inf);
  }
  else
  {
    setValue("CurveVertices", "1e9", -1, 0, 0, 1e9);
  }
  setValue("CurveOffsets", "past_end_inner", -1, 1, 0, double(numCurveVertices + 1000000));
}

/// Parameters of curved regions (boss_block: cylinders, a cone, a torus).
void CurvedRegionCases(Corpus& corpus, const Base& base)
{
  vtkDataArray* types = base.Mesh->GetFieldData()->GetArray("RegionType");
  vtkIdType cylinder = -1;
  for (vtkIdType r = 0; r < types->GetNumberOfTuples() && cylinder < 0; ++r)
  {
    if (types->GetComponent(r, 0) == 1)
    {
      cylinder = r;
    }
  }
  if (cylinder < 0)
  {
    std::cerr << "generate_corpus: no cylinder region on " << base.Name << "\n";
    std::exit(1);
  }
  // Layout (Core/segment/segmentation.h): point 0-2, axis 3-5, radius 6,
  // minor radius 7, half angle 8, convexity 9, fit RMS 10, area 11.
  auto add = [&](const std::string& what, const std::string& text,
               const std::function<void(vtkDataArray*)>& damage) {
    Grid g = Copy(base.Mesh);
    damage(g->GetFieldData()->GetArray("RegionParameters"));
    CaseEntry c = On(base, "RegionParameters.cylinder_" + what,
      "RegionParameters of cylinder region " + std::to_string(cylinder) + ": " + text);
    c.ReportOn = SegmentationReaders;
    c.Expect = "RegionParameters";
    corpus.Add(c, g);
  };
  add("nan_axis", "NaN axis", [&](vtkDataArray* p) {
    for (int k = 3; k < 6; ++k)
    {
      p->SetComponent(cylinder, k, NaN);
    }
  });
  add("zero_axis", "axis (0, 0, 0)", [&](vtkDataArray* p) {
    for (int k = 3; k < 6; ++k)
    {
      p->SetComponent(cylinder, k, 0);
    }
  });
  add("negative_radius", "radius -5", [&](vtkDataArray* p) { p->SetComponent(cylinder, 6, -5); });
  add("zero_radius", "radius 0", [&](vtkDataArray* p) { p->SetComponent(cylinder, 6, 0); });
  add("huge_radius", "radius 1e300", [&](vtkDataArray* p) { p->SetComponent(cylinder, 6, 1e300); });
  add("inf_point", "point (inf, 0, 0)", [&](vtkDataArray* p) { p->SetComponent(cylinder, 0, Inf); });
  {
    Grid g = Copy(base.Mesh);
    g->GetFieldData()->GetArray("RegionType")->SetComponent(cylinder, 0, 3);
    CaseEntry c = On(base, "RegionType.cylinder_as_sphere",
      "a cylinder region typed sphere (parameters of a cylinder; informational)");
    corpus.Add(c, g);
  }
}

//------------------------------------------------------------------------------
// Improve's RegionArrayName.
void RegionArrayCases(Corpus& corpus, const Base& base, bool full)
{
  const vtkIdType n = base.Mesh->GetNumberOfCells();
  auto mask = [&](int type, const std::string& name) {
    vtkSmartPointer<vtkDataArray> a;
    a.TakeReference(vtkDataArray::CreateDataArray(type));
    a->SetName(name.c_str());
    a->SetNumberOfTuples(n);
    for (vtkIdType c = 0; c < n; ++c)
    {
      a->SetComponent(c, 0, c % 3 == 0 ? 1 : 0);
    }
    return a;
  };
  auto add = [&](const std::string& what, const std::string& name, const std::string& text,
               const std::string& damage, const std::function<void(vtkUnstructuredGrid*)>& edit,
               bool mustReport) {
    Grid g = Copy(base.Mesh);
    edit(g);
    CaseEntry c = On(base, "RegionArray." + what, "Improve RegionArrayName '" + name + "': " + text);
    c.Region = name;
    c.Damage = damage;
    c.Filters = "Improve";
    if (what == "valid")
    {
      c.ValidOn = "Improve";
    }
    if (mustReport)
    {
      c.ReportOn = "Improve";
      c.Expect = name;
    }
    corpus.Add(c, g);
  };
  add("short", "ShortMask", "an int array truncated to 10 tuples (in memory)",
    "truncate cell ShortMask 10",
    [&](vtkUnstructuredGrid* g) { g->GetCellData()->AddArray(mask(VTK_INT, "ShortMask")); }, true);
  add("empty", "EmptyMask", "an int array of 0 tuples (in memory)", "truncate cell EmptyMask 0",
    [&](vtkUnstructuredGrid* g) { g->GetCellData()->AddArray(mask(VTK_INT, "EmptyMask")); }, true);
  if (!full)
  {
    return;
  }
  {
    add("valid", "Moved", "a valid int mask, every third cell (no fault)", "-",
      [&](vtkUnstructuredGrid* g) { g->GetCellData()->AddArray(mask(VTK_INT, "Moved")); }, false);
  }
  add("string", "TextMask", "a string array", "-",
    [&](vtkUnstructuredGrid* g) {
      vtkSmartPointer<vtkDataArray> m = mask(VTK_INT, "TextMask");
      g->GetCellData()->AddArray(AsStrings(m));
    },
    true);
  add("nan", "NanMask", "a double array with NaN in every other flagged cell", "-",
    [&](vtkUnstructuredGrid* g) {
      vtkSmartPointer<vtkDataArray> m = mask(VTK_DOUBLE, "NanMask");
      for (vtkIdType c = 0; c < n; c += 6)
      {
        m->SetComponent(c, 0, NaN);
      }
      g->GetCellData()->AddArray(m);
    },
    true);
  add("inf", "InfMask", "a double array with Inf flags", "-",
    [&](vtkUnstructuredGrid* g) {
      vtkSmartPointer<vtkDataArray> m = mask(VTK_DOUBLE, "InfMask");
      m->SetComponent(0, 0, Inf);
      g->GetCellData()->AddArray(m);
    },
    true);
  add("missing", "NoSuchArray", "no array of that name", "-", [](vtkUnstructuredGrid*) {}, true);
  add("point_data", "PointMask", "a point array, not a cell array", "-",
    [&](vtkUnstructuredGrid* g) {
      vtkNew<vtkIntArray> m;
      m->SetName("PointMask");
      m->SetNumberOfTuples(g->GetNumberOfPoints());
      m->Fill(1);
      g->GetPointData()->AddArray(m);
    },
    true);
  add("field_data", "FieldMask", "a field array of one tuple per cell, not a cell array", "-",
    [&](vtkUnstructuredGrid* g) { g->GetFieldData()->AddArray(mask(VTK_INT, "FieldMask")); }, true);
  add("components3", "VectorMask", "3 components (which one flags?)", "-",
    [&](vtkUnstructuredGrid* g) {
      vtkSmartPointer<vtkDataArray> m = mask(VTK_INT, "VectorMask");
      g->GetCellData()->AddArray(Reshaped(m, 3));
    },
    false);
  add("all_zero", "ZeroMask", "all 0 (nothing to improve: a warning, the input passed through)",
    "-",
    [&](vtkUnstructuredGrid* g) {
      vtkSmartPointer<vtkDataArray> m = mask(VTK_INT, "ZeroMask");
      m->Fill(0);
      g->GetCellData()->AddArray(m);
    },
    true);
  add("long", "LongMask", "1000 tuples more than cells (in memory)", "extend cell LongMask 1000",
    [&](vtkUnstructuredGrid* g) { g->GetCellData()->AddArray(mask(VTK_INT, "LongMask")); }, true);
}

//------------------------------------------------------------------------------
// Improve's Reference (input 1).
void ReferenceCases(Corpus& corpus, const Base& base, const Base& other, bool full)
{
  auto add = [&](const std::string& what, const std::string& text, vtkUnstructuredGrid* reference,
               const std::string& damage, const std::string& expect) {
    CaseEntry c = On(base, "Reference." + what, "Improve Reference: " + text);
    c.Reference = corpus.AddReference(base.Name + "." + what, reference);
    c.Damage = damage;
    c.Filters = "Improve";
    if (!expect.empty())
    {
      c.ReportOn = "Improve";
      c.Expect = expect;
    }
    if (reference->GetNumberOfPoints() == 0)
    {
      c.Reader = "may-fail"; // no Points element in the file
    }
    corpus.Add(c, base.Mesh);
  };
  // Short FaceRegion (in memory) and the base itself: every size.
  add("short_FaceRegion", "FaceRegion with 10 tuples (in memory)", base.Mesh,
    "ref:truncate cell FaceRegion 10", "Reference|FaceRegion");
  if (!full)
  {
    return;
  }
  {
    CaseEntry c = On(base, "Reference.valid", "Improve Reference: the input itself (no fault)");
    c.Reference = corpus.AddReference(base.Name + ".valid", base.Mesh);
    c.Filters = "Improve";
    c.ValidOn = "Improve";
    corpus.Add(c, base.Mesh);
  }
  {
    Grid r = Copy(base.Mesh);
    AppendPoints(r, { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 },
                      { 1, 1, 1 }, { 0, 1, 1 } });
    const vtkIdType p = r->GetNumberOfPoints() - 8;
    AppendCell(r, VTK_HEXAHEDRON, { p, p + 1, p + 2, p + 3, p + 4, p + 5, p + 6, p + 7 });
    add("hexahedron", "one VTK_HEXAHEDRON among the tetrahedra", r, "-", "Reference");
  }
  {
    Grid r = Copy(base.Mesh);
    double q[3];
    r->GetPoint(0, q);
    q[1] = NaN;
    r->GetPoints()->SetPoint(0, q);
    add("nan_point", "a NaN coordinate", r, "-", "Reference");
  }
  {
    Grid r = Copy(base.Mesh);
    double q[3];
    r->GetPoint(1, q);
    q[0] = Inf;
    r->GetPoints()->SetPoint(1, q);
    add("inf_point", "an infinite coordinate", r, "-", "Reference");
  }
  {
    Grid r = Copy(base.Mesh);
    r->GetCellData()->GetArray("FaceRegion")->SetComponent(BoundaryFace(r).first,
      BoundaryFace(r).second, IntMax);
    add("FaceRegion_intmax", "FaceRegion 2147483647 on one face", r, "-", "Reference|FaceRegion");
  }
  {
    Grid r = Copy(base.Mesh);
    r->GetFieldData()->GetArray("CurveOffsets")->SetComponent(1, 0, 1e9);
    add("CurveOffsets_past_end", "CurveOffsets past the end", r, "-", "Reference|CurveOffsets");
  }
  add("other_part", "another part (other points, cells and region count)", other.Mesh, "-",
    "Reference");
  {
    Grid r = Copy(base.Mesh);
    vtkDataArray* types = r->GetFieldData()->GetArray("RegionType");
    r->GetFieldData()->AddArray(Resized(types, types->GetNumberOfTuples() + 1));
    for (const char* name : { "RegionParameters", "RegionConvexity" })
    {
      vtkDataArray* a = r->GetFieldData()->GetArray(name);
      r->GetFieldData()->AddArray(Resized(a, a->GetNumberOfTuples() + 1));
    }
    add("one_more_region", "the same mesh with one more (unused) region", r, "-", "Reference");
  }
  {
    Grid r = Copy(base.Mesh);
    EditCells(r, [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == r->GetNumberOfCells() / 2)
      {
        pts[3] = r->GetNumberOfPoints() + 1000000;
      }
      return true;
    });
    add("point_id_out_of_range", "a cell refers to point n + 1000000", r, "-", "Reference");
  }
  {
    Grid r = Copy(base.Mesh);
    EditCells(r, [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == r->GetNumberOfCells() / 2)
      {
        pts.pop_back();
      }
      return true;
    });
    add("tet_with_3_points", "a VTK_TETRA with 3 points", r, "-", "Reference");
  }
  {
    Grid r = Copy(base.Mesh);
    EditCells(r, [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == 0)
      {
        pts[1] = pts[0];
      }
      return true;
    });
    add("repeated_vertex", "a tetrahedron using one point twice", r, "-", "Reference");
  }
  {
    Grid r = Copy(base.Mesh);
    vtkPoints* pts = r->GetPoints();
    for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
    {
      double q[3];
      pts->GetPoint(i, q);
      q[2] = 0;
      pts->SetPoint(i, q);
    }
    add("flat", "every point at z = 0 (all tetrahedra flat)", r, "-", "Reference");
  }
  {
    Grid r = Grid::New();
    add("empty", "an empty grid (no reference: no fault)", r, "-", "");
  }
  {
    Grid r = Copy(base.Mesh);
    vtkNew<vtkCellArray> none;
    r->SetCells(VTK_TETRA, none);
    r->GetCellData()->Initialize();
    add("points_only", "points and no cells (no reference: no fault)", r, "-", "");
  }
  add("short_VertexClass", "VertexClass with 1 tuple (in memory)", base.Mesh,
    "ref:truncate point VertexClass 1", "Reference|VertexClass");
  add("no_points", "cells and no points (in memory)", base.Mesh, "ref:drop-points", "Reference");
  {
    Grid r = Copy(base.Mesh);
    vtkPoints* pts = r->GetPoints();
    for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
    {
      double q[3];
      pts->GetPoint(i, q);
      pts->SetPoint(i, q[0] * 1e300, q[1] * 1e300, q[2] * 1e300);
    }
    add("scale_1e300", "coordinates scaled by 1e300", r, "-", "");
  }
}

//------------------------------------------------------------------------------
// Cells: point ids, point counts, cell types, duplicates.
void CellCases(Corpus& corpus, const Base& base, bool full)
{
  const vtkIdType n = base.Mesh->GetNumberOfCells();
  const vtkIdType np = base.Mesh->GetNumberOfPoints();
  const vtkIdType middle = n / 2;
  bool corrupt = true;
  auto edited = [&](const std::string& what, const std::string& text,
                  const std::function<bool(vtkIdType, int&, std::vector<vtkIdType>&)>& edit) {
    Grid g = Copy(base.Mesh);
    EditCells(g, edit);
    CaseEntry c = On(base, "cell." + what, text);
    // A cell whose points are not there or not a tetrahedron's: corrupt.
    c.ErrorOn = corrupt ? "all" : "-";
    corpus.Add(c, g);
  };
  auto pointId = [&](const std::string& what, vtkIdType id) {
    edited("point_id_" + what, "cell " + std::to_string(middle) + " refers to point " +
        std::to_string(id) + " (" + std::to_string(np) + " points)",
      [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
        if (c == middle)
        {
          pts[2] = id;
        }
        return true;
      });
  };
  pointId("far", np + 1000000);
  pointId("m1", -1);
  pointId("2pow32p1", (vtkIdType(1) << 32) + 1);
  if (full)
  {
    pointId("npoints", np);
    pointId("m1000000", -1000000);
    pointId("2pow31", vtkIdType(1) << 31);
    pointId("int64max", std::numeric_limits<vtkIdType>::max());
  }
  edited("tet_with_3_points", "a VTK_TETRA with 3 points",
    [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == middle)
      {
        pts.pop_back();
      }
      return true;
    });
  if (!full)
  {
    return;
  }
  edited("tet_with_5_points", "a VTK_TETRA with 5 points",
    [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == middle)
      {
        pts.push_back(pts[0] == 0 ? 1 : 0);
      }
      return true;
    });
  edited("tet_with_0_points", "a VTK_TETRA with no points",
    [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == middle)
      {
        pts.clear();
      }
      return true;
    });
  edited("tet_with_1_point", "a VTK_TETRA with 1 point",
    [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == middle)
      {
        pts.resize(1);
      }
      return true;
    });
  // Well-formed cells of a broken mesh: a filter may repair or refuse them.
  corrupt = false;
  edited("repeated_vertex", "a tetrahedron using one point twice",
    [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == middle)
      {
        pts[1] = pts[0];
      }
      return true;
    });
  edited("one_point_four_times", "a tetrahedron (p, p, p, p)",
    [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == middle)
      {
        pts.assign(4, pts[0]);
      }
      return true;
    });
  corrupt = true;
  edited("hexahedron_with_4_points", "a VTK_HEXAHEDRON with a tetrahedron's 4 points",
    [&](vtkIdType c, int& type, std::vector<vtkIdType>&) {
      if (c == middle)
      {
        type = VTK_HEXAHEDRON;
      }
      return true;
    });
  edited("triangle_with_4_points", "a VTK_TRIANGLE with a tetrahedron's 4 points",
    [&](vtkIdType c, int& type, std::vector<vtkIdType>&) {
      if (c == middle)
      {
        type = VTK_TRIANGLE;
      }
      return true;
    });
  edited("empty_cell_with_4_points", "a VTK_EMPTY_CELL with a tetrahedron's 4 points",
    [&](vtkIdType c, int& type, std::vector<vtkIdType>&) {
      if (c == middle)
      {
        type = VTK_EMPTY_CELL;
      }
      return true;
    });
  edited("cell_type_99", "a cell of type 99 (not a VTK type) with 4 points",
    [&](vtkIdType c, int& type, std::vector<vtkIdType>&) {
      if (c == middle)
      {
        type = 99;
      }
      return true;
    });
  {
    Grid g = Copy(base.Mesh);
    vtkNew<vtkIdList> ids;
    g->GetCellPoints(middle, ids);
    AppendCell(g, VTK_TETRA, std::vector<vtkIdType>(ids->begin(), ids->end()));
    corpus.Add(On(base, "cell.duplicate_tet_appended", "cell " + std::to_string(middle) +
                 " appended again (a face shared by more than two tetrahedra)"),
      g);
    Grid h = Copy(base.Mesh);
    std::vector<vtkIdType> pts(ids->begin(), ids->end());
    std::swap(pts[0], pts[1]);
    std::swap(pts[2], pts[3]);
    AppendCell(h, VTK_TETRA, pts);
    corpus.Add(On(base, "cell.duplicate_tet_permuted", "cell " + std::to_string(middle) +
                 " appended again with its points permuted (same orientation)"),
      h);
    Grid k = Copy(base.Mesh);
    std::swap(pts[0], pts[1]);
    AppendCell(k, VTK_TETRA, pts);
    corpus.Add(On(base, "cell.duplicate_tet_inverted",
                 "cell " + std::to_string(middle) + " appended again, inverted"),
      k);
  }
  // Other cell types beside the tetrahedra, on their own points.
  auto appended = [&](const std::string& what, const std::string& text, int type, int points,
                    bool faces) {
    Grid g = Copy(base.Mesh);
    std::vector<std::array<double, 3>> pts;
    for (int i = 0; i < points; ++i)
    {
      pts.push_back({ -2.0 - (i % 2), -2.0 - ((i / 2) % 2), -2.0 - ((i / 4) % 4) * 0.5 });
    }
    const vtkIdType first = AppendPoints(g, pts);
    std::vector<vtkIdType> ids;
    for (int i = 0; i < points; ++i)
    {
      ids.push_back(first + i);
    }
    if (faces)
    {
      // A tetrahedron as a polyhedron: 4 triangular faces.
      const vtkIdType f[] = { 3, ids[0], ids[2], ids[1], 3, ids[0], ids[1], ids[3], 3, ids[1],
        ids[2], ids[3], 3, ids[0], ids[3], ids[2] };
      g->InsertNextCell(VTK_POLYHEDRON, 4, ids.data(), 4, f);
      vtkCellData* cd = g->GetCellData();
      for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
      {
        cd->GetAbstractArray(a)->InsertNextTuple(0, cd->GetAbstractArray(a));
      }
    }
    else
    {
      AppendCell(g, type, ids);
    }
    corpus.Add(On(base, "cell." + what, text), g);
  };
  appended("plus_hexahedron", "one VTK_HEXAHEDRON beside the tetrahedra", VTK_HEXAHEDRON, 8, false);
  appended("plus_triangle", "one VTK_TRIANGLE beside the tetrahedra", VTK_TRIANGLE, 3, false);
  appended("plus_vertex", "one VTK_VERTEX beside the tetrahedra", VTK_VERTEX, 1, false);
  appended("plus_quadratic_tetra", "one VTK_QUADRATIC_TETRA (10 points)", VTK_QUADRATIC_TETRA, 10,
    false);
  appended("plus_lagrange_tetra", "one VTK_LAGRANGE_TETRAHEDRON (10 points)",
    VTK_LAGRANGE_TETRAHEDRON, 10, false);
  appended("plus_polyhedron", "one VTK_POLYHEDRON (a tetrahedron's faces)", VTK_POLYHEDRON, 4, true);
  appended("plus_empty_cell", "one VTK_EMPTY_CELL", VTK_EMPTY_CELL, 0, false);
  appended("plus_convex_point_set", "one VTK_CONVEX_POINT_SET (8 points)", VTK_CONVEX_POINT_SET, 8,
    false);
}

//------------------------------------------------------------------------------
// Points: NaN, Inf, scales, none.
void PointCases(Corpus& corpus, const Base& base, bool full)
{
  const vtkIdType p = InnerPoint(base.Mesh);
  // NaN or infinite coordinates of used points: every filter documents
  // them as an error.
  bool corrupt = true;
  auto moved = [&](const std::string& what, const std::string& text,
                 const std::function<void(vtkPoints*)>& edit) {
    Grid g = Copy(base.Mesh);
    vtkSmartPointer<vtkPoints> pts = CopyPoints(g);
    edit(pts);
    g->SetPoints(pts);
    CaseEntry c = On(base, "points." + what, text);
    c.ErrorOn = corrupt ? "all" : "-";
    corpus.Add(c, g);
  };
  auto coordinate = [&](const std::string& what, int axis, double value) {
    moved(what, "point " + std::to_string(p) + " coordinate " + std::to_string(axis) + " = " +
        Text(value),
      [&](vtkPoints* pts) {
        double q[3];
        pts->GetPoint(p, q);
        q[axis] = value;
        pts->SetPoint(p, q);
      });
  };
  coordinate("nan", 0, NaN);
  if (!full)
  {
    return;
  }
  coordinate("inf", 1, Inf);
  coordinate("neginf", 2, -Inf);
  moved("all_nan", "every coordinate NaN", [](vtkPoints* pts) {
    for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
    {
      pts->SetPoint(i, NaN, NaN, NaN);
    }
  });
  // Finite coordinates at the ends of double's range: a filter may work or
  // refuse, but its output must be valid.
  corrupt = false;
  coordinate("huge", 0, 1e300);
  for (double s : { 1e300, 1e150, 1e-150, 1e-300 })
  {
    moved("scale_" + Tag(s), "coordinates scaled by " + Text(s), [s](vtkPoints* pts) {
      for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
      {
        double q[3];
        pts->GetPoint(i, q);
        pts->SetPoint(i, q[0] * s, q[1] * s, q[2] * s);
      }
    });
  }
  moved("offset_1e15", "coordinates moved by 1e15 (spacing below double precision there)",
    [](vtkPoints* pts) {
      for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
      {
        double q[3];
        pts->GetPoint(i, q);
        pts->SetPoint(i, q[0] + 1e15, q[1] + 1e15, q[2] + 1e15);
      }
    });
  {
    Grid g = Copy(base.Mesh);
    vtkNew<vtkPoints> floats;
    floats->SetDataTypeToFloat();
    floats->SetNumberOfPoints(g->GetNumberOfPoints());
    for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
    {
      floats->SetPoint(i, g->GetPoint(i));
    }
    g->SetPoints(floats);
    CaseEntry c = On(base, "points.float", "single-precision points (no fault)");
    c.ValidOn = "all";
    corpus.Add(c, g);
  }
  {
    Grid g = Copy(base.Mesh);
    g->SetPoints(vtkNew<vtkPoints>());
    g->GetPointData()->Initialize();
    CaseEntry c = On(base, "points.zero_points", "cells and 0 points (ids all out of range)");
    c.Reader = "may-fail"; // no Points element in the file
    c.ErrorOn = "all";
    corpus.Add(c, g);
  }
  {
    CaseEntry c = On(base, "points.no_points_array", "cells and no vtkPoints (in memory)");
    c.Damage = "drop-points";
    c.ErrorOn = "all";
    corpus.Add(c, base.Mesh);
  }
  {
    Grid g = Copy(base.Mesh);
    AppendPoints(g, { { 0.5, 0.5, 0.5 }, { NaN, 0, 0 }, { 100, 100, 100 } });
    corpus.Add(On(base, "points.unused", "3 points no cell uses, one of them NaN"), g);
  }
  {
    Grid g = Copy(base.Mesh);
    AppendPoints(g, { { 100, 100, 100 } });
    corpus.Add(On(base, "points.unused_finite", "1 point no cell uses (a warning at most)"), g);
  }
  {
    Grid g = Copy(base.Mesh);
    double q[3];
    g->GetPoint(p, q);
    AppendPoints(g, { { q[0], q[1], q[2] } });
    corpus.Add(On(base, "points.coincident_unused", "a copy of an inner point, unused"), g);
  }
}

//------------------------------------------------------------------------------
// Other cell and point arrays that filters copy (material ids, masks).
void PassThroughArrayCases(Corpus& corpus, const Base& base, bool full)
{
  Grid g = Copy(base.Mesh);
  vtkNew<vtkIntArray> material;
  material->SetName("Material");
  material->SetNumberOfTuples(g->GetNumberOfCells());
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c)
  {
    material->SetValue(c, static_cast<int>(c % 4));
  }
  g->GetCellData()->AddArray(material);
  vtkNew<vtkDoubleArray> temperature;
  temperature->SetName("Temperature");
  temperature->SetNumberOfTuples(g->GetNumberOfPoints());
  for (vtkIdType i = 0; i < g->GetNumberOfPoints(); ++i)
  {
    temperature->SetValue(i, 20.0 + i % 7);
  }
  g->GetPointData()->AddArray(temperature);
  // A filter that copies cell or point data reads these arrays: one whose
  // length is not the cell or point count must be reported (an error, or a
  // warning and the array left out of a valid output).
  auto add = [&](const std::string& what, const std::string& text, const std::string& damage,
               const std::string& validOn) {
    CaseEntry c = On(base, what, text);
    c.Damage = damage;
    c.ValidOn = validOn;
    if (damage != "-")
    {
      c.ReportOn = "all";
      c.Expect = what.substr(0, what.find('.'));
    }
    corpus.Add(c, g);
  };
  add("Material.short", "cell array Material truncated to 1 tuple (in memory)",
    "truncate cell Material 1", "-");
  add("Temperature.short", "point array Temperature truncated to 1 tuple (in memory)",
    "truncate point Temperature 1", "-");
  if (!full)
  {
    return;
  }
  add("Material.valid", "cell array Material and point array Temperature (no fault)", "-", "all");
  add("Material.long", "cell array Material with 1000 more tuples (in memory)",
    "extend cell Material 1000", "-");
  add("Temperature.long", "point array Temperature with 1000 more tuples (in memory)",
    "extend point Temperature 1000", "-");
  {
    Grid h = Copy(g);
    h->GetCellData()->GetArray("Material")->SetComponent(0, 0, IntMax);
    h->GetPointData()->GetArray("Temperature")->SetComponent(0, 0, NaN);
    CaseEntry c = On(base, "Material.extreme_values",
      "Material 2147483647 and Temperature NaN: user data, not a fault");
    c.ValidOn = "all";
    corpus.Add(c, h);
  }
}

//------------------------------------------------------------------------------
// Topology on the lattice base: orientation, degenerate and non-conforming
// cells, seams.
void TopologyCases(Corpus& corpus, const Base& base, bool full)
{
  const vtkIdType middle = base.Mesh->GetNumberOfCells() / 2;
  {
    Grid g = Copy(base.Mesh);
    EditCells(g, [](vtkIdType, int&, std::vector<vtkIdType>& pts) {
      std::swap(pts[2], pts[3]);
      return true;
    });
    corpus.Add(On(base, "topology.all_inverted",
                 "every tetrahedron in the opposite vertex order (consistently inverted)"),
      g);
  }
  {
    Grid g = Copy(base.Mesh);
    EditCells(g, [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c == middle)
      {
        std::swap(pts[2], pts[3]);
      }
      return true;
    });
    corpus.Add(On(base, "topology.one_inverted", "one tetrahedron's vertex order reversed (mixed "
                                                 "orientation)"),
      g);
  }
  if (!full)
  {
    return;
  }
  {
    Grid g = Copy(base.Mesh);
    EditCells(g, [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c % 2 == 0)
      {
        std::swap(pts[2], pts[3]);
      }
      return true;
    });
    corpus.Add(On(base, "topology.half_inverted", "every other tetrahedron reversed"), g);
  }
  // An inner point moved through its neighbours: geometrically inverted
  // tetrahedra, consistently numbered (what Improve repairs).
  const vtkIdType inner = InnerPoint(base.Mesh);
  auto movePoint = [&](const std::string& what, const std::string& text, double dx, double dy,
                     double dz) {
    Grid g = Copy(base.Mesh);
    vtkSmartPointer<vtkPoints> pts = CopyPoints(g);
    double q[3];
    pts->GetPoint(inner, q);
    pts->SetPoint(inner, q[0] + dx, q[1] + dy, q[2] + dz);
    g->SetPoints(pts);
    corpus.Add(On(base, "topology." + what, text), g);
  };
  movePoint("folded", "an inner point moved 1.6 spacings (folded, inverted tetrahedra)", 1.6, 0, 0);
  {
    // Zero volume: a tetrahedron's fourth point moved onto its other three's
    // plane (the mesh keeps its numbering).
    Grid g = Copy(base.Mesh);
    vtkNew<vtkIdList> ids;
    g->GetCellPoints(middle, ids);
    vtkSmartPointer<vtkPoints> pts = CopyPoints(g);
    double a[3], b[3], c[3], d[3];
    pts->GetPoint(ids->GetId(0), a);
    pts->GetPoint(ids->GetId(1), b);
    pts->GetPoint(ids->GetId(2), c);
    pts->GetPoint(ids->GetId(3), d);
    // Put d at the centroid of a, b, c.
    for (int k = 0; k < 3; ++k)
    {
      d[k] = (a[k] + b[k] + c[k]) / 3;
    }
    pts->SetPoint(ids->GetId(3), d);
    g->SetPoints(pts);
    corpus.Add(On(base, "topology.zero_volume",
                 "one tetrahedron's point moved onto its opposite face's centroid (zero volume)"),
      g);
  }
  {
    Grid g = Copy(base.Mesh);
    vtkSmartPointer<vtkPoints> pts = CopyPoints(g);
    for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
    {
      double q[3];
      pts->GetPoint(i, q);
      pts->SetPoint(i, q[0], q[1], 0);
    }
    g->SetPoints(pts);
    corpus.Add(On(base, "topology.flat", "every point at z = 0 (every tetrahedron flat)"), g);
  }
  {
    // Two copies of the part side by side, the second's points not merged on
    // the shared plane: a seam of duplicate nodes.
    Grid g = Copy(base.Mesh);
    double bounds[6];
    g->GetBounds(bounds);
    const vtkIdType np = g->GetNumberOfPoints();
    std::vector<std::array<double, 3>> shifted;
    for (vtkIdType i = 0; i < np; ++i)
    {
      double q[3];
      g->GetPoint(i, q);
      shifted.push_back({ q[0] + (bounds[1] - bounds[0]), q[1], q[2] });
    }
    AppendPoints(g, shifted);
    const vtkIdType nc = g->GetNumberOfCells();
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < nc; ++c)
    {
      g->GetCellPoints(c, ids);
      std::vector<vtkIdType> pts(ids->begin(), ids->end());
      for (vtkIdType& id : pts)
      {
        id += np;
      }
      AppendCell(g, VTK_TETRA, pts);
    }
    corpus.Add(On(base, "topology.unmerged_seam",
                 "two copies side by side touching along a face, duplicate nodes not merged"),
      g);
    // The same with the second copy moved away: two parts (no fault).
    Grid h = Copy(g);
    vtkSmartPointer<vtkPoints> pts = CopyPoints(h);
    for (vtkIdType i = np; i < pts->GetNumberOfPoints(); ++i)
    {
      double q[3];
      pts->GetPoint(i, q);
      pts->SetPoint(i, q[0] + 0.5 * (bounds[1] - bounds[0]), q[1], q[2]);
    }
    h->SetPoints(pts);
    CaseEntry c = On(base, "topology.two_parts", "two separate copies of the part (no fault)");
    c.ValidOn = "MeshQuality,Segment,Improve,HexToTet,TetToHex";
    corpus.Add(c, h);
    // Touching at one corner: the second copy's corner point merged into the
    // first's opposite corner (a non-manifold vertex).
    Grid k = Copy(base.Mesh);
    const vtkIdType far = np - 1; // the lattice's last point is its (n, n, n) corner
    double corner[3];
    k->GetPoint(far, corner);
    std::vector<std::array<double, 3>> moved;
    for (vtkIdType i = 0; i < np; ++i)
    {
      double q[3];
      k->GetPoint(i, q);
      moved.push_back({ q[0] + corner[0] - bounds[0], q[1] + corner[1] - bounds[2],
        q[2] + corner[2] - bounds[4] });
    }
    AppendPoints(k, moved);
    for (vtkIdType c2 = 0; c2 < nc; ++c2)
    {
      k->GetCellPoints(c2, ids);
      std::vector<vtkIdType> p2(ids->begin(), ids->end());
      for (vtkIdType& id : p2)
      {
        id = id == 0 ? far : id + np; // point 0 is the (0, 0, 0) corner
      }
      AppendCell(k, VTK_TETRA, p2);
    }
    corpus.Add(On(base, "topology.touching_at_vertex",
                 "two copies sharing one corner point (non-manifold vertex; point " +
                   std::to_string(np) + " unused)"),
      k);
  }
  {
    // One cube's tetrahedra turned around the other diagonal: its faces no
    // longer match its neighbours' (non-conforming, hanging edges).
    Grid g = Copy(base.Mesh);
    // The cells of cube (1, 1, 1) of the lattice: 6 consecutive cells.
    const int n = static_cast<int>(std::lround(std::cbrt(g->GetNumberOfCells() / 6.0)));
    const vtkIdType cube = (1 * n + 1) * n + 1;
    const int m = n + 1;
    auto id = [m](int i, int j, int k) { return static_cast<vtkIdType>((k * m + j) * m + i); };
    std::vector<std::array<vtkIdType, 4>> replacement;
    // The 6 tets around the diagonal from (2, 1, 1) to (1, 2, 2).
    const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 },
      { 2, 1, 0 } };
    for (const auto& perm : perms)
    {
      int c[3] = { 2, 1, 1 };
      const int step[3] = { -1, 1, 1 };
      std::array<vtkIdType, 4> tet;
      tet[0] = id(c[0], c[1], c[2]);
      for (int s = 0; s < 3; ++s)
      {
        c[perm[s]] += step[perm[s]];
        tet[s + 1] = id(c[0], c[1], c[2]);
      }
      double p[4][3];
      for (int v = 0; v < 4; ++v)
      {
        g->GetPoint(tet[v], p[v]);
      }
      if (Orient(p[0], p[1], p[2], p[3]) < 0)
      {
        std::swap(tet[2], tet[3]);
      }
      replacement.push_back(tet);
    }
    EditCells(g, [&](vtkIdType c, int&, std::vector<vtkIdType>& pts) {
      if (c >= 6 * cube && c < 6 * cube + 6)
      {
        const auto& tet = replacement[static_cast<std::size_t>(c - 6 * cube)];
        pts.assign(tet.begin(), tet.end());
      }
      return true;
    });
    corpus.Add(On(base, "topology.nonconforming_cube",
                 "one inner cube split along its other diagonal (faces do not match)"),
      g);
  }
  {
    // A sliver: an inner point pushed almost onto a face.
    Grid g = Copy(base.Mesh);
    vtkNew<vtkIdList> ids;
    g->GetCellPoints(middle, ids);
    vtkSmartPointer<vtkPoints> pts = CopyPoints(g);
    double a[3], b[3], c[3], d[3];
    pts->GetPoint(ids->GetId(0), a);
    pts->GetPoint(ids->GetId(1), b);
    pts->GetPoint(ids->GetId(2), c);
    pts->GetPoint(ids->GetId(3), d);
    for (int k = 0; k < 3; ++k)
    {
      d[k] = 0.999 * (a[k] + b[k] + c[k]) / 3 + 0.001 * d[k];
    }
    pts->SetPoint(ids->GetId(3), d);
    g->SetPoints(pts);
    corpus.Add(On(base, "topology.sliver", "one tetrahedron squashed to 0.1% of its height"), g);
  }
}

/// Small hand-made grids, each a topology fault of its own.
void HandMadeCases(Corpus& corpus)
{
  auto add = [&](const std::string& what, const std::string& text, Grid g, const std::string& valid) {
    CaseEntry c;
    c.Name = "handmade." + what;
    c.Timeout = 20;
    c.Description = text;
    c.ValidOn = valid;
    // The XML reader reports an error for a file without a Points element.
    if (g->GetNumberOfPoints() == 0)
    {
      c.Reader = "may-fail";
    }
    corpus.Add(c, g);
  };
  const std::array<double, 3> a{ 0, 0, 0 }, b{ 1, 0, 0 }, c{ 0, 1, 0 }, d{ 0, 0, 1 }, e{ 1, 1, 1 };
  add("two_tets", "two tetrahedra sharing a face (no fault)",
    MakeGrid({ a, b, c, d, e }, { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 1, 3, 2 } } }),
    "MeshQuality,HexToTet,TetToHex");
  add("one_tet", "a single tetrahedron (no fault)", MakeGrid({ a, b, c, d }, { { VTK_TETRA, { 0, 1, 2, 3 } } }),
    "MeshQuality,HexToTet,TetToHex");
  add("one_tet_inverted", "a single tetrahedron in the opposite vertex order",
    MakeGrid({ a, b, c, d }, { { VTK_TETRA, { 0, 2, 1, 3 } } }), "-");
  add("nonmanifold_edge", "two tetrahedra sharing only an edge",
    MakeGrid({ a, b, c, d, { 0.5, -1, -1 }, { 1, -1, 0.2 } },
      { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 0, 1, 4, 5 } } }),
    "-");
  add("nonmanifold_vertex", "two tetrahedra sharing only a vertex",
    MakeGrid({ a, b, c, d, { -1, 0, 0 }, { 0, -1, 0 }, { 0, 0, -1 } },
      { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 0, 4, 5, 6 } } }),
    "-");
  add("face_shared_by_three", "three tetrahedra on one face (two of them overlapping)",
    MakeGrid({ a, b, c, d, e, { 0.1, 0.1, 0.8 } },
      { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 1, 3, 2 } },
        { VTK_TETRA, { 0, 1, 2, 5 } } }),
    "-");
  add("overlapping", "two tetrahedra overlapping without sharing a face",
    MakeGrid({ a, b, c, d, { 0.1, 0.1, 0.1 }, { 1.1, 0.1, 0.1 }, { 0.1, 1.1, 0.1 }, { 0.1, 0.1, 1.1 } },
      { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 5, 6, 7 } } }),
    "-");
  add("flat_tet", "a single tetrahedron with four coplanar points",
    MakeGrid({ a, b, c, { 1, 1, 0 } }, { { VTK_TETRA, { 0, 1, 2, 3 } } }), "-");
  add("coincident_points", "a tetrahedron whose four points are the same point",
    MakeGrid({ a, a, a, a }, { { VTK_TETRA, { 0, 1, 2, 3 } } }), "-");
  add("empty_grid", "an empty grid (no points, no cells)", Grid::New(), "all");
  add("points_only", "points and no cells", MakeGrid({ a, b, c, d }, {}), "all");
  {
    Grid g = MakeGrid({ a, b, c, d }, { { VTK_TETRA, { 0, 1, 2, 3 } } });
    vtkNew<vtkIntArray> f;
    f->SetName("FaceRegion");
    f->SetNumberOfComponents(4);
    f->SetNumberOfTuples(1);
    f->SetTypedTuple(0, std::array<int, 4>{ IntMax, IntMax, IntMax, IntMax }.data());
    g->GetCellData()->AddArray(f);
    CaseEntry cse;
    cse.Name = "handmade.one_tet_FaceRegion_intmax";
    cse.Timeout = 20;
    cse.Description = "a single tetrahedron, FaceRegion 2147483647 on each face, no region arrays";
    cse.ReportOn = FaceRegionReaders;
    cse.Expect = "FaceRegion";
    corpus.Add(cse, g);
  }
  {
    // An unstructured grid whose only cells are 2D.
    add("triangles_only", "two triangles, no 3D cell",
      MakeGrid({ a, b, c, d }, { { VTK_TRIANGLE, { 0, 1, 2 } }, { VTK_TRIANGLE, { 0, 1, 3 } } }), "-");
  }
}

/// The all-hexahedral part and faults a hexahedral mesh can have.
void HexCases(Corpus& corpus, const Base& base)
{
  {
    CaseEntry c = On(base, "valid", "the all-hexahedral part (no fault for the filters that take "
                                    "hexahedra)");
    c.ValidOn = "MeshQuality,HexToTet";
    corpus.Add(c, base.Mesh);
  }
  const vtkIdType middle = base.Mesh->GetNumberOfCells() / 2;
  bool corrupt = true; // a cell that is not what its type says: only an error is right
  auto edited = [&](const std::string& what, const std::string& text,
                  const std::function<void(int&, std::vector<vtkIdType>&)>& edit) {
    Grid g = Copy(base.Mesh);
    EditCells(g, [&](vtkIdType c, int& type, std::vector<vtkIdType>& pts) {
      if (c == middle)
      {
        edit(type, pts);
      }
      return true;
    });
    CaseEntry c = On(base, "cell." + what, text);
    c.ErrorOn = corrupt ? "all" : "-";
    corpus.Add(c, g);
  };
  const vtkIdType np = base.Mesh->GetNumberOfPoints();
  edited("point_id_far", "a hexahedron refers to point n + 1000000",
    [&](int&, std::vector<vtkIdType>& pts) { pts[5] = np + 1000000; });
  edited("point_id_m1", "a hexahedron refers to point -1",
    [&](int&, std::vector<vtkIdType>& pts) { pts[5] = -1; });
  edited("hex_with_7_points", "a VTK_HEXAHEDRON with 7 points",
    [&](int&, std::vector<vtkIdType>& pts) { pts.pop_back(); });
  edited("hex_with_9_points", "a VTK_HEXAHEDRON with 9 points",
    [&](int&, std::vector<vtkIdType>& pts) { pts.push_back(pts[0]); });
  corrupt = false; // well-formed cells of a broken mesh
  edited("inverted_hex", "a hexahedron with its top and bottom faces swapped",
    [&](int&, std::vector<vtkIdType>& pts) {
      std::rotate(pts.begin(), pts.begin() + 4, pts.end());
    });
  edited("repeated_vertex", "a hexahedron using one point twice",
    [&](int&, std::vector<vtkIdType>& pts) { pts[6] = pts[0]; });
  edited("collapsed_hex", "a hexahedron whose top face is its bottom face",
    [&](int&, std::vector<vtkIdType>& pts) {
      for (int k = 0; k < 4; ++k)
      {
        pts[4 + k] = pts[k];
      }
    });
  corrupt = true;
  edited("wedge_with_8_points", "a VTK_WEDGE with a hexahedron's 8 points",
    [&](int& type, std::vector<vtkIdType>&) { type = VTK_WEDGE; });
  {
    Grid g = Copy(base.Mesh);
    vtkSmartPointer<vtkPoints> pts = CopyPoints(g);
    pts->SetPoint(np / 2, NaN, 0, 0);
    g->SetPoints(pts);
    CaseEntry c = On(base, "points.nan", "a NaN coordinate");
    c.ErrorOn = "all";
    corpus.Add(c, g);
  }
}

} // namespace

int main(int argc, char* argv[])
{
  std::string data, out;
  int bigCells = 27;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--data" && i + 1 < argc)
    {
      data = argv[++i];
    }
    else if (arg == "--out" && i + 1 < argc)
    {
      out = argv[++i];
    }
    else if (arg == "--big-cubes" && i + 1 < argc)
    {
      bigCells = std::stoi(argv[++i]);
    }
    else
    {
      std::cerr << "usage: generate_corpus --data <Data folder> --out <folder> [--big-cubes N]\n";
      return 2;
    }
  }
  if (data.empty() || out.empty())
  {
    std::cerr << "usage: generate_corpus --data <Data folder> --out <folder> [--big-cubes N]\n";
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  Corpus corpus(out);

  // The bases, each with Segment's arrays.
  Base box{ "box", Segmented(MakeLattice(4, 0.15, 1), "box"), 20, 0 };
  Base boss{ "boss", Segmented(ReadVtu(data + "/boss_block.vtu"), "boss"), 40, 0 };
  Base big{ "big", Segmented(MakeLattice(bigCells, 0.1, 2), "big"), 60, 0 };
  Base hex{ "hex", ReadVtu(data + "/hex/hex_block.vtu"), 30, 0 };
  Base plain{ "plain", MakeLattice(4, 0.15, 1), 20, 0 };
  for (Base* b : { &box, &boss, &big })
  {
    b->Regions = b->Mesh->GetFieldData()->GetArray("RegionType")->GetNumberOfTuples();
  }
  for (Base* b : { &box, &boss, &big, &plain })
  {
    CaseEntry c = On(*b, "valid", "the base as it is (no fault)");
    c.ValidOn = "all";
    corpus.Add(c, b->Mesh);
  }

  // Array faults: all of them on the small base; on the large ones those
  // whose effect grows with the size (over-reads of short arrays, ids far
  // out of range) or needs curved regions (boss_block's cylinders), so that
  // the run stays within about two minutes on two cores.
  FaceRegionCases(corpus, box, true);
  FaceRegionCases(corpus, boss, false);
  FaceRegionCases(corpus, big, false);
  FaceRegionLengthCases(corpus, box, true);
  FaceRegionLengthCases(corpus, boss, false);
  FaceRegionLengthCases(corpus, big, false);
  VertexClassCases(corpus, box, true);
  VertexClassCases(corpus, big, false);
  FieldArrayCases(corpus, box, true);
  FieldArrayCases(corpus, big, false);
  CurvedRegionCases(corpus, boss);
  RegionArrayCases(corpus, box, true);
  RegionArrayCases(corpus, big, false);
  ReferenceCases(corpus, box, boss, true);
  ReferenceCases(corpus, big, box, false);
  PassThroughArrayCases(corpus, box, true);
  PassThroughArrayCases(corpus, big, false);

  // Mesh faults.
  CellCases(corpus, box, true);
  CellCases(corpus, plain, false);
  CellCases(corpus, big, false);
  PointCases(corpus, box, true);
  TopologyCases(corpus, box, true);
  TopologyCases(corpus, plain, false);
  HandMadeCases(corpus);
  HexCases(corpus, hex);

  corpus.WriteManifest();
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "generate_corpus: " << corpus.Size() << " cases in " << out << " ("
            << seconds << " s; bases: box " << box.Mesh->GetNumberOfCells() << " tets, "
            << box.Regions << " regions; boss " << boss.Mesh->GetNumberOfCells() << " tets, "
            << boss.Regions << " regions; big " << big.Mesh->GetNumberOfCells() << " tets, "
            << big.Regions << " regions; hex " << hex.Mesh->GetNumberOfCells() << " cells)\n";
  return 0;
}
