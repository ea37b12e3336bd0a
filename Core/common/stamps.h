// Stamps: one mark per slot (a tet, a vertex ...) that is cleared in O(1).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace femorph {

/// A slot is marked when stamp[slot] == the value next() returned last.
/// next() takes a fresh value, which unmarks every slot at once, so a walk or
/// a "seen" test needs no clearing pass; only when the counter wraps to 0 is
/// the array cleared. T: an unsigned integer type; a narrow one is smaller in
/// cache but clears the array more often (uint16_t: every 65,535 values).
template <class T>
struct Stamps {
  std::vector<T> stamp;
  T value = 0;

  /// A value no slot holds, with `stamp` grown to at least `slots` entries.
  T next(std::size_t slots) {
    if (stamp.size() < slots) stamp.resize(slots, T(0));
    if (++value == 0) {
      std::fill(stamp.begin(), stamp.end(), T(0));
      value = 1;
    }
    return value;
  }

  /// Unmarks everything: `slots` entries, all 0, and the counter restarted.
  void reset(std::size_t slots) {
    stamp.assign(slots, T(0));
    value = 0;
  }
};

}  // namespace femorph
