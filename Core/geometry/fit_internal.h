// Shared by the fitting functions (fit_*.cpp, ransac_*.cpp, refine_fit_lm.cpp);
// not part of the API: the RANSAC loop of thesis 2.4.3.3 / 2.4.4 and the
// change to unit-free coordinates every fit works in.
#pragma once

#include "geometry/fit_primitives.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace femorph {
namespace detail {

/// Centre and scale of a point set: fits work on (x - center) / scale, so that
/// parts in mm or m, near the origin or far from it, give the same numbers.
struct Normalisation {
  Vec3 center = Vec3::Zero();
  double scale = 1;

  explicit Normalisation(const std::vector<Vec3>& points) {
    if (points.empty()) return;
    for (const Vec3& p : points) center += p;
    center /= static_cast<double>(points.size());
    double sum = 0;
    for (const Vec3& p : points) sum += (p - center).squaredNorm();
    scale = std::sqrt(sum / static_cast<double>(points.size()));
  }
  bool valid() const { return scale > 0 && std::isfinite(scale); }

  std::vector<Vec3> apply(const std::vector<Vec3>& points) const {
    std::vector<Vec3> out(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) out[i] = (points[i] - center) / scale;
    return out;
  }
  SurfacePrimitive to_unit(SurfacePrimitive s) const {
    s.point = (s.point - center) / scale;
    s.radius /= scale;
    s.minor_radius /= scale;
    return s;
  }
  SurfacePrimitive to_world(SurfacePrimitive s) const {
    s.point = center + scale * s.point;
    s.radius *= scale;
    s.minor_radius *= scale;
    if (s.type == SurfaceType::Cylinder) s.point -= s.point.dot(s.axis) * s.axis;  // axis point closest to the origin
    return s;
  }
};

/// Unit normals (zero stays zero).
inline std::vector<Vec3> unit_normals(const std::vector<Vec3>& normals) {
  std::vector<Vec3> out(normals.size(), Vec3::Zero());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double n = normals[i].norm();
    if (n > 0) out[i] = normals[i] / n;
  }
  return out;
}

/// Consensus of a model: inlier count, ties broken by the rms of the inliers.
struct Consensus {
  int inliers = -1;
  double rms = std::numeric_limits<double>::infinity();
  bool better_than(const Consensus& o) const { return inliers > o.inliers || (inliers == o.inliers && rms < o.rms); }
};

inline bool finite_surface(const SurfacePrimitive& s) {
  return s.point.allFinite() && s.axis.allFinite() && std::isfinite(s.radius) && std::isfinite(s.minor_radius) &&
         std::isfinite(s.half_angle);
}

/// The RANSAC loop shared by cones, spheres and tori: draws samples with a
/// seeded std::mt19937_64 (mapped by modulo, the same on every platform),
/// scores candidates first on a fixed random subset of the points and only
/// those that may beat the best on all of them, and stops after
/// params.iterations samples or earlier once a better consensus is unlikely
/// (probability below kMissProbability, after at least kMinIterations).
/// Each new best model is refitted to its consensus set while that improves
/// the consensus (local optimisation, as LO-RANSAC): with normals that err by
/// a degree, minimal samples alone rarely give a model whose consensus is the
/// whole surface.
class Ransac {
 public:
  /// Fits a model to the consensus set (indices) of `model`; false if none.
  using Refit = std::function<bool(const SurfacePrimitive& model, const std::vector<int>&, SurfacePrimitive&)>;
  static constexpr int kLocalSteps = 5;

  static constexpr int kSubsetSize = 200;
  static constexpr int kMinIterations = 50;
  static constexpr double kMissProbability = 1e-6;

  Ransac(const std::vector<Vec3>& points, double tolerance, const RansacParams& params, int sample_size, Refit refit)
      : points_(points), tolerance_(tolerance), max_iterations_(std::max(0, params.iterations)),
        sample_size_(sample_size), rng_(params.seed), refit_(std::move(refit)) {
    const int n = static_cast<int>(points.size());
    if (n > 2 * kSubsetSize) {
      // Partial Fisher-Yates: the first kSubsetSize of a shuffled index list.
      std::vector<int> all(n);
      for (int i = 0; i < n; ++i) all[i] = i;
      for (int i = 0; i < kSubsetSize; ++i) std::swap(all[i], all[i + static_cast<int>(rng_() % (n - i))]);
      subset_.assign(all.begin(), all.begin() + kSubsetSize);
    }
  }

  /// Whether to draw another sample (counts it).
  bool next() {
    if (iterations_ >= max_iterations_ || static_cast<int>(points_.size()) < sample_size_) return false;
    if (iterations_ >= std::min(kMinIterations, max_iterations_) && has_best() &&
        iterations_ >= needed_iterations())
      return false;
    ++iterations_;
    return true;
  }

  /// sample_size distinct indices into the points.
  void sample(int* out) {
    const std::uint64_t n = points_.size();
    for (int k = 0; k < sample_size_; ++k) {
      for (;;) {
        out[k] = static_cast<int>(rng_() % n);
        bool repeated = false;
        for (int j = 0; j < k; ++j) repeated = repeated || out[j] == out[k];
        if (!repeated) break;
      }
    }
  }

  /// Scores a candidate; keeps it when its consensus beats the best, then
  /// refits the best to its consensus set while that improves it.
  void offer(const SurfacePrimitive& candidate) {
    if (!score_and_keep(candidate) || !refit_) return;
    SurfacePrimitive refitted;
    for (int step = 0; step < kLocalSteps; ++step)
      if (!refit_(best_, inliers(), refitted) || !score_and_keep(refitted)) break;
  }

  bool has_best() const { return best_consensus_.inliers > 0; }
  const SurfacePrimitive& best() const { return best_; }
  const Consensus& best_consensus() const { return best_consensus_; }
  int iterations() const { return iterations_; }
  double tolerance() const { return tolerance_; }

  /// Indices of the points within the tolerance of the best model.
  std::vector<int> inliers() const {
    std::vector<int> out;
    for (int i = 0; i < static_cast<int>(points_.size()); ++i)
      if (std::abs(signed_distance(best_, points_[i])) <= tolerance_) out.push_back(i);
    return out;
  }

 private:
  // Whether the candidate became the best.
  bool score_and_keep(const SurfacePrimitive& candidate) {
    if (!finite_surface(candidate)) return false;
    Consensus on_subset;
    if (!subset_.empty()) {
      on_subset = score(candidate, &subset_);
      // Full scoring only for what may beat the best: more inliers on the
      // subset, or as many up to its sampling noise (two standard deviations)
      // with a lower rms there.
      const double margin = 2.0 * std::sqrt(static_cast<double>(std::max(best_subset_.inliers, 0))) + 1.0;
      const bool promising = on_subset.inliers > best_subset_.inliers ||
                             (on_subset.inliers + margin >= best_subset_.inliers && on_subset.rms < best_subset_.rms);
      if (has_best() && !promising) return false;
    }
    const Consensus c = score(candidate, nullptr);
    if (!c.better_than(best_consensus_)) return false;
    best_consensus_ = c;
    best_ = candidate;
    best_subset_ = on_subset;
    return true;
  }

  Consensus score(const SurfacePrimitive& s, const std::vector<int>* subset) const {
    Consensus c;
    c.inliers = 0;
    double sum = 0;
    const auto visit = [&](int i) {
      const double d = std::abs(signed_distance(s, points_[i]));
      if (d <= tolerance_) {
        ++c.inliers;
        sum += d * d;
      }
    };
    if (subset != nullptr) {
      for (int i : *subset) visit(i);
    } else {
      for (int i = 0; i < static_cast<int>(points_.size()); ++i) visit(i);
    }
    c.rms = c.inliers > 0 ? std::sqrt(sum / c.inliers) : std::numeric_limits<double>::infinity();
    return c;
  }

  // Samples needed to draw an all-inlier sample with probability
  // 1 - kMissProbability at the best model's inlier ratio.
  int needed_iterations() const {
    const double w = static_cast<double>(best_consensus_.inliers) / static_cast<double>(points_.size());
    const double all_inlier = std::pow(w, sample_size_);
    if (all_inlier >= 1.0) return 0;
    if (all_inlier <= 0.0) return max_iterations_;
    const double needed = std::log(kMissProbability) / std::log1p(-all_inlier);
    return needed >= max_iterations_ ? max_iterations_ : static_cast<int>(std::ceil(needed));
  }

  const std::vector<Vec3>& points_;
  double tolerance_;
  int max_iterations_;
  int sample_size_;
  std::mt19937_64 rng_;
  Refit refit_;
  std::vector<int> subset_;
  int iterations_ = 0;
  SurfacePrimitive best_;
  Consensus best_consensus_;
  Consensus best_subset_;
};

/// The inliers whose normal agrees with the model's (sign ignored) within
/// kNormalAgreement: refits from normals must not take the normals of other
/// surfaces' points that happen to lie near the model (Schnabel 2007 scores
/// the normal deviation for the same reason).
inline std::vector<int> normal_consistent(const SurfacePrimitive& model, const std::vector<Vec3>& points,
                                          const std::vector<Vec3>& normals, const std::vector<int>& inliers) {
  const double kNormalAgreement = std::cos(20.0 * kPi / 180.0);
  std::vector<int> out;
  out.reserve(inliers.size());
  for (int i : inliers)
    if (std::abs(normals[i].dot(surface_normal(model, points[i]))) >= kNormalAgreement) out.push_back(i);
  return out;
}

/// Picks points by index.
inline std::vector<Vec3> gather(const std::vector<Vec3>& points, const std::vector<int>& indices) {
  std::vector<Vec3> out;
  out.reserve(indices.size());
  for (int i : indices) out.push_back(points[i]);
  return out;
}

}  // namespace detail
}  // namespace femorph
