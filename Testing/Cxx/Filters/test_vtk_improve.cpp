// FEMorph Improve (vtkFEMorphImprove) on the Data/ parts: the acceptance
// cases of docs/ARCHITECTURE.md ("Goals the tests and benchmarks check") -- (a) inner vertices moved randomly by
// up to 40% of the local edge length, (b) the boss's slab stretched x1.6 and
// x3 along z (a boss-height change, thesis Fig. 2.53), (c) surface vertices
// slid along their planes (inverted and flat tets) -- checked with the
// independent validity checker and closed-form surface distances; bad input.
#include "vtkFEMorphImprove.h"
#include "vtkFEMorphSegment.h"

#include "filters_test_utils.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "geometry/predicates.h"
#include "geometry/surface_primitive.h"
#include "quality/check_validity.h"
#include "quality/tet_quality.h"
#include "segment/segmentation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <vector>

namespace
{
using femorph::Tet;
using femorph::Vec3;

struct Arrays
{
  std::vector<Vec3> Points;
  std::vector<Tet> Tets;
};

Arrays ToArrays(vtkUnstructuredGrid* grid)
{
  Arrays a;
  a.Points.resize(static_cast<std::size_t>(grid->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    grid->GetPoint(i, a.Points[static_cast<std::size_t>(i)].data());
  }
  a.Tets.resize(static_cast<std::size_t>(grid->GetNumberOfCells()));
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    vtkIdType n = 0;
    const vtkIdType* p = nullptr;
    grid->GetCellPoints(c, n, p);
    EXPECT_EQ(n, 4);
    for (int k = 0; k < 4 && k < n; ++k)
    {
      a.Tets[static_cast<std::size_t>(c)][k] = static_cast<femorph::index_t>(p[k]);
    }
  }
  return a;
}

struct Quality
{
  double Min = 0, Mean = 0, Volume = 0;
  std::size_t Inverted = 0;
};

Quality Measure(const Arrays& a)
{
  Quality q;
  q.Min = std::numeric_limits<double>::infinity();
  for (const Tet& t : a.Tets)
  {
    const Vec3 &p0 = a.Points[t[0]], &p1 = a.Points[t[1]], &p2 = a.Points[t[2]], &p3 = a.Points[t[3]];
    const double s = femorph::tet_stretch(p0, p1, p2, p3);
    q.Min = std::min(q.Min, s);
    q.Mean += s;
    q.Volume += femorph::tet_signed_volume(p0, p1, p2, p3);
    q.Inverted += femorph::orient3d_sign(p0, p1, p2, p3) <= 0;
  }
  q.Mean /= static_cast<double>(a.Tets.size());
  return q;
}

vtkSmartPointer<vtkUnstructuredGrid> WithPoints(vtkUnstructuredGrid* grid, const std::vector<Vec3>& points)
{
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->DeepCopy(grid);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    out->GetPoints()->SetPoint(static_cast<vtkIdType>(i), points[i].data());
  }
  return out;
}

vtkSmartPointer<vtkUnstructuredGrid> Segmented(vtkUnstructuredGrid* grid)
{
  vtkNew<vtkFEMorphSegment> segment;
  segment->SetInputData(grid);
  segment->Update();
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->DeepCopy(segment->GetMeshOutput());
  return out;
}

double Field(vtkUnstructuredGrid* grid, const char* name, const char* component)
{
  vtkDataArray* a = grid->GetFieldData()->GetArray(name);
  if (!a)
  {
    ADD_FAILURE() << "no field array " << name;
    return std::numeric_limits<double>::quiet_NaN();
  }
  for (int i = 0; i < a->GetNumberOfComponents(); ++i)
  {
    if (a->GetComponentName(i) && std::string(a->GetComponentName(i)) == component)
    {
      return a->GetComponent(0, i);
    }
  }
  ADD_FAILURE() << name << " has no component " << component;
  return std::numeric_limits<double>::quiet_NaN();
}

/// Stretches the slab lo <= z <= hi by `factor` and shifts what is above.
std::vector<Vec3> StretchSlab(std::vector<Vec3> points, double lo, double hi, double factor)
{
  for (Vec3& p : points)
  {
    const double z = p.z();
    p.z() = z <= lo ? z : (z >= hi ? z + (factor - 1) * (hi - lo) : lo + factor * (z - lo));
  }
  return points;
}

/// Points on boundary faces, and the regions of those faces.
std::vector<std::set<int>> PointRegions(vtkUnstructuredGrid* grid, const Arrays& a)
{
  std::vector<std::set<int>> regions(a.Points.size());
  vtkDataArray* fr = grid->GetCellData()->GetArray("FaceRegion");
  EXPECT_NE(fr, nullptr);
  if (!fr)
  {
    return regions;
  }
  for (std::size_t t = 0; t < a.Tets.size(); ++t)
  {
    for (int f = 0; f < 4; ++f)
    {
      const int r = static_cast<int>(fr->GetComponent(static_cast<vtkIdType>(t), f));
      if (r < 0)
      {
        continue;
      }
      for (int k = 0; k < 4; ++k)
      {
        if (k != f)
        {
          regions[a.Tets[t][k]].insert(r);
        }
      }
    }
  }
  return regions;
}

/// Largest distance of a boundary point that Improve made or moved to the
/// fitted surface of a region it lies on (fitted regions only), over the
/// part's size.
double MaxSurfaceDistance(vtkUnstructuredGrid* grid, const Arrays& a, vtkUnstructuredGrid* inputGrid)
{
  std::set<std::array<double, 3>> input;
  for (const Vec3& p : ToArrays(inputGrid).Points)
  {
    input.insert({ p.x(), p.y(), p.z() });
  }
  vtkDataArray* types = grid->GetFieldData()->GetArray("RegionType");
  vtkDataArray* params = grid->GetFieldData()->GetArray("RegionParameters");
  EXPECT_TRUE(types && params);
  if (!types || !params)
  {
    return 1;
  }
  std::vector<femorph::SurfacePrimitive> surfaces(static_cast<std::size_t>(types->GetNumberOfTuples()));
  for (vtkIdType r = 0; r < types->GetNumberOfTuples(); ++r)
  {
    std::vector<double> row(static_cast<std::size_t>(params->GetNumberOfComponents()));
    params->GetTuple(r, row.data());
    surfaces[static_cast<std::size_t>(r)] = femorph::unpack_region_surface(
      static_cast<femorph::SurfaceType>(std::lround(types->GetComponent(r, 0))), row.data());
  }
  double bounds[6];
  grid->GetBounds(bounds);
  const double size = std::hypot(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]);
  const auto regions = PointRegions(grid, a);
  double worst = 0;
  for (std::size_t v = 0; v < a.Points.size(); ++v)
  {
    for (const int r : regions[v])
    {
      if (surfaces[static_cast<std::size_t>(r)].type == femorph::SurfaceType::Unknown)
      {
        continue;
      }
      if (input.count({ a.Points[v].x(), a.Points[v].y(), a.Points[v].z() }))
      {
        continue;  // an input point left in place: on the surface up to the fit's residual
      }
      worst = std::max(worst, femorph::distance(surfaces[static_cast<std::size_t>(r)], a.Points[v]));
    }
  }
  return worst / size;
}

/// What every output must be: a valid conforming mesh (the independent
/// checker) without inverted or flat tets, with Stretch and Inverted arrays.
void ExpectValid(vtkUnstructuredGrid* out, const Arrays& a)
{
  const femorph::ValidityReport report = femorph::check_validity(a.Points, a.Tets);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(Measure(a).Inverted, 0u);
  EXPECT_NE(out->GetCellData()->GetArray("Stretch"), nullptr);
  EXPECT_NE(out->GetCellData()->GetArray("Inverted"), nullptr);
}

/// The curve vertex lists of the output are chains of existing edges.
void ExpectCurvesConsistent(vtkUnstructuredGrid* out, const Arrays& a)
{
  vtkDataArray* vertices = out->GetFieldData()->GetArray("CurveVertices");
  vtkDataArray* offsets = out->GetFieldData()->GetArray("CurveOffsets");
  ASSERT_TRUE(vertices && offsets);
  std::set<std::pair<vtkIdType, vtkIdType>> edges;
  for (const Tet& t : a.Tets)
  {
    for (int i = 0; i < 4; ++i)
    {
      for (int j = i + 1; j < 4; ++j)
      {
        edges.insert({ std::min(t[i], t[j]), std::max(t[i], t[j]) });
      }
    }
  }
  std::size_t nonEmpty = 0;
  for (vtkIdType c = 0; c + 1 < offsets->GetNumberOfTuples(); ++c)
  {
    const auto b = static_cast<vtkIdType>(offsets->GetComponent(c, 0));
    const auto e = static_cast<vtkIdType>(offsets->GetComponent(c + 1, 0));
    nonEmpty += e > b;
    for (vtkIdType i = b; i + 1 < e; ++i)
    {
      const auto u = static_cast<vtkIdType>(vertices->GetComponent(i, 0));
      const auto w = static_cast<vtkIdType>(vertices->GetComponent(i + 1, 0));
      EXPECT_TRUE(edges.count({ std::min(u, w), std::max(u, w) })) << "curve " << c << " at " << i;
    }
  }
  EXPECT_GT(nonEmpty, 0u);
}

struct ImproveRun
{
  vtkSmartPointer<vtkUnstructuredGrid> Output;
  Arrays Out;
  Quality Before, After;
};

ImproveRun Improve(vtkUnstructuredGrid* input, vtkUnstructuredGrid* reference,
  const std::function<void(vtkFEMorphImprove*)>& configure = {})
{
  ImproveRun run;
  run.Before = Measure(ToArrays(input));
  vtkNew<vtkFEMorphImprove> improve;
  improve->SetInputData(input);
  if (reference)
  {
    improve->SetReferenceData(reference);
  }
  if (configure)
  {
    configure(improve);
  }
  improve->Update();
  run.Output = improve->GetOutput();
  run.Out = ToArrays(run.Output);
  if (!run.Out.Tets.empty())
  {
    run.After = Measure(run.Out);
  }
  std::printf("  stretch min %.3f -> %.3f, mean %.3f -> %.3f; tets %zu -> %zu; density error %.3f -> %.3f; "
              "%.2f s\n",
    run.Before.Min, run.After.Min, run.Before.Mean, run.After.Mean, static_cast<std::size_t>(input->GetNumberOfCells()),
    run.Out.Tets.size(), Field(run.Output, "ImproveDensityError", "Before"),
    Field(run.Output, "ImproveDensityError", "After"), Field(run.Output, "ImproveTimes", "Total"));
  return run;
}

/// ImproveStepTimes splits the time after the segmentation by step: none
/// negative, together no more than that time and most of it.
void ExpectStepTimesAddUp(vtkUnstructuredGrid* out)
{
  vtkDataArray* steps = out->GetFieldData()->GetArray("ImproveStepTimes");
  ASSERT_NE(steps, nullptr);
  ASSERT_EQ(steps->GetNumberOfComponents(), 8);
  double sum = 0;
  for (int i = 0; i < steps->GetNumberOfComponents(); ++i)
  {
    EXPECT_GE(steps->GetComponent(0, i), 0.0) << steps->GetComponentName(i);
    sum += steps->GetComponent(0, i);
  }
  const double improve = Field(out, "ImproveTimes", "Total") - Field(out, "ImproveTimes", "Segmentation");
  EXPECT_LE(sum, improve + 1e-9);
  EXPECT_GE(sum, 0.5 * improve);
  EXPECT_GT(Field(out, "ImproveStepTimes", "Density"), 0.0);
  EXPECT_GT(Field(out, "ImproveStepTimes", "Smoothing"), 0.0);
}

/// Every region's largest geometric error is within its acceptable error.
void ExpectAccuracyKept(vtkUnstructuredGrid* out)
{
  vtkDataArray* err = out->GetFieldData()->GetArray("GeometricError");
  vtkDataArray* ok = out->GetFieldData()->GetArray("AcceptableGeometricError");
  ASSERT_TRUE(err && ok);
  ASSERT_EQ(err->GetNumberOfTuples(), ok->GetNumberOfTuples());
  for (vtkIdType r = 0; r < err->GetNumberOfTuples(); ++r)
  {
    if (std::isnan(ok->GetComponent(r, 0)))
    {
      continue;
    }
    EXPECT_LE(err->GetComponent(r, 0), ok->GetComponent(r, 0) * (1 + 1e-9)) << "region " << r;
  }
}

/// The goals every case must meet (docs/ARCHITECTURE.md): a valid output, the minimum
/// stretch reached, the mean stretch at least the undeformed mesh's, the
/// points Improve placed on their fitted surfaces (1e-9 of the part's size)
/// and every curved region's chord error within its acceptable error.
void ExpectGoals(const ImproveRun& run, vtkUnstructuredGrid* input, double minGoal, double undeformedMean)
{
  ASSERT_GT(run.Out.Tets.size(), 0u);
  ExpectValid(run.Output, run.Out);
  EXPECT_GE(run.After.Min, minGoal);
  EXPECT_GE(run.After.Mean, undeformedMean);
  EXPECT_LE(MaxSurfaceDistance(run.Output, run.Out, input), 1e-9);
  ExpectAccuracyKept(run.Output);
}

/// Eq. 2.35 of the undeformed mesh against its own density field: what a
/// mesh generator's output scores (the Data parts score 0.15 to 0.19
/// themselves; the goal for the improved mesh is 0.15).
double OwnDensityError(vtkUnstructuredGrid* mesh)
{
  vtkNew<vtkFEMorphImprove> improve;
  improve->SetInputData(mesh);
  improve->SetMaxLoops(1);
  improve->Update();
  return Field(improve->GetOutput(), "ImproveDensityError", "Before");
}

/// Issue 5 (b) on boss_block: the part (segmented, the reference), its
/// undeformed mean stretch and the part with the boss's slab (z from the
/// block's top, 20, to the boss's top, 35) stretched by `factor` along its
/// axis (segmented).
struct StretchedBoss
{
  vtkSmartPointer<vtkUnstructuredGrid> Reference, Deformed;
  double UndeformedMean = 0;
};

StretchedBoss StretchBoss(double factor)
{
  StretchedBoss out;
  auto part = femorph_test::ReadPart("boss_block.vtu");
  if (!part)
  {
    ADD_FAILURE() << "boss_block.vtu not found";
    return out;
  }
  out.Reference = Segmented(part);
  const Arrays original = ToArrays(part);
  out.UndeformedMean = Measure(original).Mean;
  out.Deformed = Segmented(WithPoints(part, StretchSlab(original.Points, 20, 35, factor)));
  return out;
}

// Issue 5 (b): the boss's slab stretched x1.6 along its axis; the
// reference is the part before.
TEST(Improve, BossHeightStretch16)
{
  const StretchedBoss boss = StretchBoss(1.6);
  ASSERT_NE(boss.Deformed, nullptr);
  vtkUnstructuredGrid* deformed = boss.Deformed;
  vtkUnstructuredGrid* reference = boss.Reference;
  const vtkMTimeType inputTime = deformed->GetMTime();
  ImproveRun run = Improve(deformed, reference);
  EXPECT_EQ(deformed->GetMTime(), inputTime);
  ExpectGoals(run, deformed, 0.2, boss.UndeformedMean);
  const double before = Field(run.Output, "ImproveDensityError", "Before");
  const double after = Field(run.Output, "ImproveDensityError", "After");
  // Eq. 2.35, as in thesis 2.7.4 (Table 2.14: 0.26 deformed -> 0.15).
  EXPECT_LT(after, before);
  EXPECT_LE(after, 0.15);
  // The undeformed part scores what a mesh generator's output does (the Data
  // parts: 0.15 to 0.19; boss_block 0.17); the improved stretched part is
  // more even than that (0.14).
  const double own = OwnDensityError(reference);
  std::printf("  density error of the undeformed mesh against its own field: %.3f\n", own);
  EXPECT_GE(own, 0.15);
  EXPECT_LE(own, 0.19);
  EXPECT_LT(after, own - 0.01);
  ExpectCurvesConsistent(run.Output, run.Out);
  EXPECT_NEAR(run.After.Volume, run.Before.Volume, 2e-3 * run.Before.Volume);
}

TEST(Improve, BossHeightStretch3)
{
  const StretchedBoss boss = StretchBoss(3.0);
  ASSERT_NE(boss.Deformed, nullptr);
  vtkUnstructuredGrid* reference = boss.Reference;
  ImproveRun run = Improve(boss.Deformed, reference);
  ExpectGoals(run, boss.Deformed, 0.2, boss.UndeformedMean);
  EXPECT_LE(Field(run.Output, "ImproveDensityError", "After"), 0.15);  // the goal of case (b)
  EXPECT_LT(Field(run.Output, "ImproveDensityError", "After"), OwnDensityError(reference));
  ExpectStepTimesAddUp(run.Output);
}

// PoorElementsOnly on case (b) x1.6: the poor tets repaired to the
// case's goal, the rest of the mesh as it was (most points where they were,
// about the same number of tets), no density target (NaN), and the same
// checks as the phased loop's output: valid, points on their surfaces,
// chords within the acceptable error.
TEST(Improve, PoorElementsOnly)
{
  const StretchedBoss boss = StretchBoss(1.6);
  ASSERT_NE(boss.Deformed, nullptr);
  ImproveRun run = Improve(boss.Deformed, boss.Reference, [](vtkFEMorphImprove* f) { f->PoorElementsOnlyOn(); });
  ExpectGoals(run, boss.Deformed, 0.2, 0.0);
  EXPECT_GE(run.After.Mean, run.Before.Mean);
  EXPECT_TRUE(std::isnan(Field(run.Output, "ImproveDensityError", "After")));
  EXPECT_EQ(Field(run.Output, "ImproveCounts", "Collapses"), 0.0);
  const Arrays in = ToArrays(boss.Deformed);
  const double tets = static_cast<double>(in.Tets.size());
  EXPECT_NEAR(static_cast<double>(run.Out.Tets.size()), tets, 0.05 * tets);  // flips 3-2 remove a few
  std::set<std::array<double, 3>> inputPoints;
  for (const Vec3& p : in.Points)
  {
    inputPoints.insert({ p.x(), p.y(), p.z() });
  }
  std::size_t unmoved = 0;
  for (const Vec3& p : run.Out.Points)
  {
    unmoved += inputPoints.count({ p.x(), p.y(), p.z() });
  }
  std::printf("  %zu of %zu input points where they were\n", unmoved, in.Points.size());
  EXPECT_GE(static_cast<double>(unmoved), 0.7 * static_cast<double>(in.Points.size()));
}

// QualityFloor: with Poor Elements Only at 0.2 instead of 0.3, the tets
// below 0.2 are repaired (the minimum reaches most of the way) and more of
// the mesh is left as it is: over 10% more input points where they were,
// no more splits.
TEST(Improve, QualityFloor)
{
  const StretchedBoss boss = StretchBoss(1.6);
  ASSERT_NE(boss.Deformed, nullptr);
  ImproveRun at3 = Improve(boss.Deformed, boss.Reference, [](vtkFEMorphImprove* f) { f->PoorElementsOnlyOn(); });
  ImproveRun at2 = Improve(boss.Deformed, boss.Reference, [](vtkFEMorphImprove* f) {
    f->PoorElementsOnlyOn();
    f->SetQualityFloor(0.2);
  });
  ASSERT_LT(at3.Before.Min, 0.2);
  ExpectGoals(at2, boss.Deformed, 0.15, 0.0);
  EXPECT_GE(at2.After.Mean, at2.Before.Mean);
  const Arrays in = ToArrays(boss.Deformed);
  std::set<std::array<double, 3>> inputPoints;
  for (const Vec3& p : in.Points)
  {
    inputPoints.insert({ p.x(), p.y(), p.z() });
  }
  const auto unmoved = [&](const ImproveRun& run) {
    std::size_t n = 0;
    for (const Vec3& p : run.Out.Points)
    {
      n += inputPoints.count({ p.x(), p.y(), p.z() });
    }
    return n;
  };
  std::printf("  floor 0.3: min %.3f, %zu points unmoved, %.0f splits; floor 0.2: min %.3f, %zu, %.0f\n",
    at3.After.Min, unmoved(at3), Field(at3.Output, "ImproveCounts", "Splits"), at2.After.Min, unmoved(at2),
    Field(at2.Output, "ImproveCounts", "Splits"));
  EXPECT_GT(unmoved(at2), unmoved(at3) + unmoved(at3) / 10);
  EXPECT_LE(Field(at2.Output, "ImproveCounts", "Splits"), Field(at3.Output, "ImproveCounts", "Splits"));
}

// TraceQuality records the minimum stretch after every step: from the
// input's minimum to the output's, at times that grow within the run, and
// the mesh is the same as without it (the trace only reads). Off: no array.
TEST(Improve, QualityTrace)
{
  const StretchedBoss boss = StretchBoss(1.6);
  ASSERT_NE(boss.Deformed, nullptr);
  ImproveRun plain = Improve(boss.Deformed, boss.Reference);
  ImproveRun traced = Improve(boss.Deformed, boss.Reference, [](vtkFEMorphImprove* f) { f->TraceQualityOn(); });
  EXPECT_EQ(plain.Output->GetFieldData()->GetArray("ImproveQualityTrace"), nullptr);
  vtkDataArray* trace = traced.Output->GetFieldData()->GetArray("ImproveQualityTrace");
  ASSERT_NE(trace, nullptr);
  ASSERT_EQ(trace->GetNumberOfComponents(), 2);
  ASSERT_GT(trace->GetNumberOfTuples(), 5);
  EXPECT_STREQ(trace->GetComponentName(0), "Seconds");
  EXPECT_STREQ(trace->GetComponentName(1), "MinStretch");
  const vtkIdType last = trace->GetNumberOfTuples() - 1;
  EXPECT_NEAR(trace->GetComponent(0, 1), Field(traced.Output, "ImproveStretch", "MinBefore"), 1e-12);
  EXPECT_NEAR(trace->GetComponent(last, 1), Field(traced.Output, "ImproveStretch", "MinAfter"), 1e-12);
  EXPECT_GT(trace->GetComponent(0, 0), 0.0);
  for (vtkIdType i = 1; i <= last; ++i)
  {
    EXPECT_GE(trace->GetComponent(i, 0), trace->GetComponent(i - 1, 0)) << i;
  }
  EXPECT_LE(trace->GetComponent(last, 0), Field(traced.Output, "ImproveTimes", "Total"));
  EXPECT_EQ(traced.Out.Points, plain.Out.Points);
  EXPECT_EQ(traced.Out.Tets, plain.Out.Tets);
}

// Issue 5 (a): inner vertices moved by up to 40% of their mean edge length
// (moves that would invert are skipped, so the input is valid).
TEST(Improve, JitteredInnerVertices)
{
  auto part = femorph_test::ReadPart("filleted_box.vtu");
  ASSERT_NE(part, nullptr);
  auto segmented = Segmented(part);
  Arrays a = ToArrays(segmented);
  const Quality undeformed = Measure(a);
  std::vector<std::vector<femorph::index_t>> neighbours(a.Points.size());
  std::vector<char> boundary(a.Points.size(), 0);
  const auto regions = PointRegions(segmented, a);
  for (std::size_t v = 0; v < a.Points.size(); ++v)
  {
    boundary[v] = !regions[v].empty();
  }
  std::vector<std::vector<std::size_t>> ball(a.Points.size());
  for (std::size_t t = 0; t < a.Tets.size(); ++t)
  {
    for (int i = 0; i < 4; ++i)
    {
      ball[a.Tets[t][i]].push_back(t);
      for (int j = 0; j < 4; ++j)
      {
        if (i != j)
        {
          neighbours[a.Tets[t][i]].push_back(a.Tets[t][j]);
        }
      }
    }
  }
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t v = 0; v < a.Points.size(); ++v)
  {
    if (boundary[v] || neighbours[v].empty())
    {
      continue;
    }
    double len = 0;
    for (const auto w : neighbours[v])
    {
      len += (a.Points[w] - a.Points[v]).norm();
    }
    len /= static_cast<double>(neighbours[v].size());
    Vec3 d;
    do
    {
      d = Vec3(u(rng), u(rng), u(rng));
    } while (d.squaredNorm() > 1);
    const Vec3 old = a.Points[v];
    a.Points[v] = old + 0.4 * len * d;
    for (const std::size_t t : ball[v])
    {
      const Tet& T = a.Tets[t];
      if (femorph::orient3d_sign(a.Points[T[0]], a.Points[T[1]], a.Points[T[2]], a.Points[T[3]]) <= 0)
      {
        a.Points[v] = old;
        break;
      }
    }
  }
  auto jittered = WithPoints(segmented, a.Points);
  ImproveRun run = Improve(jittered, segmented);
  EXPECT_LT(run.Before.Min, 0.2);
  ExpectGoals(run, jittered, 0.3, undeformed.Mean);
}

// Issue 5 (c): "a few inverted and many sliver elements", made by moving
// surface vertices along their planes: each by a random vector of up to 50%
// of its mean edge length; a move that would fold a tet over goes through
// with probability 0.04 (inverted tets) and otherwise stops where that tet
// keeps 0.5-6% of its volume (a sliver).
TEST(Improve, SlidSurfaceVertices)
{
  auto part = femorph_test::ReadPart("boss_block.vtu");
  ASSERT_NE(part, nullptr);
  auto segmented = Segmented(part);
  Arrays a = ToArrays(segmented);
  const Quality undeformed = Measure(a);
  const auto regions = PointRegions(segmented, a);
  vtkDataArray* types = segmented->GetFieldData()->GetArray("RegionType");
  vtkDataArray* params = segmented->GetFieldData()->GetArray("RegionParameters");
  vtkDataArray* classes = segmented->GetPointData()->GetArray("VertexClass");
  ASSERT_TRUE(types && params && classes);
  std::vector<double> length(a.Points.size(), 0);
  std::vector<int> count(a.Points.size(), 0);
  std::vector<std::vector<std::size_t>> ball(a.Points.size());
  for (std::size_t c = 0; c < a.Tets.size(); ++c)
  {
    const Tet& t = a.Tets[c];
    for (int i = 0; i < 4; ++i)
    {
      ball[t[i]].push_back(c);
      for (int j = 0; j < 4; ++j)
      {
        if (i != j)
        {
          length[t[i]] += (a.Points[t[j]] - a.Points[t[i]]).norm();
          ++count[t[i]];
        }
      }
    }
  }
  const auto volume = [&](std::size_t c) {
    const Tet& t = a.Tets[c];
    return femorph::tet_signed_volume(a.Points[t[0]], a.Points[t[1]], a.Points[t[2]], a.Points[t[3]]);
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::size_t slid = 0;
  for (std::size_t v = 0; v < a.Points.size(); ++v)
  {
    if (classes->GetComponent(static_cast<vtkIdType>(v), 0) != 1 || regions[v].size() != 1)
    {
      continue;
    }
    const int r = *regions[v].begin();
    if (types->GetComponent(r, 0) != 0)  // planes only
    {
      continue;
    }
    const Vec3 n(params->GetComponent(r, 3), params->GetComponent(r, 4), params->GetComponent(r, 5));
    Vec3 d(u(rng), u(rng), u(rng));
    d -= d.dot(n) * n;
    if (d.norm() > 1)
    {
      d /= d.norm();
    }
    d *= 0.5 * length[v] / count[v];
    const double through = 0.5 * (u(rng) + 1), share = 0.5 * (u(rng) + 1);
    // The volumes are affine in v's position: the first tet of the ball to
    // turn flat along d sets where the move stops.
    const Vec3 start = a.Points[v];
    std::vector<double> before(ball[v].size());
    double flat = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < ball[v].size(); ++i)
    {
      before[i] = volume(ball[v][i]);
      a.Points[v] = start + d;
      const double slope = volume(ball[v][i]) - before[i];
      a.Points[v] = start;
      if (before[i] > 0 && slope < 0)
      {
        flat = std::min(flat, -before[i] / slope);
      }
    }
    double step = 1;
    if (flat < 1 && through >= 0.04)
    {
      step = flat * (1 - (0.005 + 0.055 * share));
    }
    for (int tries = 0; tries < 60; ++tries)  // rounding: no tet may turn flat
    {
      a.Points[v] = start + step * d;
      bool positive = true;
      for (std::size_t i = 0; i < ball[v].size() && positive && step < 1; ++i)
      {
        const Tet& t = a.Tets[ball[v][i]];
        positive = before[i] <= 0 ||
          femorph::orient3d_sign(a.Points[t[0]], a.Points[t[1]], a.Points[t[2]], a.Points[t[3]]) > 0;
      }
      if (positive)
      {
        break;
      }
      step *= 0.5;
    }
    ++slid;
  }
  const Quality slidQuality = Measure(a);
  std::size_t flat = 0;
  for (const Tet& t : a.Tets)
  {
    flat += femorph::tet_stretch(a.Points[t[0]], a.Points[t[1]], a.Points[t[2]], a.Points[t[3]]) < 0.05;
  }
  std::printf("  %zu surface points slid: %zu inverted, %zu below 0.05\n", slid, slidQuality.Inverted, flat);
  EXPECT_GE(slidQuality.Inverted, 3u);   // a few
  EXPECT_LE(slidQuality.Inverted, 40u);
  EXPECT_GT(flat, 10 * slidQuality.Inverted);  // many slivers
  auto slidGrid = WithPoints(segmented, a.Points);
  ImproveRun run = Improve(slidGrid, segmented);
  ExpectGoals(run, slidGrid, 0.3, undeformed.Mean);
  // Planar faces: the part's volume is the input's (inverted tets count
  // negative in both sums, so the signed volume of the input is the part's).
  EXPECT_NEAR(run.After.Volume, undeformed.Volume, 1e-3 * undeformed.Volume);
}

// An input that needs nothing: the Data part itself, with itself as the
// reference. Quality does not drop, the density error does not grow, the
// tet count stays within 10%.
TEST(Improve, GoodInputStaysGood)
{
  auto part = femorph_test::ReadPart("cone_sphere_torus.vtu");
  ASSERT_NE(part, nullptr);
  auto segmented = Segmented(part);
  ImproveRun run = Improve(segmented, nullptr);
  ASSERT_GT(run.Out.Tets.size(), 0u);
  ExpectValid(run.Output, run.Out);
  EXPECT_GE(run.After.Min, run.Before.Min);
  EXPECT_GE(run.After.Mean, run.Before.Mean);
  EXPECT_LE(Field(run.Output, "ImproveDensityError", "After"),
    Field(run.Output, "ImproveDensityError", "Before") + 1e-9);
  EXPECT_NEAR(static_cast<double>(run.Out.Tets.size()), static_cast<double>(segmented->GetNumberOfCells()),
    0.1 * static_cast<double>(segmented->GetNumberOfCells()));
  EXPECT_LE(MaxSurfaceDistance(run.Output, run.Out, segmented), 1e-9);
}

// Issue 29, through the filter with its defaults (no Reference, segmented by
// the filter itself): the perfect lattice of 2 x 2 x 2 cubes of six Kuhn tets
// (48 tets, minimum stretch 0.586) came out with 84 tets and minimum 0.550.
// Without a Reference the target density is the input's own, so the output
// may not fall below the input's minimum: the lattice comes out as it went
// in, with a warning and KeptInput = 1.
TEST(Improve, PerfectLatticeIsNotMadeWorse)
{
  std::vector<std::array<double, 3>> points;
  for (int k = 0; k <= 2; ++k)
    for (int j = 0; j <= 2; ++j)
      for (int i = 0; i <= 2; ++i)
        points.push_back({ double(i), double(j), double(k) });
  const auto id = [](int i, int j, int k) { return static_cast<vtkIdType>((k * 3 + j) * 3 + i); };
  // Kuhn's six tets per cube (one per order of the axes), positive.
  const int kuhn[6][4] = { { 0, 1, 3, 7 }, { 0, 1, 7, 5 }, { 0, 2, 7, 3 }, { 0, 2, 6, 7 },
    { 0, 4, 5, 7 }, { 0, 4, 7, 6 } };
  std::vector<std::pair<int, std::vector<vtkIdType>>> cells;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        for (const auto& t : kuhn)
        {
          std::vector<vtkIdType> ids;
          for (const int c : t)
          {
            ids.push_back(id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)));
          }
          cells.push_back({ VTK_TETRA, ids });
        }
  auto lattice = femorph_test::MakeGrid(points, cells);
  ASSERT_EQ(lattice->GetNumberOfCells(), 48);
  vtkNew<femorph_test::MessageRecorder> messages;
  vtkNew<vtkFEMorphImprove> improve;
  messages->Observe(improve);
  improve->SetInputData(lattice);
  improve->Update();
  ASSERT_EQ(messages->Errors.size(), 0u) << messages->AllErrors();
  vtkUnstructuredGrid* out = improve->GetOutput();
  const Quality before = Measure(ToArrays(lattice));
  const Quality after = Measure(ToArrays(out));
  EXPECT_NEAR(before.Min, 2 - std::sqrt(2.0), 1e-3);  // the 0.586
  EXPECT_GE(after.Min, before.Min);
  EXPECT_EQ(out->GetNumberOfCells(), 48);
  EXPECT_EQ(Field(out, "ImproveCounts", "KeptInput"), 1);
  EXPECT_NE(messages->AllWarnings().find("the mesh is output unchanged"), std::string::npos)
    << messages->AllWarnings();
}

// Restriction to a region: cells outside the flagged ones keep their points.
TEST(Improve, RegionArrayRestrictsTheChange)
{
  auto part = femorph_test::ReadPart("boss_block.vtu");
  ASSERT_NE(part, nullptr);
  const Arrays original = ToArrays(part);
  auto deformed = Segmented(WithPoints(part, StretchSlab(original.Points, 20, 35, 1.6)));
  // Flag the cells with a point above the block (the stretched boss).
  vtkNew<vtkIntArray> flag;
  flag->SetName("Moved");
  flag->SetNumberOfTuples(deformed->GetNumberOfCells());
  std::vector<char> outside(original.Points.size(), 0);
  for (std::size_t t = 0; t < original.Tets.size(); ++t)
  {
    bool above = false;
    for (const auto v : original.Tets[t])
    {
      above = above || original.Points[v].z() > 20 + 1e-9;
    }
    flag->SetValue(static_cast<vtkIdType>(t), above ? 1 : 0);
    if (!above)
    {
      for (const auto v : original.Tets[t])
      {
        outside[v] = 1;
      }
    }
  }
  deformed->GetCellData()->AddArray(flag);
  ImproveRun run = Improve(deformed, nullptr, [](vtkFEMorphImprove* f) { f->SetRegionArrayName("Moved"); });
  ASSERT_GT(run.Out.Tets.size(), 0u);
  ExpectValid(run.Output, run.Out);
  // Every point of an unflagged cell is in the output, unmoved.
  std::set<std::array<double, 3>> out;
  for (const Vec3& p : run.Out.Points)
  {
    out.insert({ p.x(), p.y(), p.z() });
  }
  const Arrays in = ToArrays(deformed);
  std::size_t missing = 0;
  for (std::size_t v = 0; v < in.Points.size(); ++v)
  {
    missing += outside[v] && !out.count({ in.Points[v].x(), in.Points[v].y(), in.Points[v].z() });
  }
  EXPECT_EQ(missing, 0u);
  EXPECT_GT(run.After.Min, run.Before.Min);
}

// Without segmentation arrays and SegmentIfMissing off: a warning, and every
// boundary point stays where it is.
TEST(Improve, NoSegmentationKeepsBoundary)
{
  auto part = femorph_test::ReadPart("boss_block.vtu");
  ASSERT_NE(part, nullptr);
  const Arrays original = ToArrays(part);
  auto deformed = WithPoints(part, StretchSlab(original.Points, 20, 35, 1.6));
  vtkNew<femorph_test::MessageRecorder> messages;
  vtkNew<vtkFEMorphImprove> improve;
  messages->Observe(improve);
  improve->SetInputData(deformed);
  improve->SetSegmentIfMissing(false);
  improve->Update();
  ASSERT_EQ(messages->Errors.size(), 0u);
  ASSERT_FALSE(messages->Warnings.empty());
  EXPECT_NE(messages->Warnings[0].find("kept where it is"), std::string::npos) << messages->Warnings[0];
  const Arrays out = ToArrays(improve->GetOutput());
  ExpectValid(improve->GetOutput(), out);
  // The boundary points of the input are all in the output.
  std::set<std::array<double, 3>> points;
  for (const Vec3& p : out.Points)
  {
    points.insert({ p.x(), p.y(), p.z() });
  }
  const Arrays in = ToArrays(deformed);
  vtkNew<vtkFEMorphSegment> segment;  // only to find the boundary points
  segment->SetInputData(deformed);
  segment->Update();
  const auto regions = PointRegions(segment->GetMeshOutput(), in);
  std::size_t moved = 0;
  for (std::size_t v = 0; v < in.Points.size(); ++v)
  {
    moved += !regions[v].empty() && !points.count({ in.Points[v].x(), in.Points[v].y(), in.Points[v].z() });
  }
  EXPECT_EQ(moved, 0u);
}

// A part squashed into a plate thinner than its mesh: most tets span the
// thickness with all four vertices on the boundary, where no inner vertex
// can be moved. The filter says what limits the quality (a warning and the
// BelowFloor counts) and still outputs a valid mesh.
TEST(Improve, SaysWhenTheBoundaryLimitsTheQuality)
{
  auto part = femorph_test::ReadPart("boss_block.vtu");
  ASSERT_NE(part, nullptr);
  Arrays plate = ToArrays(part);
  for (Vec3& p : plate.Points)
  {
    p.z() *= 0.02;
  }
  vtkNew<femorph_test::MessageRecorder> messages;
  vtkNew<vtkFEMorphImprove> improve;
  messages->Observe(improve);
  improve->SetInputData(Segmented(WithPoints(part, plate.Points)));
  improve->Update();
  ASSERT_EQ(messages->Errors.size(), 0u);
  const Arrays out = ToArrays(improve->GetOutput());
  ExpectValid(improve->GetOutput(), out);
  const double below = Field(improve->GetOutput(), "ImproveCounts", "BelowFloor");
  const double locked = Field(improve->GetOutput(), "ImproveCounts", "BelowFloorAllBoundary");
  std::printf("  plate: %zu tets, %.0f below 0.3, %.0f with all vertices on the boundary\n", out.Tets.size(), below,
    locked);
  EXPECT_GT(locked, 0);
  EXPECT_LE(locked, below);
  std::size_t counted = 0;
  for (const Tet& t : out.Tets)
  {
    counted += femorph::tet_stretch(out.Points[t[0]], out.Points[t[1]], out.Points[t[2]], out.Points[t[3]]) < 0.3;
  }
  EXPECT_EQ(below, static_cast<double>(counted));
  bool warned = false;
  for (const auto& w : messages->Warnings)
  {
    warned = warned || w.find("all four vertices on the boundary") != std::string::npos;
  }
  EXPECT_TRUE(warned);
}

TEST(Improve, BadInput)
{
  // Not tetrahedra.
  {
    auto grid = femorph_test::MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
                                         { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } },
      { { VTK_HEXAHEDRON, { 0, 1, 2, 3, 4, 5, 6, 7 } } });
    vtkNew<femorph_test::MessageRecorder> messages;
    vtkNew<vtkFEMorphImprove> improve;
    messages->Observe(improve);
    improve->SetInputData(grid);
    improve->Update();
    ASSERT_FALSE(messages->Errors.empty());
    EXPECT_NE(messages->Errors[0].find("VTK_HEXAHEDRON"), std::string::npos) << messages->Errors[0];
    EXPECT_EQ(improve->GetOutput()->GetNumberOfCells(), 0);
  }
  // A region array that is not there.
  {
    auto grid = femorph_test::MakeTwoTets();
    vtkNew<femorph_test::MessageRecorder> messages;
    vtkNew<vtkFEMorphImprove> improve;
    messages->Observe(improve);
    improve->SetInputData(grid);
    improve->SetRegionArrayName("NoSuchArray");
    improve->Update();
    ASSERT_FALSE(messages->Errors.empty());
    EXPECT_NE(messages->Errors[0].find("NoSuchArray"), std::string::npos) << messages->Errors[0];
    EXPECT_EQ(improve->GetOutput()->GetNumberOfCells(), 0);
  }
  // A NaN coordinate.
  {
    auto grid = femorph_test::MakeTwoTets();
    grid->GetPoints()->SetPoint(4, std::nan(""), 1, 1);
    vtkNew<femorph_test::MessageRecorder> messages;
    vtkNew<vtkFEMorphImprove> improve;
    messages->Observe(improve);
    improve->SetInputData(grid);
    improve->SetSegmentIfMissing(false);
    improve->Update();
    ASSERT_FALSE(messages->Errors.empty());
    EXPECT_NE(messages->Errors[0].find("NaN"), std::string::npos) << messages->Errors[0];
  }
  // Settings the filter refuses: an error containing `word`, no output.
  const auto expectRefused = [](const std::function<void(vtkFEMorphImprove*)>& set, const char* word) {
    auto grid = femorph_test::MakeTwoTets();
    vtkNew<femorph_test::MessageRecorder> messages;
    vtkNew<vtkFEMorphImprove> improve;
    messages->Observe(improve);
    improve->SetInputData(grid);
    set(improve);
    improve->Update();
    ASSERT_FALSE(messages->Errors.empty()) << word;
    EXPECT_NE(messages->Errors[0].find(word), std::string::npos) << messages->Errors[0];
    EXPECT_EQ(improve->GetOutput()->GetNumberOfCells(), 0);
  };
  // Density thresholds that do not converge (thesis 2.6.3).
  expectRefused(
    [](vtkFEMorphImprove* f) {
      f->SetSplitThreshold(1.2);
      f->SetCollapseThreshold(0.67);
    },
    "converge");
  // A quality floor at or below the degenerate threshold.
  expectRefused(
    [](vtkFEMorphImprove* f) {
      f->SetDegenerateThreshold(0.1);
      f->SetQualityFloor(0.1);
    },
    "QualityFloor");
  // An inverted tet left unrepaired (two tets on the same side of their
  // shared face, with the repair of inverted tetrahedra off): an error
  // naming it, or with RequireValid off the mesh with it marked.
  for (const bool requireValid : { true, false })
  {
    auto grid = femorph_test::MakeGrid({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0.1, 0.1, 0.1 } },
      { { VTK_TETRA, { 0, 1, 2, 3 } }, { VTK_TETRA, { 4, 1, 3, 2 } } });
    vtkNew<femorph_test::MessageRecorder> messages;
    vtkNew<vtkFEMorphImprove> improve;
    messages->Observe(improve);
    improve->SetInputData(grid);
    improve->SetSegmentIfMissing(false);
    improve->SetRemoveInverted(false);
    improve->SetRequireValid(requireValid);
    improve->Update();
    if (requireValid)
    {
      ASSERT_FALSE(messages->Errors.empty());
      EXPECT_NE(messages->Errors[0].find("1 inverted tetrahedron could not be repaired"), std::string::npos)
        << messages->Errors[0];
      EXPECT_EQ(improve->GetOutput()->GetNumberOfCells(), 0);
    }
    else
    {
      EXPECT_TRUE(messages->Errors.empty());
      ASSERT_EQ(improve->GetOutput()->GetNumberOfCells(), 2);
      vtkDataArray* inverted = improve->GetOutput()->GetCellData()->GetArray("Inverted");
      ASSERT_NE(inverted, nullptr);
      EXPECT_EQ(inverted->GetComponent(0, 0) + inverted->GetComponent(1, 0), 1);
      bool warned = false;
      for (const auto& w : messages->Warnings)
      {
        warned = warned || w.find("could not be repaired") != std::string::npos;
      }
      EXPECT_TRUE(warned);
    }
  }
  // An empty mesh is passed through.
  {
    vtkNew<vtkUnstructuredGrid> empty;
    vtkNew<vtkFEMorphImprove> improve;
    improve->SetInputData(empty);
    improve->Update();
    EXPECT_EQ(improve->GetOutput()->GetNumberOfCells(), 0);
  }
}

TEST(Improve, XmlDefaultsEqualCxxDefaults)
{
  vtkSmartPointer<vtkXMLDataElement> root;
  vtkXMLDataElement* proxy = femorph_test::FindFilterProxy(
    FEMORPH_PLUGIN_XML, "vtkFEMorphImprove", "FEMorphImprove", "FEMorph Improve", root);
  ASSERT_NE(proxy, nullptr);
  vtkNew<vtkFEMorphImprove> d;
  const auto flag = [](vtkTypeBool v) { return femorph_test::XmlProperty{ double(v), 0, 1 }; };
  const std::map<std::string, femorph_test::XmlProperty> expected = {
    { "SetPoorElementsOnly", flag(d->GetPoorElementsOnly()) },
    { "SetSmoothCurves", flag(d->GetSmoothCurves()) },
    { "SetSmoothSurfaces", flag(d->GetSmoothSurfaces()) },
    { "SetSmoothVolume", flag(d->GetSmoothVolume()) },
    { "SetRemoveDegenerate", flag(d->GetRemoveDegenerate()) },
    { "SetRemoveInverted", flag(d->GetRemoveInverted()) },
    { "SetDensityControl", flag(d->GetDensityControl()) },
    { "SetAccuracyControl", flag(d->GetAccuracyControl()) },
    { "SetFlips", flag(d->GetFlips()) },
    { "SetRelaxEdgeLengths", flag(d->GetRelaxEdgeLengths()) },
    { "SetMoveUnfittedRegions", flag(d->GetMoveUnfittedRegions()) },
    { "SetOdtIterations",
      { double(d->GetOdtIterations()), double(d->GetOdtIterationsMinValue()),
        double(d->GetOdtIterationsMaxValue()) } },
    { "SetMaxLoops",
      { double(d->GetMaxLoops()), double(d->GetMaxLoopsMinValue()), double(d->GetMaxLoopsMaxValue()) } },
    { "SetSplitThreshold",
      { d->GetSplitThreshold(), d->GetSplitThresholdMinValue(), d->GetSplitThresholdMaxValue() } },
    { "SetCollapseThreshold",
      { d->GetCollapseThreshold(), d->GetCollapseThresholdMinValue(), d->GetCollapseThresholdMaxValue() } },
    { "SetGridCellSize", { d->GetGridCellSize(), d->GetGridCellSizeMinValue(), d->GetGridCellSizeMaxValue() } },
    { "SetDegenerateThreshold",
      { d->GetDegenerateThreshold(), d->GetDegenerateThresholdMinValue(), d->GetDegenerateThresholdMaxValue() } },
    { "SetQualityFloor", { d->GetQualityFloor(), d->GetQualityFloorMinValue(), d->GetQualityFloorMaxValue() } },
    { "SetSegmentIfMissing", flag(d->GetSegmentIfMissing()) },
    { "SetRequireValid", flag(d->GetRequireValid()) },
    { "SetTraceQuality", { double(d->GetTraceQuality()), 0, 1, true } },
  };
  femorph_test::CheckFilterProperties(
    proxy, expected, {}, { { "SetRegionArrayName", d->GetRegionArrayName() } });
  // The help names the output's arrays.
  vtkXMLDataElement* doc = proxy->FindNestedElementWithName("Documentation");
  ASSERT_NE(doc, nullptr);
  const std::string help = doc->GetCharacterData() ? doc->GetCharacterData() : "";
  for (const char* name : { "Stretch", "Inverted", "ImproveStretch", "ImproveDensityError", "ImproveCounts",
         "ImproveTimes", "ImproveStepTimes", "ImproveQualityTrace", "GeometricError", "AcceptableGeometricError" })
  {
    EXPECT_NE(help.find(name), std::string::npos) << name;
  }
}
}
