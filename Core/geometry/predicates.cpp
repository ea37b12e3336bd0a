#include "geometry/predicates.h"

#include <tetgen.h>

#include <algorithm>
#include <cmath>

// Shewchuk's 2D predicates are compiled into libtet next to the 3D ones but
// tetgen.h does not declare them.
REAL orient2d(REAL* pa, REAL* pb, REAL* pc);
REAL incircle(REAL* pa, REAL* pb, REAL* pc, REAL* pd);

namespace femorph {
namespace {

// exactinit() computes the machine epsilon and error bounds; after that the
// predicates only read globals, so they are safe to call concurrently. It
// runs once when the library is loaded (this file is always linked in with
// the predicates), not on every call: the predicates sit in hot loops.
// Arguments: verbose = 0, noexact = 0 (adaptive exact arithmetic), nofilter
// = 1 (no static filter, which would need a bound on the coordinates); the
// box size is then unused.
const bool exact_arithmetic_ready = (exactinit(0, 0, 1, 1.0, 1.0, 1.0), true);

inline void ensure_exactinit() { (void)exact_arithmetic_ready; }

inline REAL* ptr(const Eigen::Vector3d& p) {
  // Shewchuk's predicates take REAL* but never write through it.
  return const_cast<REAL*>(p.data());
}

inline REAL* ptr(const Eigen::Vector2d& p) { return const_cast<REAL*>(p.data()); }

inline int sign(REAL x) { return (x > 0) - (x < 0); }

}  // namespace

int orient3d_sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  ensure_exactinit();
  // Shewchuk's orient3d(a, b, c, d) = (a - d) . ((b - d) x (c - d)), which is
  // minus six times the signed volume in VTK's convention.
  const REAL det = orient3d(ptr(a), ptr(b), ptr(c), ptr(d));
  if (det != 0 && std::isfinite(det)) return -sign(det);
  // Shewchuk's arithmetic is exact only without underflow and overflow: with
  // coordinates near 1e-300 the products of three differences underflow to
  // 0, near 1e300 they overflow (every tet flat at either scale).
  // Zero and non-finite results are therefore redone on the points scaled by
  // a power of two that brings the largest coordinate into [0.5, 1): exact,
  // so the sign is the points' own. Off the hot path: only coplanar points
  // and extreme scales get here.
  double largest = 0;
  for (const Eigen::Vector3d* p : {&a, &b, &c, &d}) largest = std::max(largest, p->cwiseAbs().maxCoeff());
  if (!(largest > 0) || !std::isfinite(largest) || (largest >= 0x1p-200 && largest <= 0x1p200))
    return -sign(det);
  int exponent = 0;
  std::frexp(largest, &exponent);
  const double s = std::ldexp(1.0, -exponent);
  const Eigen::Vector3d sa = a * s, sb = b * s, sc = c * s, sd = d * s;
  return -sign(orient3d(ptr(sa), ptr(sb), ptr(sc), ptr(sd)));
}

int insphere_sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                  const Eigen::Vector3d& e) {
  ensure_exactinit();
  // Shewchuk's insphere expects orient3d(a, b, c, d) > 0; swapping a and b
  // turns our positive orientation into his.
  return sign(insphere(ptr(b), ptr(a), ptr(c), ptr(d), ptr(e)));
}

int orient2d_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  ensure_exactinit();
  return sign(orient2d(ptr(a), ptr(b), ptr(c)));
}

int incircle_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                  const Eigen::Vector2d& d) {
  ensure_exactinit();
  return sign(incircle(ptr(a), ptr(b), ptr(c), ptr(d)));
}

}  // namespace femorph
