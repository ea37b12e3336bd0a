// Basic types shared by every part of femorph_core.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <string>

namespace femorph {

using Vec3 = Eigen::Vector3d;
/// Vertex, tet and region ids. 32 bits: meshes up to 500M tets (neighbour
/// codes 4*t + f must fit).
using index_t = std::int32_t;
constexpr index_t kInvalidIndex = -1;
constexpr double kPi = 3.14159265358979323846;
inline double degrees_to_radians(double deg) { return deg * kPi / 180.0; }
/// Loops over fewer items run on one thread: waking the pool's threads
/// (common/parallel.h) costs more than the work, and more still on a busy
/// machine where a thread is not scheduled at once.
constexpr long kParallelMinItems = 10000;
/// The same for loops whose items cost microseconds each (curvature fits).
constexpr long kParallelMinHeavyItems = 500;
using Tet = std::array<index_t, 4>;

/// Result of a core function that can fail: ok, or a message for the user.
struct Status {
  bool ok = true;
  std::string message;

  static Status success() { return {}; }
  static Status failure(std::string msg) { return {false, std::move(msg)}; }
  explicit operator bool() const { return ok; }
};

}  // namespace femorph
