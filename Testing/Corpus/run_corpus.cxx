// run_corpus: every case of the malformed-input corpus (generate_corpus)
// through every FEMorph filter, each (case, filter) in a child process
// (fork + waitpid, with a timeout), against the contract every filter keeps:
//
//   either the filter reports an error (ErrorEvent) and its output is empty,
//   or its output is valid (checked here, independently of the filters:
//   cell point ids in range, the right point count per cell type, no NaN
//   point, tetrahedra of positive volume by a determinant computed here, the
//   segmentation arrays consistent with the mesh);
//   where the case names an array that the filter reads, its error or
//   warning text names it (the case's expected substrings);
//   a case without a fault is accepted;
//   the input (and the Reference) is not modified;
//   never a crash, a hang, a sanitizer report, or a silently wrong mesh.
//
// Prints a table (filter x outcome) and the failing (case, filter) pairs with
// their reason. Exit status 1 when any pair fails. README.md beside this
// file has the details.
#include "corpus_manifest.h"

#include "vtkFEMorphAdapt.h"
#include "vtkFEMorphDeform.h"
#include "vtkFEMorphHexToTet.h"
#include "vtkFEMorphImprove.h"
#include "vtkFEMorphMeshQuality.h"
#include "vtkFEMorphSegment.h"
#include "vtkFEMorphTetToHex.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using femorph_corpus::CaseEntry;
using femorph_corpus::ListHas;
using femorph_corpus::SplitList;

namespace
{
using Clock = std::chrono::steady_clock;

//------------------------------------------------------------------------------
// Outcomes. The first two meet the contract.
enum Outcome
{
  Refused,      // error reported, output empty (and named where required)
  Accepted,     // no error, output valid (and a warning named the damage where required)
  Crash,        // killed by a signal (SIGSEGV, SIGABRT, ...) or ASan's SEGV report
  Hang,         // still running at the timeout
  Sanitizer,    // an AddressSanitizer or UBSan report (over-read, overflow, ...)
  Silent,       // read damaged data without any error or warning
  Unnamed,      // an error or warning, but not naming the damaged array
  InvalidOutput,// no error and an output that is not valid
  NotEmpty,     // an error, but the output is not empty
  RefusedValid, // an error on a case without a fault
  AcceptedCorrupt, // no error on an input no output can be right for
  InputModified,// the input or the Reference changed
  NoMessage,    // the pipeline failed without an error from the filter
  CorpusError,  // the case could not be set up (reader error, bad recipe)
  NumOutcomes
};

const char* const OutcomeNames[NumOutcomes] = { "error", "valid", "crash", "hang", "sanitizer",
  "silent", "unnamed", "invalid", "not-empty", "refused-valid", "no-error", "modified",
  "no-message", "corpus" };

bool Passes(Outcome o)
{
  return o == Refused || o == Accepted;
}

//------------------------------------------------------------------------------
/// Records ErrorEvent and WarningEvent messages (and keeps them off stderr).
class Recorder : public vtkCommand
{
public:
  static Recorder* New() { return new Recorder; }
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
  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;
};

//------------------------------------------------------------------------------
// Fingerprint of a grid: counts, points, cells and every array's bytes.
class Fingerprint
{
public:
  void Add(const void* data, std::size_t size)
  {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i)
    {
      this->Hash = (this->Hash ^ bytes[i]) * 1099511628211ull;
    }
  }
  void Add(long long value) { this->Add(&value, sizeof(value)); }
  void Add(const std::string& text)
  {
    this->Add(static_cast<long long>(text.size()));
    this->Add(text.data(), text.size());
  }
  void Add(vtkAbstractArray* array)
  {
    if (!array)
    {
      this->Add(-1LL);
      return;
    }
    this->Add(std::string(array->GetName() ? array->GetName() : "(null)"));
    this->Add(static_cast<long long>(array->GetDataType()));
    this->Add(static_cast<long long>(array->GetNumberOfComponents()));
    this->Add(static_cast<long long>(array->GetNumberOfTuples()));
    if (auto* strings = vtkStringArray::SafeDownCast(array))
    {
      for (vtkIdType i = 0; i < strings->GetNumberOfValues(); ++i)
      {
        this->Add(strings->GetValue(i));
      }
    }
    else if (auto* data = vtkDataArray::SafeDownCast(array))
    {
      const std::size_t bytes = static_cast<std::size_t>(data->GetNumberOfValues()) *
        static_cast<std::size_t>(data->GetDataTypeSize());
      if (bytes > 0)
      {
        this->Add(data->GetVoidPointer(0), bytes);
      }
    }
  }
  void Add(vtkFieldData* data)
  {
    this->Add(static_cast<long long>(data->GetNumberOfArrays()));
    for (int a = 0; a < data->GetNumberOfArrays(); ++a)
    {
      this->Add(data->GetAbstractArray(a));
    }
  }
  void Add(vtkUnstructuredGrid* grid)
  {
    this->Add(static_cast<long long>(grid->GetNumberOfPoints()));
    this->Add(static_cast<long long>(grid->GetNumberOfCells()));
    this->Add(grid->GetPoints() ? grid->GetPoints()->GetData() : nullptr);
    if (vtkCellArray* cells = grid->GetCells())
    {
      this->Add(cells->GetOffsetsArray());
      this->Add(cells->GetConnectivityArray());
    }
    this->Add(grid->GetCellTypesArray());
    this->Add(grid->GetPointData());
    this->Add(grid->GetCellData());
    this->Add(grid->GetFieldData());
  }
  std::uint64_t Hash = 1469598103934665603ull;
};

std::uint64_t FingerprintOf(vtkUnstructuredGrid* grid)
{
  Fingerprint f;
  if (grid)
  {
    f.Add(grid);
  }
  return f.Hash;
}

//------------------------------------------------------------------------------
// Damage recipes (corpus_manifest.h).
bool ApplyRecipe(const std::string& recipe, vtkUnstructuredGrid* grid, std::string& error)
{
  std::istringstream in(recipe);
  std::string verb;
  in >> verb;
  if (verb == "drop-points")
  {
    grid->SetPoints(nullptr);
    return true;
  }
  std::string where, name;
  long long tuples = -1;
  in >> where >> name >> tuples;
  vtkFieldData* data = where == "cell" ? static_cast<vtkFieldData*>(grid->GetCellData())
    : where == "point"                 ? static_cast<vtkFieldData*>(grid->GetPointData())
    : where == "field"                 ? grid->GetFieldData()
                                       : nullptr;
  vtkAbstractArray* source = data ? data->GetAbstractArray(name.c_str()) : nullptr;
  if (!source || tuples < 0 || (verb != "truncate" && verb != "extend"))
  {
    error = "cannot apply the damage recipe '" + recipe + "'";
    return false;
  }
  const vtkIdType count = verb == "truncate" ? tuples : source->GetNumberOfTuples() + tuples;
  // A new array of exactly `count` tuples, so that reading past it is
  // reading past its heap block (AddressSanitizer sees it).
  vtkSmartPointer<vtkAbstractArray> resized;
  resized.TakeReference(source->NewInstance());
  resized->SetName(source->GetName());
  resized->SetNumberOfComponents(source->GetNumberOfComponents());
  resized->SetNumberOfTuples(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    resized->SetTuple(i, std::min(i, source->GetNumberOfTuples() - 1), source);
  }
  resized->Squeeze();
  // Keep the attribute role (e.g. active scalars) when there was one.
  auto* attributes = vtkDataSetAttributes::SafeDownCast(data);
  int role = -1;
  for (int a = 0; attributes && a < vtkDataSetAttributes::NUM_ATTRIBUTES; ++a)
  {
    if (attributes->GetAbstractAttribute(a) == source)
    {
      role = a;
    }
  }
  data->RemoveArray(name.c_str());
  data->AddArray(resized);
  if (role >= 0)
  {
    attributes->SetActiveAttribute(name.c_str(), role);
  }
  return true;
}

bool ApplyRecipes(const std::string& recipes, bool reference, vtkUnstructuredGrid* grid,
  std::string& error)
{
  for (std::string recipe : SplitList(recipes, ';'))
  {
    const bool forReference = recipe.rfind("ref:", 0) == 0;
    if (forReference)
    {
      recipe = recipe.substr(4);
    }
    if (forReference == reference && grid && !ApplyRecipe(recipe, grid, error))
    {
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
// Output checks, independent of the filters.

/// Points of a linear cell type; -1 for types whose count varies or that
/// are not checked.
int PointCount(int type)
{
  switch (type)
  {
    case VTK_VERTEX: return 1;
    case VTK_LINE: return 2;
    case VTK_TRIANGLE: return 3;
    case VTK_QUAD: return 4;
    case VTK_PIXEL: return 4;
    case VTK_TETRA: return 4;
    case VTK_VOXEL: return 8;
    case VTK_HEXAHEDRON: return 8;
    case VTK_WEDGE: return 6;
    case VTK_PYRAMID: return 5;
    case VTK_QUADRATIC_TETRA: return 10;
    case VTK_QUADRATIC_HEXAHEDRON: return 20;
    case VTK_EMPTY_CELL: return 0;
    default: return -1;
  }
}

/// Six times the volume of tetrahedron (a, b, c, d), positive in VTK_TETRA's
/// order ((b - a) x (c - a) . (d - a) > 0), computed on the edges scaled to
/// unit size so that neither 1e300 nor 1e-300 meshes over- or underflow
/// (only its sign is meant). NaN for non-finite input.
double TetSign(const double* a, const double* b, const double* c, const double* d)
{
  double e[3][3];
  double scale = 0;
  for (int k = 0; k < 3; ++k)
  {
    e[0][k] = b[k] - a[k];
    e[1][k] = c[k] - a[k];
    e[2][k] = d[k] - a[k];
    for (int r = 0; r < 3; ++r)
    {
      scale = std::max(scale, std::fabs(e[r][k]));
    }
  }
  if (!(scale > 0) || !std::isfinite(scale))
  {
    return scale == 0 ? 0.0 : std::nan("");
  }
  for (auto& row : e)
  {
    for (double& x : row)
    {
      x /= scale;
    }
  }
  return e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
    e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
    e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
}

/// Faces of the linear 3D cells in VTK's node orders, outward normals.
const std::vector<std::vector<int>>& Faces(int type)
{
  static const std::vector<std::vector<int>> hex = { { 0, 4, 7, 3 }, { 1, 2, 6, 5 },
    { 0, 1, 5, 4 }, { 3, 7, 6, 2 }, { 0, 3, 2, 1 }, { 4, 5, 6, 7 } };
  static const std::vector<std::vector<int>> wedge = { { 0, 1, 2 }, { 3, 5, 4 }, { 0, 3, 4, 1 },
    { 1, 4, 5, 2 }, { 2, 5, 3, 0 } };
  static const std::vector<std::vector<int>> pyramid = { { 0, 3, 2, 1 }, { 0, 1, 4 },
    { 1, 2, 4 }, { 2, 3, 4 }, { 3, 0, 4 } };
  static const std::vector<std::vector<int>> tet = { { 0, 1, 3 }, { 1, 2, 3 }, { 2, 0, 3 },
    { 0, 2, 1 } };
  static const std::vector<std::vector<int>> none;
  switch (type)
  {
    case VTK_HEXAHEDRON: return hex;
    case VTK_WEDGE: return wedge;
    case VTK_PYRAMID: return pyramid;
    case VTK_TETRA: return tet;
    default: return none;
  }
}

/// Signed volume of a linear 3D cell by the divergence theorem over its
/// outward faces (each face fanned from its centroid), relative to the
/// cube of the cell's size; positive for a valid cell in VTK's order.
double CellVolumeSign(int type, const std::vector<std::array<double, 3>>& p)
{
  double lo[3] = { p[0][0], p[0][1], p[0][2] }, scale = 0;
  for (const auto& q : p)
  {
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], q[k]);
    }
  }
  std::vector<std::array<double, 3>> r(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      r[i][k] = p[i][k] - lo[k];
      scale = std::max(scale, std::fabs(r[i][k]));
    }
  }
  if (!(scale > 0))
  {
    return 0;
  }
  for (auto& q : r)
  {
    for (double& x : q)
    {
      x /= scale;
    }
  }
  double volume = 0;
  for (const auto& face : Faces(type))
  {
    std::array<double, 3> c{ 0, 0, 0 };
    for (int v : face)
    {
      for (int k = 0; k < 3; ++k)
      {
        c[k] += r[v][k] / face.size();
      }
    }
    for (std::size_t i = 0; i < face.size(); ++i)
    {
      const auto& a = r[face[i]];
      const auto& b = r[face[(i + 1) % face.size()]];
      // (a x b) . c / 6: the tetrahedron (origin, a, b, c).
      volume += (a[1] * b[2] - a[2] * b[1]) * c[0] + (a[2] * b[0] - a[0] * b[2]) * c[1] +
        (a[0] * b[1] - a[1] * b[0]) * c[2];
    }
  }
  return volume / 6;
}

struct MeshRules
{
  std::set<int> Types;          // allowed cell types; empty: any
  bool PositiveVolume = false;  // every 3D cell of positive volume
  bool ConsistentSign = false;  // tetrahedra all of one sign (zero allowed)
  bool RepeatedPointOk = false; // a cell may use a point twice
  bool Segmentation = false;    // FaceRegion and the field arrays must be consistent
  bool FacesShared = false;     // no triangle in more than two tetrahedra
  bool ClosedBoundary = false;  // every boundary edge in exactly two boundary triangles
};

/// Why the tetrahedra of `grid` do not fit together by `rules` (faces shared
/// by more than two tetrahedra, an open or non-manifold boundary); empty
/// when they do. Cells other than tetrahedra are ignored.
std::string CheckConformity(vtkUnstructuredGrid* grid, const MeshRules& rules)
{
  using Triple = std::array<vtkIdType, 3>;
  std::vector<Triple> faces;
  faces.reserve(static_cast<std::size_t>(4 * grid->GetNumberOfCells()));
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    if (grid->GetCellType(c) != VTK_TETRA)
    {
      continue;
    }
    grid->GetCellPoints(c, npts, pts);
    for (int f = 0; f < 4; ++f)
    {
      Triple t = { pts[(f + 1) % 4], pts[(f + 2) % 4], pts[(f + 3) % 4] };
      std::sort(t.begin(), t.end());
      faces.push_back(t);
    }
  }
  std::sort(faces.begin(), faces.end());
  using Pair = std::array<vtkIdType, 2>;
  std::vector<Pair> edges;
  for (std::size_t i = 0; i < faces.size();)
  {
    std::size_t j = i;
    while (j < faces.size() && faces[j] == faces[i])
    {
      ++j;
    }
    if (rules.FacesShared && j - i > 2)
    {
      return "the face (" + std::to_string(faces[i][0]) + ", " + std::to_string(faces[i][1]) +
        ", " + std::to_string(faces[i][2]) + ") is in " + std::to_string(j - i) + " tetrahedra";
    }
    if (j - i == 1)
    {
      const Triple& t = faces[i];
      edges.push_back({ t[0], t[1] });
      edges.push_back({ t[0], t[2] });
      edges.push_back({ t[1], t[2] });
    }
    i = j;
  }
  if (!rules.ClosedBoundary)
  {
    return "";
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();)
  {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i])
    {
      ++j;
    }
    if (j - i != 2)
    {
      return "the boundary edge (" + std::to_string(edges[i][0]) + ", " +
        std::to_string(edges[i][1]) + ") is in " + std::to_string(j - i) +
        " boundary triangles (not a closed manifold boundary)";
    }
    i = j;
  }
  return "";
}

/// Why `grid` is not a valid mesh by `rules`; empty when it is.
std::string CheckMesh(vtkUnstructuredGrid* grid, const MeshRules& rules)
{
  std::ostringstream why;
  const vtkIdType np = grid->GetNumberOfPoints();
  const vtkIdType nc = grid->GetNumberOfCells();
  if (nc > 0 && !grid->GetPoints())
  {
    return "cells without points";
  }
  vtkIdType nonFinite = 0;
  for (vtkIdType i = 0; i < np; ++i)
  {
    double p[3];
    grid->GetPoint(i, p);
    nonFinite += !(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
  }
  if (nonFinite > 0)
  {
    why << nonFinite << " NaN or infinite points";
    return why.str();
  }
  for (vtkFieldData* data : { static_cast<vtkFieldData*>(grid->GetPointData()),
         static_cast<vtkFieldData*>(grid->GetCellData()) })
  {
    const vtkIdType expected = data == grid->GetPointData() ? np : nc;
    for (int a = 0; a < data->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* array = data->GetAbstractArray(a);
      if (array && array->GetNumberOfTuples() != expected)
      {
        why << (data == grid->GetPointData() ? "point" : "cell") << " array "
            << (array->GetName() ? array->GetName() : "(unnamed)") << " has "
            << array->GetNumberOfTuples() << " tuples for " << expected
            << (data == grid->GetPointData() ? " points" : " cells");
        return why.str();
      }
    }
  }
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  int sign = 0;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    const int type = grid->GetCellType(c);
    if (!rules.Types.empty() && !rules.Types.count(type))
    {
      why << "cell " << c << " has type " << type << ", not one this filter outputs";
      return why.str();
    }
    grid->GetCellPoints(c, npts, pts);
    const int expected = PointCount(type);
    if (expected >= 0 && npts != expected)
    {
      why << "cell " << c << " (type " << type << ") has " << npts << " points instead of "
          << expected;
      return why.str();
    }
    for (vtkIdType k = 0; k < npts; ++k)
    {
      if (pts[k] < 0 || pts[k] >= np)
      {
        why << "cell " << c << " refers to point " << pts[k] << " of " << np;
        return why.str();
      }
      for (vtkIdType j = 0; j < k && !rules.RepeatedPointOk; ++j)
      {
        if (pts[j] == pts[k])
        {
          why << "cell " << c << " uses point " << pts[k] << " twice";
          return why.str();
        }
      }
    }
    if (Faces(type).empty() || (!rules.PositiveVolume && !rules.ConsistentSign))
    {
      continue;
    }
    std::vector<std::array<double, 3>> p(static_cast<std::size_t>(npts));
    for (vtkIdType k = 0; k < npts; ++k)
    {
      grid->GetPoint(pts[k], p[static_cast<std::size_t>(k)].data());
    }
    const double v = type == VTK_TETRA ? TetSign(p[0].data(), p[1].data(), p[2].data(), p[3].data())
                                       : CellVolumeSign(type, p);
    if (rules.PositiveVolume && !(v > 0))
    {
      why << "cell " << c << " (type " << type << ") has " << (v < 0 ? "negative" : "zero")
          << " volume";
      return why.str();
    }
    if (rules.ConsistentSign && v != 0)
    {
      const int s = v > 0 ? 1 : -1;
      if (sign != 0 && s != sign)
      {
        why << "tetrahedra of both orientations (cell " << c << ")";
        return why.str();
      }
      sign = s;
    }
  }
  if (rules.FacesShared || rules.ClosedBoundary)
  {
    why << CheckConformity(grid, rules);
    if (!why.str().empty())
    {
      return why.str();
    }
  }
  if (!rules.Segmentation)
  {
    return "";
  }
  // The segmentation arrays (vtkFEMorphSegmentationArrays.h).
  vtkFieldData* fd = grid->GetFieldData();
  vtkDataArray* types = fd->GetArray("RegionType");
  vtkDataArray* regions = grid->GetCellData()->GetArray("FaceRegion");
  if (!types || !regions)
  {
    return "no RegionType or FaceRegion array";
  }
  const vtkIdType nr = types->GetNumberOfTuples();
  if (regions->GetNumberOfComponents() != 4)
  {
    return "FaceRegion has " + std::to_string(regions->GetNumberOfComponents()) + " components";
  }
  for (vtkIdType c = 0; c < nc; ++c)
  {
    for (int f = 0; f < 4; ++f)
    {
      const double r = regions->GetComponent(c, f);
      if (!(r >= -1 && r < nr && r == std::floor(r)))
      {
        why << "FaceRegion " << r << " at cell " << c << " (" << nr << " regions)";
        return why.str();
      }
    }
  }
  for (vtkIdType r = 0; r < nr; ++r)
  {
    const double t = types->GetComponent(r, 0);
    if (!(t >= 0 && t <= 5 && t == std::floor(t)))
    {
      why << "RegionType " << t << " at region " << r;
      return why.str();
    }
  }
  for (const char* name : { "RegionParameters", "RegionConvexity" })
  {
    vtkDataArray* a = fd->GetArray(name);
    if (!a || a->GetNumberOfTuples() != nr)
    {
      why << name << (a ? " has " + std::to_string(a->GetNumberOfTuples()) + " tuples" : " is missing")
          << " for " << nr << " regions";
      return why.str();
    }
  }
  if (vtkDataArray* classes = grid->GetPointData()->GetArray("VertexClass"))
  {
    for (vtkIdType i = 0; i < np; ++i)
    {
      const double v = classes->GetComponent(i, 0);
      if (!(v >= 0 && v <= 3))
      {
        why << "VertexClass " << v << " at point " << i;
        return why.str();
      }
    }
  }
  vtkDataArray* curveTypes = fd->GetArray("CurveType");
  vtkDataArray* offsets = fd->GetArray("CurveOffsets");
  vtkDataArray* vertices = fd->GetArray("CurveVertices");
  if (!curveTypes || !offsets || !vertices)
  {
    return "no CurveType, CurveOffsets or CurveVertices array";
  }
  const vtkIdType ncurves = curveTypes->GetNumberOfTuples();
  if (offsets->GetNumberOfTuples() != ncurves + 1)
  {
    why << "CurveOffsets has " << offsets->GetNumberOfTuples() << " tuples for " << ncurves
        << " curves";
    return why.str();
  }
  double previous = 0;
  for (vtkIdType c = 0; c <= ncurves; ++c)
  {
    const double o = offsets->GetComponent(c, 0);
    if ((c == 0 && o != 0) || o < previous || o > vertices->GetNumberOfTuples() ||
      (c == ncurves && o != vertices->GetNumberOfTuples()))
    {
      why << "CurveOffsets " << o << " at " << c;
      return why.str();
    }
    previous = o;
  }
  for (vtkIdType i = 0; i < vertices->GetNumberOfTuples(); ++i)
  {
    const double v = vertices->GetComponent(i, 0);
    if (!(v >= 0 && v < np))
    {
      why << "CurveVertices " << v << " at " << i << " (" << np << " points)";
      return why.str();
    }
  }
  for (const char* name : { "CurveParameters", "CurveClosed" })
  {
    vtkDataArray* a = fd->GetArray(name);
    if (!a || a->GetNumberOfTuples() != ncurves)
    {
      why << name << " does not have one tuple per curve";
      return why.str();
    }
  }
  return "";
}

/// FEMorph Mesh Quality passes the mesh through: its cells must be the
/// input's, the Inverted array must agree with the sign computed here.
std::string CheckQualityOutput(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output)
{
  MeshRules rules;
  rules.RepeatedPointOk = true;
  std::string why = CheckMesh(output, rules);
  if (!why.empty())
  {
    return why;
  }
  if (output->GetNumberOfCells() != input->GetNumberOfCells())
  {
    return "the output has " + std::to_string(output->GetNumberOfCells()) + " cells, the input " +
      std::to_string(input->GetNumberOfCells());
  }
  vtkDataArray* inverted = output->GetCellData()->GetArray("Inverted");
  if (output->GetNumberOfCells() > 0 && !inverted)
  {
    return "no Inverted array";
  }
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  for (vtkIdType c = 0; c < output->GetNumberOfCells(); ++c)
  {
    if (output->GetCellType(c) != VTK_TETRA)
    {
      continue;
    }
    output->GetCellPoints(c, npts, pts);
    double p[4][3];
    for (int k = 0; k < 4; ++k)
    {
      output->GetPoint(pts[k], p[k]);
    }
    const double v = TetSign(p[0], p[1], p[2], p[3]);
    const double flag = inverted->GetComponent(c, 0);
    // Only clear signs: the filter's exact test may differ from this
    // floating-point one near zero.
    if ((v < -1e-9 && flag != 1) || (v > 1e-9 && flag != 0))
    {
      std::ostringstream why2;
      why2 << "cell " << c << ": Inverted = " << flag << " but its volume is "
           << (v < 0 ? "negative" : "positive");
      return why2.str();
    }
  }
  return "";
}

bool IsEmpty(vtkDataObject* data)
{
  if (!data)
  {
    return true;
  }
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(data))
  {
    return grid->GetNumberOfCells() == 0 && grid->GetNumberOfPoints() == 0;
  }
  if (auto* poly = vtkPolyData::SafeDownCast(data))
  {
    return poly->GetNumberOfCells() == 0 && poly->GetNumberOfPoints() == 0;
  }
  if (auto* table = vtkTable::SafeDownCast(data))
  {
    return table->GetNumberOfRows() == 0;
  }
  return false;
}

//------------------------------------------------------------------------------
// The filters.

struct FilterRun
{
  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;
  std::vector<std::string> PipelineErrors; // the executive's ("returned failure")
  bool PipelineOk = true;
  std::vector<vtkSmartPointer<vtkDataObject>> Outputs;
};

/// Runs `algorithm` on `input` (and `reference` on port 1 when given), at
/// `time` when it is a number, recording its messages.
FilterRun RunAlgorithm(vtkAlgorithm* algorithm, vtkUnstructuredGrid* input,
  vtkUnstructuredGrid* reference, double time = std::nan(""))
{
  FilterRun run;
  vtkNew<Recorder> messages;
  messages->Observe(algorithm);
  vtkNew<Recorder> pipeline;
  pipeline->Observe(algorithm->GetExecutive());
  algorithm->SetInputDataObject(0, input);
  if (reference)
  {
    algorithm->SetInputDataObject(1, reference);
  }
  run.PipelineOk =
    (std::isnan(time) ? algorithm->GetExecutive()->Update() : algorithm->UpdateTimeStep(time)) != 0;
  run.Errors = messages->Errors;
  run.Warnings = messages->Warnings;
  run.PipelineErrors = pipeline->Errors;
  for (int port = 0; port < algorithm->GetNumberOfOutputPorts(); ++port)
  {
    run.Outputs.emplace_back(algorithm->GetOutputDataObject(port));
  }
  return run;
}

/**
 * Adapt's assembly: `input` shallow-copied into `assembly` (the input's
 * arrays shared, not changed) with the cell array MaterialId: 1 on the
 * tetrahedron nearest the centre of the points' box whose points are all
 * off the boundary (faces of one tetrahedron), 0 elsewhere. Cells with ids
 * out of range or another point count are skipped. Returns that
 * tetrahedron's shortest edge (the motion's scale: the space around it is
 * about as thick), 0 when no tetrahedron qualifies.
 */
double MakeAssembly(vtkUnstructuredGrid* input, vtkUnstructuredGrid* assembly)
{
  assembly->ShallowCopy(input);
  const vtkIdType numCells = input->GetNumberOfCells();
  const vtkIdType numPoints = input->GetNumberOfPoints();
  vtkNew<vtkIntArray> material;
  material->SetName("MaterialId");
  material->SetNumberOfValues(numCells);
  material->Fill(0);
  assembly->GetCellData()->AddArray(material);
  if (!input->GetPoints() || numPoints == 0)
  {
    return 0;
  }
  using Triple = std::array<vtkIdType, 3>;
  std::vector<Triple> faces;
  std::vector<vtkIdType> tets;
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    if (input->GetCellType(c) != VTK_TETRA)
    {
      continue;
    }
    input->GetCellPoints(c, npts, pts);
    if (npts != 4 || std::any_of(pts, pts + 4, [&](vtkIdType p) { return p < 0 || p >= numPoints; }))
    {
      continue;
    }
    tets.push_back(c);
    for (int f = 0; f < 4; ++f)
    {
      Triple t = { pts[(f + 1) % 4], pts[(f + 2) % 4], pts[(f + 3) % 4] };
      std::sort(t.begin(), t.end());
      faces.push_back(t);
    }
  }
  std::sort(faces.begin(), faces.end());
  std::vector<char> boundary(static_cast<std::size_t>(numPoints), 0);
  for (std::size_t i = 0; i < faces.size();)
  {
    std::size_t j = i;
    while (j < faces.size() && faces[j] == faces[i])
    {
      ++j;
    }
    if (j - i == 1)
    {
      for (const vtkIdType p : faces[i])
      {
        boundary[static_cast<std::size_t>(p)] = 1;
      }
    }
    i = j;
  }
  double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
  for (vtkIdType p = 0; p < numPoints; ++p)
  {
    double x[3];
    input->GetPoint(p, x);
    for (int k = 0; k < 3; ++k)
    {
      if (std::isfinite(x[k]))
      {
        lo[k] = std::min(lo[k], x[k]);
        hi[k] = std::max(hi[k], x[k]);
      }
    }
  }
  vtkIdType best = -1;
  double bestDistance = HUGE_VAL;
  for (const vtkIdType c : tets)
  {
    input->GetCellPoints(c, npts, pts);
    if (std::any_of(pts, pts + 4, [&](vtkIdType p) { return boundary[static_cast<std::size_t>(p)] != 0; }))
    {
      continue;
    }
    double d = 0;
    for (int k = 0; k < 3; ++k)
    {
      double centroid = 0;
      for (int v = 0; v < 4; ++v)
      {
        centroid += 0.25 * input->GetPoint(pts[v])[k];
      }
      d += (centroid - 0.5 * (lo[k] + hi[k])) * (centroid - 0.5 * (lo[k] + hi[k]));
    }
    if (d < bestDistance)
    {
      best = c;
      bestDistance = d;
    }
  }
  if (best < 0)
  {
    return 0;
  }
  material->SetValue(best, 1);
  input->GetCellPoints(best, npts, pts);
  double shortest = HUGE_VAL;
  for (int a = 0; a < 4; ++a)
  {
    for (int b = a + 1; b < 4; ++b)
    {
      double x[3], y[3];
      input->GetPoint(pts[a], x);
      input->GetPoint(pts[b], y);
      const double d2 = (x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) + (x[2] - y[2]) * (x[2] - y[2]);
      shortest = std::min(shortest, std::sqrt(d2));
    }
  }
  return std::isfinite(shortest) ? shortest : 0;
}

struct FilterSpec
{
  std::string Name;
  std::function<FilterRun(vtkUnstructuredGrid*, vtkUnstructuredGrid*, const CaseEntry&)> Run;
  /// Why the outputs of an accepted run are not valid; empty when valid.
  std::function<std::string(vtkUnstructuredGrid* input, const FilterRun&)> Check;
};

std::string CheckFirstOutput(const FilterRun& run, const MeshRules& rules)
{
  auto* grid = vtkUnstructuredGrid::SafeDownCast(run.Outputs.empty() ? nullptr : run.Outputs[0].Get());
  if (!grid)
  {
    return "no vtkUnstructuredGrid output";
  }
  return CheckMesh(grid, rules);
}

std::vector<FilterSpec> Filters()
{
  std::vector<FilterSpec> filters;
  filters.push_back({ "MeshQuality",
    [](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      vtkNew<vtkFEMorphMeshQuality> filter;
      return RunAlgorithm(filter, input, nullptr);
    },
    [](vtkUnstructuredGrid* input, const FilterRun& run) {
      auto* grid = vtkUnstructuredGrid::SafeDownCast(run.Outputs[0]);
      return grid ? CheckQualityOutput(input, grid) : std::string("no output");
    } });
  filters.push_back({ "Segment",
    [](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      vtkNew<vtkFEMorphSegment> filter;
      return RunAlgorithm(filter, input, nullptr);
    },
    [](vtkUnstructuredGrid*, const FilterRun& run) {
      MeshRules rules;
      rules.Types = { VTK_TETRA };
      rules.ConsistentSign = true;
      rules.FacesShared = true;
      rules.ClosedBoundary = true;
      auto* grid = vtkUnstructuredGrid::SafeDownCast(run.Outputs[0]);
      rules.Segmentation = grid && grid->GetNumberOfCells() > 0;
      std::string why = CheckFirstOutput(run, rules);
      auto* surface = vtkPolyData::SafeDownCast(run.Outputs[1]);
      if (why.empty() && surface && grid)
      {
        vtkDataArray* ids = surface->GetPointData()->GetArray("MeshPointId");
        for (vtkIdType i = 0; ids && i < ids->GetNumberOfTuples(); ++i)
        {
          const double v = ids->GetComponent(i, 0);
          if (!(v >= 0 && v < grid->GetNumberOfPoints()))
          {
            why = "surface MeshPointId " + std::to_string(v) + " out of range";
            break;
          }
        }
      }
      return why;
    } });
  filters.push_back({ "Improve",
    [](vtkUnstructuredGrid* input, vtkUnstructuredGrid* reference, const CaseEntry& c) {
      vtkNew<vtkFEMorphImprove> filter;
      if (c.Region != "-")
      {
        filter->SetRegionArrayName(c.Region.c_str());
      }
      return RunAlgorithm(filter, input, reference);
    },
    [](vtkUnstructuredGrid*, const FilterRun& run) {
      MeshRules rules;
      rules.Types = { VTK_TETRA };
      rules.PositiveVolume = true;
      rules.FacesShared = true;
      rules.ClosedBoundary = true;
      auto* grid = vtkUnstructuredGrid::SafeDownCast(run.Outputs[0]);
      rules.Segmentation = grid && grid->GetCellData()->GetArray("FaceRegion") &&
        grid->GetFieldData()->GetArray("RegionType");
      return CheckFirstOutput(run, rules);
    } });
  filters.push_back({ "Deform",
    [](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      // Distance on the first planar region (RegionType 0; region 0 when
      // the array says none), measured: classification, valid range and the
      // deformable region run on every case, the mesh stays as it is.
      vtkNew<vtkFEMorphDeform> filter;
      int control = 0;
      if (vtkDataArray* types = input->GetFieldData()->GetArray("RegionType"))
      {
        for (vtkIdType r = 0; r < types->GetNumberOfTuples() && types->GetNumberOfComponents() == 1; ++r)
        {
          if (types->GetComponent(r, 0) == 0)
          {
            control = static_cast<int>(r);
            break;
          }
        }
      }
      filter->SetControlRegion(control);
      return RunAlgorithm(filter, input, nullptr);
    },
    [](vtkUnstructuredGrid*, const FilterRun& run) {
      MeshRules rules;
      rules.Types = { VTK_TETRA };
      rules.FacesShared = true;
      rules.ClosedBoundary = true;
      return CheckFirstOutput(run, rules);
    } });
  filters.push_back({ "HexToTet",
    [](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      vtkNew<vtkFEMorphHexToTet> filter;
      return RunAlgorithm(filter, input, nullptr);
    },
    [](vtkUnstructuredGrid*, const FilterRun& run) {
      MeshRules rules;
      rules.Types = { VTK_TETRA };
      rules.PositiveVolume = true;
      rules.FacesShared = true;
      return CheckFirstOutput(run, rules);
    } });
  filters.push_back({ "TetToHex",
    [](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      vtkNew<vtkFEMorphTetToHex> filter;
      return RunAlgorithm(filter, input, nullptr);
    },
    [](vtkUnstructuredGrid*, const FilterRun& run) {
      MeshRules rules;
      rules.Types = { VTK_HEXAHEDRON, VTK_WEDGE, VTK_PYRAMID, VTK_TETRA };
      rules.PositiveVolume = true;
      return CheckFirstOutput(run, rules);
    } });
  filters.push_back({ "Adapt",
    [](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      // One inner tetrahedron as the object (MaterialId on a shallow copy),
      // moved by 5% of its shortest edge in one step: the core's whole step
      // runs on every case it accepts, and no motion that small is refused
      // (a refused step is an error with the last good mesh as output).
      vtkNew<vtkUnstructuredGrid> assembly;
      const double edge = MakeAssembly(input, assembly);
      vtkNew<vtkFEMorphAdapt> filter;
      filter->SetTranslationPerStep(0.05 * edge, 0, 0);
      filter->SetNumberOfSteps(1);
      return RunAlgorithm(filter, assembly, nullptr, 1.0);
    },
    [](vtkUnstructuredGrid*, const FilterRun& run) {
      MeshRules rules;
      rules.Types = { VTK_TETRA };
      rules.PositiveVolume = true;
      rules.FacesShared = true;
      rules.ClosedBoundary = true;
      return CheckFirstOutput(run, rules);
    } });
  return filters;
}

//------------------------------------------------------------------------------
// Self-test filters: known misbehaviours the runner must classify.
std::vector<FilterSpec> SelfTestFilters()
{
  const FilterSpec improve = Filters()[2];
  auto passThrough = [](vtkUnstructuredGrid* input) {
    FilterRun run;
    auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
    out->ShallowCopy(input);
    run.Outputs.emplace_back(out);
    return run;
  };
  std::vector<FilterSpec> filters;
  filters.push_back({ "SelfTest.Segfault",
    [](vtkUnstructuredGrid*, vtkUnstructuredGrid*, const CaseEntry&) -> FilterRun {
      // A store to a page without access: a real SIGSEGV, not undefined
      // behaviour UBSan would report first (as it does a null store).
      void* page = mmap(nullptr, 4096, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      *static_cast<volatile int*>(page) = 1;
      return {};
    },
    improve.Check });
  filters.push_back({ "SelfTest.Abort",
    [](vtkUnstructuredGrid*, vtkUnstructuredGrid*, const CaseEntry&) -> FilterRun {
      std::abort();
    },
    improve.Check });
  filters.push_back({ "SelfTest.Hang",
    [](vtkUnstructuredGrid*, vtkUnstructuredGrid*, const CaseEntry&) -> FilterRun {
      for (;;)
      {
        std::this_thread::sleep_for(std::chrono::seconds(1));
      }
    },
    improve.Check });
  filters.push_back({ "SelfTest.PassThrough",
    [passThrough](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      return passThrough(input);
    },
    improve.Check });
  filters.push_back({ "SelfTest.ErrorWithOutput",
    [passThrough](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      FilterRun run = passThrough(input);
      run.Errors.push_back("SelfTest: the FaceRegion array is bad");
      return run;
    },
    improve.Check });
  filters.push_back({ "SelfTest.Inverts",
    [](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      FilterRun run;
      auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
      out->DeepCopy(input);
      vtkIdType npts = 0;
      const vtkIdType* pts = nullptr;
      out->GetCellPoints(0, npts, pts);
      const vtkIdType swapped[4] = { pts[0], pts[2], pts[1], pts[3] };
      out->ReplaceCell(0, 4, swapped);
      run.Outputs.emplace_back(out);
      return run;
    },
    improve.Check });
  filters.push_back({ "SelfTest.ModifiesInput",
    [passThrough](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      double p[3];
      input->GetPoint(0, p);
      p[0] += 1e-3;
      input->GetPoints()->SetPoint(0, p);
      return passThrough(input);
    },
    improve.Check });
  auto stripped = [](vtkUnstructuredGrid* input) {
    FilterRun run;
    auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
    out->ShallowCopy(input);
    out->GetCellData()->RemoveArray("FaceRegion");
    run.Outputs.emplace_back(out);
    return run;
  };
  filters.push_back({ "SelfTest.DropsFaceRegion",
    [stripped](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      return stripped(input);
    },
    improve.Check });
  filters.push_back({ "SelfTest.WarnsVaguely",
    [stripped](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      FilterRun run = stripped(input);
      run.Warnings.push_back("SelfTest: something is odd");
      return run;
    },
    improve.Check });
  filters.push_back({ "SelfTest.Refuses",
    [](vtkUnstructuredGrid*, vtkUnstructuredGrid*, const CaseEntry&) {
      FilterRun run;
      run.Errors.push_back("SelfTest: the cell array FaceRegion is bad");
      run.PipelineOk = false;
      run.Outputs.emplace_back(vtkSmartPointer<vtkUnstructuredGrid>::New());
      return run;
    },
    improve.Check });
  filters.push_back({ "SelfTest.FailsQuietly",
    [](vtkUnstructuredGrid*, vtkUnstructuredGrid*, const CaseEntry&) {
      FilterRun run;
      run.PipelineOk = false;
      run.Outputs.emplace_back(vtkSmartPointer<vtkUnstructuredGrid>::New());
      return run;
    },
    improve.Check });
  filters.push_back({ "SelfTest.OverRead",
    [passThrough](vtkUnstructuredGrid* input, vtkUnstructuredGrid*, const CaseEntry&) {
      // Reads one value past a heap block: only AddressSanitizer sees it.
      std::vector<int> values(16, 1);
      volatile int sum = 0;
      const int* data = values.data();
      for (int i = 0; i <= 16; ++i)
      {
        sum += data[i];
      }
      return passThrough(input);
    },
    improve.Check });
  return filters;
}

//------------------------------------------------------------------------------
// One (case, filter) in the child.

struct ChildResult
{
  Outcome What = CorpusError;
  std::string Reason;
  std::vector<std::string> Messages;
};

/// The first line of `text`, shortened.
std::string FirstLine(const std::string& text)
{
  std::string line = text.substr(0, text.find('\n'));
  if (line.size() > 240)
  {
    line = line.substr(0, 237) + "...";
  }
  return line;
}

/// What a vtkErrorMacro / vtkWarningMacro message says, without its
/// "ERROR: In file, line N" line and "vtkClass (0x...): " prefix.
std::string MessageText(const std::string& text)
{
  std::string body = text;
  if (body.rfind("ERROR: In ", 0) == 0 || body.rfind("Warning: In ", 0) == 0)
  {
    const std::size_t eol = body.find('\n');
    body = eol == std::string::npos ? body : body.substr(eol + 1);
  }
  const std::size_t prefix = body.find("): ");
  if (prefix != std::string::npos && body.rfind("vtk", 0) == 0 && prefix < 80)
  {
    body = body.substr(prefix + 3);
  }
  while (!body.empty() && (body.back() == '\n' || body.back() == ' '))
  {
    body.pop_back();
  }
  return FirstLine(body);
}

vtkSmartPointer<vtkUnstructuredGrid> Read(const std::string& path, bool mayFail, std::string& error)
{
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  vtkNew<Recorder> messages;
  messages->Observe(reader);
  reader->SetFileName(path.c_str());
  reader->Update();
  if (!messages->Errors.empty() && !mayFail)
  {
    error = "the reader reported: " + MessageText(messages->Errors.front());
    return nullptr;
  }
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->ShallowCopy(reader->GetOutput());
  return grid;
}

bool ContainsAll(const std::vector<std::string>& messages, const std::vector<std::string>& needles,
  std::string& missing)
{
  std::string all;
  for (const std::string& m : messages)
  {
    all += m + "\n";
  }
  for (const std::string& needle : needles)
  {
    if (all.find(needle) == std::string::npos)
    {
      missing = needle;
      return false;
    }
  }
  return true;
}



ChildResult RunOne(const std::string& folder, const CaseEntry& c, const FilterSpec& filter)
{
  ChildResult result;
  const bool mayFail = c.Reader == "may-fail";
  std::string error;
  vtkSmartPointer<vtkUnstructuredGrid> input = Read(folder + "/" + c.File, mayFail, error);
  vtkSmartPointer<vtkUnstructuredGrid> reference;
  if (input && c.Reference != "-")
  {
    reference = Read(folder + "/" + c.Reference, mayFail, error);
  }
  if (!input || (c.Reference != "-" && !reference) ||
    !ApplyRecipes(c.Damage, false, input, error) ||
    !ApplyRecipes(c.Damage, true, reference, error))
  {
    result.What = CorpusError;
    result.Reason = error;
    return result;
  }
  const std::uint64_t inputBefore = FingerprintOf(input);
  const std::uint64_t referenceBefore = FingerprintOf(reference);
  const vtkIdType inputCells = input->GetNumberOfCells();

  FilterRun run = filter.Run(input, reference, c);

  for (const std::string& e : run.Errors)
  {
    result.Messages.push_back("error: " + MessageText(e));
  }
  for (const std::string& w : run.Warnings)
  {
    result.Messages.push_back("warning: " + MessageText(w));
  }
  std::vector<std::string> all = run.Errors;
  all.insert(all.end(), run.Warnings.begin(), run.Warnings.end());
  const bool mustReport = ListHas(c.ReportOn, filter.Name);
  const bool mustAccept = ListHas(c.ValidOn, filter.Name);
  const bool mustRefuse = ListHas(c.ErrorOn, filter.Name);
  const std::vector<std::string> expect = SplitList(c.Expect, '|');
  std::string missing;
  const bool named = !mustReport || ContainsAll(all, expect, missing);

  if (FingerprintOf(input) != inputBefore || FingerprintOf(reference) != referenceBefore)
  {
    result.What = InputModified;
    result.Reason = FingerprintOf(input) != inputBefore ? "the input grid was modified"
                                                        : "the Reference grid was modified";
    return result;
  }
  if (!run.Errors.empty())
  {
    bool empty = true;
    for (const auto& output : run.Outputs)
    {
      empty = empty && IsEmpty(output);
    }
    if (mustAccept)
    {
      result.What = RefusedValid;
      result.Reason = "error on a case without a fault: " + MessageText(run.Errors.front());
    }
    else if (!empty)
    {
      result.What = NotEmpty;
      result.Reason = "error reported but the output is not empty: " + MessageText(run.Errors.front());
    }
    else if (!named)
    {
      result.What = Unnamed;
      result.Reason = "the error does not name '" + missing + "': " + MessageText(run.Errors.front());
    }
    else
    {
      result.What = Refused;
      result.Reason = MessageText(run.Errors.front());
    }
    return result;
  }
  if (!run.PipelineOk)
  {
    result.What = NoMessage;
    result.Reason = "the filter failed without an error message" +
      (run.PipelineErrors.empty() ? std::string() : ": " + MessageText(run.PipelineErrors.front()));
    return result;
  }
  if (mustRefuse)
  {
    result.What = AcceptedCorrupt;
    result.Reason = "no error on a corrupt input (" + c.Description + ")" +
      (run.Warnings.empty() ? std::string() : "; warning: " + MessageText(run.Warnings.front()));
    return result;
  }
  std::string why = filter.Check(input, run);
  if (why.empty() && inputCells > 0 && !run.Outputs.empty() && IsEmpty(run.Outputs[0]))
  {
    why = "an empty output without an error";
  }
  if (!why.empty())
  {
    result.What = InvalidOutput;
    result.Reason = "accepted without an error, but the output is not valid: " + why;
    return result;
  }
  if (!named)
  {
    result.What = run.Warnings.empty() ? Silent : Unnamed;
    result.Reason = run.Warnings.empty()
      ? "accepted without any error or warning naming '" + missing + "'"
      : "accepted with a warning that does not name '" + missing + "': " +
        MessageText(run.Warnings.front());
    return result;
  }
  result.What = Accepted;
  result.Reason = run.Warnings.empty() ? "" : "warning: " + MessageText(run.Warnings.front());
  return result;
}

void WriteResult(const std::string& path, const ChildResult& result)
{
  std::ofstream out(path);
  out << static_cast<int>(result.What) << "\n" << result.Reason << "\n";
  for (const std::string& m : result.Messages)
  {
    out << m << "\n";
  }
}

bool ReadResult(const std::string& path, ChildResult& result)
{
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line) || line.empty())
  {
    return false;
  }
  const int what = std::atoi(line.c_str());
  if (what < 0 || what >= NumOutcomes)
  {
    return false;
  }
  result.What = static_cast<Outcome>(what);
  std::getline(in, result.Reason);
  while (std::getline(in, line))
  {
    result.Messages.push_back(line);
  }
  return true;
}

std::string ReadFile(const std::string& path)
{
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The first line of `log` containing `needle`, shortened; empty if none.
std::string LineWith(const std::string& log, const std::string& needle)
{
  const std::size_t at = log.find(needle);
  if (at == std::string::npos)
  {
    return "";
  }
  const std::size_t begin = log.rfind('\n', at) == std::string::npos ? 0 : log.rfind('\n', at) + 1;
  return FirstLine(log.substr(begin));
}

/// The first frame of a sanitizer stack trace in FEMorph's own code.
std::string FemorphFrame(const std::string& log)
{
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line))
  {
    const std::size_t in_at = line.find(" in ");
    if (line.find("    #") == 0 && in_at != std::string::npos &&
      (line.find("femorph") != std::string::npos || line.find("FEMorph") != std::string::npos))
    {
      std::string frame = line.substr(in_at + 4);
      const std::size_t paren = frame.find('(');
      const std::size_t space = frame.find(' ');
      std::string where = frame.substr(0, std::min(paren, space));
      const std::size_t file = frame.rfind('/');
      if (file != std::string::npos)
      {
        where += " at " + frame.substr(file + 1);
      }
      return where;
    }
  }
  return "";
}

//------------------------------------------------------------------------------
// The parent: jobs, children, table.

struct Job
{
  std::size_t Case = 0;
  std::size_t Filter = 0;
  pid_t Pid = -1;
  Clock::time_point Start;
  double Timeout = 0;
  bool TimedOut = false;
  std::string Log, ResultFile;
  ChildResult Result;
  double Seconds = 0;
};

std::string SignalName(int sig)
{
  switch (sig)
  {
    case SIGSEGV: return "SIGSEGV";
    case SIGABRT: return "SIGABRT";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGKILL: return "SIGKILL";
    case SIGTERM: return "SIGTERM";
    default: return "signal " + std::to_string(sig);
  }
}

/// The outcome of a child that ended without writing its result, or whose
/// log holds a sanitizer report.
void Classify(Job& job, int status)
{
  const std::string log = ReadFile(job.Log);
  const std::string frame = FemorphFrame(log);
  const std::string where = frame.empty() ? "" : " in " + frame;
  const std::string asanSegv = LineWith(log, "AddressSanitizer: SEGV");
  const std::string asan = LineWith(log, "ERROR: AddressSanitizer");
  const std::string ubsan = LineWith(log, "runtime error:");
  const std::string leak = LineWith(log, "ERROR: LeakSanitizer");
  if (job.TimedOut)
  {
    job.Result.What = Hang;
    job.Result.Reason = "still running after " + std::to_string(static_cast<int>(job.Timeout)) +
      " s (killed)";
    return;
  }
  if (!asanSegv.empty() || !LineWith(log, "AddressSanitizer: BUS").empty())
  {
    job.Result.What = Crash;
    job.Result.Reason = "SIGSEGV (AddressSanitizer)" + where + ": " + asanSegv;
    return;
  }
  if (!asan.empty())
  {
    job.Result.What = Sanitizer;
    const std::string access = LineWith(log, "READ of size").empty()
      ? LineWith(log, "WRITE of size")
      : LineWith(log, "READ of size");
    job.Result.Reason = "AddressSanitizer" + where + ": " +
      asan.substr(asan.find("AddressSanitizer")) + (access.empty() ? "" : " | " + access);
    return;
  }
  if (!ubsan.empty())
  {
    // "path/file.h:15:60: runtime error: ...": keep file:line and the error.
    const std::size_t at = ubsan.find(": runtime error:");
    const std::size_t slash = ubsan.rfind('/', at);
    const std::string location =
      ubsan.substr(slash == std::string::npos ? 0 : slash + 1, at - (slash == std::string::npos ? 0 : slash + 1));
    job.Result.What = Sanitizer;
    job.Result.Reason = "UBSan at " + location + ": " + ubsan.substr(at + 2);
    return;
  }
  if (!leak.empty())
  {
    job.Result.What = Sanitizer;
    job.Result.Reason = "LeakSanitizer" + where + ": " + leak;
    return;
  }
  if (WIFSIGNALED(status))
  {
    job.Result.What = Crash;
    job.Result.Reason = SignalName(WTERMSIG(status));
    return;
  }
  ChildResult written;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && ReadResult(job.ResultFile, written))
  {
    job.Result = written;
    return;
  }
  job.Result.What = Crash;
  job.Result.Reason = "exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
    " without a result";
  const std::string last = LineWith(log, "ERR|");
  if (!last.empty())
  {
    job.Result.Reason += ": " + last;
  }
}

struct Options
{
  std::string Cases;
  int Jobs = 2;
  double TimeoutScale = 1;
  std::vector<std::string> OnlyFilters;
  std::string OnlyCase;
  std::string Report;
  std::string Logs;
  bool Verbose = false;
  bool SelfTest = false;
};

int RunAll(const Options& options, const std::vector<CaseEntry>& cases,
  const std::vector<FilterSpec>& filters, std::vector<Job>& jobs)
{
  for (std::size_t c = 0; c < cases.size(); ++c)
  {
    if (!options.OnlyCase.empty() && cases[c].Name.find(options.OnlyCase) == std::string::npos)
    {
      continue;
    }
    for (std::size_t f = 0; f < filters.size(); ++f)
    {
      if (!options.SelfTest && !ListHas(cases[c].Filters, filters[f].Name))
      {
        continue;
      }
      if (!options.OnlyFilters.empty() &&
        std::find(options.OnlyFilters.begin(), options.OnlyFilters.end(), filters[f].Name) ==
          options.OnlyFilters.end())
      {
        continue;
      }
      Job job;
      job.Case = c;
      job.Filter = f;
      job.Timeout = cases[c].Timeout * options.TimeoutScale;
      jobs.push_back(job);
    }
  }
  // Slowest first (the large bases have the longest timeouts), so that the
  // workers finish together.
  std::stable_sort(jobs.begin(), jobs.end(),
    [](const Job& a, const Job& b) { return a.Timeout > b.Timeout; });

  const std::string scratch = options.Logs;
  std::filesystem::create_directories(scratch);
  std::size_t next = 0, done = 0;
  std::vector<std::size_t> running;
  std::cout.flush();
  std::cerr.flush();
  while (done < jobs.size())
  {
    while (next < jobs.size() && static_cast<int>(running.size()) < options.Jobs)
    {
      Job& job = jobs[next];
      const std::string stem = scratch + "/" + cases[job.Case].Name + "." + filters[job.Filter].Name;
      job.Log = stem + ".log";
      job.ResultFile = stem + ".result";
      std::remove(job.ResultFile.c_str());
      job.Start = Clock::now();
      const pid_t pid = fork();
      if (pid < 0)
      {
        std::perror("run_corpus: fork");
        return 2;
      }
      if (pid == 0)
      {
        // The child: its own process group (a hang is killed with whatever
        // it started), output into its log, the result into its file.
        setpgid(0, 0);
        const int fd = open(job.Log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0)
        {
          dup2(fd, STDOUT_FILENO);
          dup2(fd, STDERR_FILENO);
          close(fd);
        }
        const ChildResult result = RunOne(options.Cases, cases[job.Case], filters[job.Filter]);
        WriteResult(job.ResultFile, result);
        std::fflush(nullptr);
        _exit(0);
      }
      setpgid(pid, pid);
      job.Pid = pid;
      running.push_back(next);
      ++next;
    }
    int status = 0;
    const pid_t ended = waitpid(-1, &status, WNOHANG);
    if (ended > 0)
    {
      auto it = std::find_if(running.begin(), running.end(),
        [&](std::size_t j) { return jobs[j].Pid == ended; });
      if (it != running.end())
      {
        Job& job = jobs[*it];
        job.Seconds = std::chrono::duration<double>(Clock::now() - job.Start).count();
        Classify(job, status);
        // Keep the logs of failures only.
        if (Passes(job.Result.What))
        {
          std::remove(job.Log.c_str());
        }
        std::remove(job.ResultFile.c_str());
        if (options.Verbose)
        {
          std::cout << std::left << std::setw(52) << cases[job.Case].Name << std::setw(13)
                    << filters[job.Filter].Name << std::setw(14) << OutcomeNames[job.Result.What]
                    << std::fixed << std::setprecision(2) << job.Seconds << " s  "
                    << job.Result.Reason << "\n"
                    << std::flush;
        }
        running.erase(it);
        ++done;
      }
      continue;
    }
    for (std::size_t j : running)
    {
      Job& job = jobs[j];
      if (!job.TimedOut &&
        std::chrono::duration<double>(Clock::now() - job.Start).count() > job.Timeout)
      {
        job.TimedOut = true;
        kill(-job.Pid, SIGKILL);
        kill(job.Pid, SIGKILL);
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return 0;
}

int SelfTest(const Options& options, const std::vector<CaseEntry>& all)
{
  // A valid case and a damaged FaceRegion case of the corpus, through
  // filters that misbehave on purpose and through the real filters.
  std::vector<CaseEntry> cases;
  for (const CaseEntry& c : all)
  {
    if (c.Name == "box.valid" || c.Name == "box.FaceRegion.int.intmax")
    {
      cases.push_back(c);
      cases.back().Filters = "all";
      cases.back().Timeout = 4;
      if (c.Name != "box.valid")
      {
        cases.back().ReportOn = "all"; // every self-test filter "reads" FaceRegion
      }
    }
  }
  if (cases.size() != 2)
  {
    std::cerr << "run_corpus --self-test: box.valid or box.FaceRegion.int.intmax missing\n";
    return 2;
  }
  std::vector<FilterSpec> filters = SelfTestFilters();
  std::vector<Job> jobs;
  Options o = options;
  o.SelfTest = true;
  if (RunAll(o, cases, filters, jobs) != 0)
  {
    return 2;
  }
#if defined(__SANITIZE_ADDRESS__)
  const bool asan = true;
#else
  const bool asan = false;
#endif
  // Expected outcome per (case, filter): valid case first.
  const std::map<std::pair<std::string, std::string>, Outcome> expected = {
    { { "box.valid", "SelfTest.Segfault" }, Crash },
    { { "box.valid", "SelfTest.Abort" }, Crash },
    { { "box.valid", "SelfTest.Hang" }, Hang },
    { { "box.valid", "SelfTest.PassThrough" }, Accepted },
    { { "box.valid", "SelfTest.ErrorWithOutput" }, RefusedValid },
    { { "box.valid", "SelfTest.Inverts" }, InvalidOutput },
    { { "box.valid", "SelfTest.ModifiesInput" }, InputModified },
    { { "box.valid", "SelfTest.OverRead" }, asan ? Sanitizer : Accepted },
    { { "box.valid", "SelfTest.DropsFaceRegion" }, Accepted },
    { { "box.valid", "SelfTest.WarnsVaguely" }, Accepted },
    { { "box.valid", "SelfTest.Refuses" }, RefusedValid },
    { { "box.valid", "SelfTest.FailsQuietly" }, NoMessage },
    { { "box.FaceRegion.int.intmax", "SelfTest.Segfault" }, Crash },
    { { "box.FaceRegion.int.intmax", "SelfTest.Abort" }, Crash },
    { { "box.FaceRegion.int.intmax", "SelfTest.Hang" }, Hang },
    { { "box.FaceRegion.int.intmax", "SelfTest.Inverts" }, InvalidOutput },
    { { "box.FaceRegion.int.intmax", "SelfTest.ModifiesInput" }, InputModified },
    { { "box.FaceRegion.int.intmax", "SelfTest.PassThrough" }, InvalidOutput },
    { { "box.FaceRegion.int.intmax", "SelfTest.ErrorWithOutput" }, NotEmpty },
    { { "box.FaceRegion.int.intmax", "SelfTest.DropsFaceRegion" }, Silent },
    { { "box.FaceRegion.int.intmax", "SelfTest.WarnsVaguely" }, Unnamed },
    { { "box.FaceRegion.int.intmax", "SelfTest.Refuses" }, Refused },
    { { "box.FaceRegion.int.intmax", "SelfTest.FailsQuietly" }, NoMessage },
    { { "box.FaceRegion.int.intmax", "SelfTest.OverRead" }, asan ? Sanitizer : InvalidOutput },
  };
  int wrong = 0;
  for (const Job& job : jobs)
  {
    const auto key = std::make_pair(cases[job.Case].Name, filters[job.Filter].Name);
    const auto it = expected.find(key);
    const bool ok = it != expected.end() && it->second == job.Result.What;
    std::cout << (ok ? "ok    " : "WRONG ") << std::left << std::setw(28) << key.first
              << std::setw(26) << key.second << std::setw(14) << OutcomeNames[job.Result.What]
              << job.Result.Reason << "\n";
    wrong += ok ? 0 : 1;
  }
  std::cout << (wrong == 0 ? "run_corpus self-test: all outcomes as expected\n"
                           : "run_corpus self-test: " + std::to_string(wrong) + " wrong outcomes\n");
  return wrong == 0 ? 0 : 1;
}

void Usage()
{
  std::cerr
    << "usage: run_corpus --cases <folder with manifest.tsv> [options]\n"
       "  --jobs N               children at a time (default 2)\n"
       "  --timeout-scale S      multiply every case's timeout (e.g. 4 under sanitizers)\n"
       "  --filter NAME          only this filter (repeatable): MeshQuality, Segment, Improve,\n"
       "                         Deform, HexToTet, TetToHex, Adapt\n"
       "  --case TEXT            only cases whose name contains TEXT\n"
       "  --report FILE          every (case, filter) with its outcome, as TSV\n"
       "  --logs DIR             the children's logs (kept for failures; default\n"
       "                         <cases>/logs)\n"
       "  --verbose              one line per (case, filter) as it ends\n"
       "  --self-test            check the runner on filters that misbehave on purpose\n";
}

} // namespace

int main(int argc, char* argv[])
{
  Options options;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        Usage();
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--cases")
      options.Cases = value();
    else if (arg == "--jobs")
      options.Jobs = std::max(1, std::stoi(value()));
    else if (arg == "--timeout-scale")
      options.TimeoutScale = std::stod(value());
    else if (arg == "--filter")
      options.OnlyFilters.push_back(value());
    else if (arg == "--case")
      options.OnlyCase = value();
    else if (arg == "--report")
      options.Report = value();
    else if (arg == "--logs")
      options.Logs = value();
    else if (arg == "--verbose")
      options.Verbose = true;
    else if (arg == "--self-test")
      options.SelfTest = true;
    else
    {
      Usage();
      return 2;
    }
  }
  if (options.Cases.empty())
  {
    Usage();
    return 2;
  }
  if (options.Logs.empty())
  {
    options.Logs = options.Cases + "/logs";
  }
  std::vector<CaseEntry> cases;
  std::string error;
  if (!femorph_corpus::ReadManifest(options.Cases + "/manifest.tsv", cases, error))
  {
    std::cerr << "run_corpus: " << error << "\n";
    return 2;
  }
  if (options.SelfTest)
  {
    return SelfTest(options, cases);
  }

  const auto start = Clock::now();
  const std::vector<FilterSpec> filters = Filters();
  // Every filter a case names must be in the table (a typo would silently
  // drop an expectation).
  for (const CaseEntry& c : cases)
  {
    for (const std::string& list : { c.ValidOn, c.ReportOn, c.ErrorOn, c.Filters })
    {
      for (const std::string& name : SplitList(list, ','))
      {
        const bool known = name == "all" ||
          std::any_of(filters.begin(), filters.end(),
            [&](const FilterSpec& f) { return f.Name == name; });
        if (!known)
        {
          std::cerr << "run_corpus: case " << c.Name << " names the filter '" << name
                    << "', which is not in the runner's table\n";
          return 2;
        }
      }
    }
  }
  std::vector<Job> jobs;
  if (RunAll(options, cases, filters, jobs) != 0)
  {
    return 2;
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

  // The table: filter x outcome.
  std::map<std::string, std::array<int, NumOutcomes>> counts;
  for (const FilterSpec& f : filters)
  {
    counts[f.Name].fill(0);
  }
  for (const Job& job : jobs)
  {
    ++counts[filters[job.Filter].Name][job.Result.What];
  }
  std::array<bool, NumOutcomes> used{};
  for (const Job& job : jobs)
  {
    used[job.Result.What] = true;
  }
  used[Refused] = used[Accepted] = true;
  std::cout << "\nFEMorph malformed-input corpus: " << cases.size() << " cases, " << jobs.size()
            << " (case, filter) runs in " << std::fixed << std::setprecision(1) << seconds
            << " s with " << options.Jobs << " jobs\n\n";
  std::cout << std::left << std::setw(13) << "filter";
  for (int o = 0; o < NumOutcomes; ++o)
  {
    if (used[o])
    {
      std::cout << std::right << std::setw(std::max<int>(8, std::strlen(OutcomeNames[o]) + 2))
                << OutcomeNames[o];
    }
  }
  std::cout << std::right << std::setw(8) << "runs" << "\n";
  for (const FilterSpec& f : filters)
  {
    int total = 0;
    std::cout << std::left << std::setw(13) << f.Name;
    for (int o = 0; o < NumOutcomes; ++o)
    {
      total += counts[f.Name][o];
      if (used[o])
      {
        std::cout << std::right << std::setw(std::max<int>(8, std::strlen(OutcomeNames[o]) + 2))
                  << counts[f.Name][o];
      }
    }
    std::cout << std::right << std::setw(8) << total << "\n";
  }
  std::cout << "\n(error and valid meet the contract; every other column is a failure)\n";

  // The failures.
  std::vector<const Job*> failures;
  for (const Job& job : jobs)
  {
    if (!Passes(job.Result.What))
    {
      failures.push_back(&job);
    }
  }
  std::stable_sort(failures.begin(), failures.end(), [](const Job* a, const Job* b) {
    return a->Result.What < b->Result.What;
  });

  if (!failures.empty())
  {
    std::cout << "\nFailing (case, filter) pairs: " << failures.size() << "\n";
  }
  for (const Job* job : failures)
  {
    const CaseEntry& c = cases[job->Case];
    std::cout << "  FAIL  " << std::left << std::setw(50) << c.Name
              << std::setw(12) << filters[job->Filter].Name << std::setw(11)
              << OutcomeNames[job->Result.What] << job->Result.Reason << "\n";
  }
  if (!options.Report.empty())
  {
    std::ofstream out(options.Report);
    out << "#case\tfilter\toutcome\tseconds\treason\tmessages\n";
    for (const Job& job : jobs)
    {
      out << cases[job.Case].Name << '\t' << filters[job.Filter].Name << '\t'
          << OutcomeNames[job.Result.What] << '\t' << job.Seconds << '\t' << job.Result.Reason
          << '\t';
      for (std::size_t m = 0; m < job.Result.Messages.size(); ++m)
      {
        out << (m ? " || " : "") << job.Result.Messages[m];
      }
      out << '\n';
    }
  }
  const int passed = static_cast<int>(jobs.size() - failures.size());
  std::cout << "\ncorpus: " << passed << " passed, " << failures.size() << " failed\n";
  return failures.empty() ? 0 : 1;
}
