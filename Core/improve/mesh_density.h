// Mesh density of thesis 2.6.3 (Fig. 2.40 (a), (b)) and the mesh density
// error of 2.7.4 (Eq. 2.35).
//
//  (a) vertex_density: before the deformation, the density of every vertex
//      of the original mesh, the average of the reciprocals of its incident
//      edge lengths (Eq. 2.32).
//  (b) DensityGrid: after the deformation, a regular grid over the deformed
//      mesh. Each grid point takes the density of the original vertices,
//      interpolated barycentrically in the tet of the deformed mesh that holds
//      it (Eq. 2.33); the deformed mesh has the original connectivity, so the
//      density travels with the material. A grid cell's density rho_GC is the
//      average of the nonzero densities of its corners (grid points outside
//      the mesh have none).
//  mean_density_error: eps_rho(e) = |1 / L(e) - rho_GC(c_e)| / rho_GC(c_e)
//      over the edges e (Eq. 2.35), c_e the midpoint of e.
#pragma once

#include "common/types.h"

#include <array>
#include <cstddef>
#include <vector>

namespace femorph {

class TetMesh;

/// Eq. 2.32: rho_i = (1 / |N_i|) sum over the incident edges e of 1 / L(e).
/// Inputs: points (#P), tets (#T, 0-based ids into points). Returns #P values;
/// 0 for points no tet uses (and for points whose edges all have length 0).
/// `mean_length`, when given, receives mean_edge_length() of the mesh (from
/// the same edge list, which is the costly part of both).
std::vector<double> vertex_density(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                                   double* mean_length = nullptr);
/// The same for the live vertices of a TetMesh; one value per vertex slot
/// (0 for dead slots).
std::vector<double> vertex_density(const TetMesh& mesh);

/// Mean length of the (distinct) edges of a mesh; 0 without edges.
double mean_edge_length(const std::vector<Vec3>& points, const std::vector<Tet>& tets);

/// How a density is read from the grid.
enum class DensityLookup {
  /// rho_GC of the thesis: the value of the grid cell holding the point
  /// (piecewise constant). Used by Eq. 2.35 and the density thresholds.
  Cell,
  /// Trilinear interpolation of the grid point values (grid points outside
  /// the mesh filled from their neighbours). Exact for linear fields.
  Trilinear,
};

/// The target mesh density field of thesis Fig. 2.40 (b), Eq. 2.33.
class DensityGrid {
 public:
  DensityGrid() = default;

  /// Builds the grid over the bounding box of `points` (the deformed mesh)
  /// with cubic cells of edge `cell_size` (<= 0: half the mean edge length of
  /// the given mesh; the thesis suggests half the mean edge length of the
  /// original mesh for uniform meshes).
  /// Inputs:
  ///   points     #P positions of the (deformed) mesh
  ///   tets       #T tets into points, the original mesh's connectivity
  ///   densities  #P vertex densities, from vertex_density() of the original
  ///              mesh (values <= 0 are treated as unknown)
  ///   cell_size  grid spacing
  /// Grid points in no tet (up to a relative tolerance of 1e-9 in barycentric
  /// coordinates) get no density; cells with no nonzero corner take the mean
  /// of their face neighbours' values, layer by layer from the mesh outwards.
  /// Returns false (grid left empty) without tets or positive densities, or
  /// when the grid would have more than `max_points` points. Without
  /// `with_trilinear` only DensityLookup::Cell is prepared (Improve's
  /// lookup; the trilinear one needs one more pass over the grid), and a
  /// trilinear lookup returns the cell value.
  bool build(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
             const std::vector<double>& densities, double cell_size,
             std::size_t max_points = std::size_t(1) << 27, bool with_trilinear = true);

  bool empty() const { return cell_values_.empty(); }
  /// Density at p. Points outside the grid are clamped onto it.
  double density_at(const Vec3& p, DensityLookup lookup = DensityLookup::Trilinear) const;
  /// rho_GC(p): the density of the grid cell holding p (DensityLookup::Cell).
  double cell_density(const Vec3& p) const { return density_at(p, DensityLookup::Cell); }

  double cell_size() const { return h_; }
  const Vec3& origin() const { return origin_; }
  /// Number of cells along x, y, z (grid points: one more each).
  const std::array<int, 3>& cells() const { return n_; }
  /// Density of grid point (i, j, k) by Eq. 2.33, 0 outside the mesh (raw,
  /// before filling).
  double point_value(int i, int j, int k) const { return raw_points_[point_id(i, j, k)]; }

 private:
  std::size_t point_id(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * (n_[1] + 1) + j) * (n_[0] + 1) + i;
  }
  std::size_t cell_id(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i;
  }

  Vec3 origin_ = Vec3::Zero();
  double h_ = 0;
  std::array<int, 3> n_{{0, 0, 0}};
  std::vector<double> raw_points_;     // Eq. 2.33, 0 = outside the mesh
  std::vector<double> filled_points_;  // raw, zeros filled from neighbours
  std::vector<double> cell_values_;    // rho_GC
};

/// Statistics of eps_rho (Eq. 2.35) over the distinct edges of a mesh.
struct DensityError {
  double mean = 0;
  double max = 0;
  std::size_t edges = 0;
};

/// Eq. 2.35 averaged over the edges, rho_GC read with `lookup` (the thesis:
/// Cell). Edges of length 0 or in a region of density 0 are skipped.
DensityError mean_density_error(const std::vector<Vec3>& points, const std::vector<Tet>& tets,
                                const DensityGrid& grid, DensityLookup lookup = DensityLookup::Cell);
DensityError mean_density_error(const TetMesh& mesh, const DensityGrid& grid,
                                DensityLookup lookup = DensityLookup::Cell);

}  // namespace femorph
