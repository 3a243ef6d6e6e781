// Vertex-id keys of faces and edges for pumping's star evaluation (pump_star.cpp), and the per-walk count of link
// facets at each vertex. Internal to the engine.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "qualmesh/types.h"

namespace qualmesh::detail {

using Key3 = std::array<Index, 3>;
using Key2 = std::array<Index, 2>;

struct KeyHash {
  template <std::size_t N>
  std::size_t operator()(const std::array<Index, N>& k) const {
    std::size_t h = 0;
    for (Index i : k) h = h * 1000003u ^ std::hash<Index>()(i);
    return h;
  }
};

// Equality of keys, element by element: std::array's operator== calls memcmp, which was 6% of couplingdown.off's
// whole run in best_weight's scans of the link alone.
struct KeyEq {
  template <std::size_t N>
  bool operator()(const std::array<Index, N>& a, const std::array<Index, N>& b) const {
    for (std::size_t i = 0; i < N; ++i)
      if (a[i] != b[i]) return false;
    return true;
  }
};

inline Key3 sorted3(Index a, Index b, Index c) {  // three compare-exchanges (std::sort's call was 7% of best_weight)
  if (a > b) std::swap(a, b);
  if (b > c) std::swap(b, c);
  if (a > b) std::swap(a, b);
  return Key3{a, b, c};
}

// Link facets per vertex during a walk (best_weight): count(id) is valid while its stamp is the walk's generation,
// so a walk starts with every count zero without clearing. A flat array by vertex id: the scan of (id, count) pairs
// it replaces was a quarter of best_weight's own time. Per thread, for a later parallel pumping.
class LinkCounts {
 public:
  void start() {
    if (++generation_ == 0) {  // wrapped
      std::fill(stamp_.begin(), stamp_.end(), 0);
      generation_ = 1;
    }
    infinite_ = 0;
  }
  int& operator[](Index id) {
    if (id == kNoIndex) return infinite_;
    if (id >= stamp_.size()) {
      stamp_.resize(std::size_t(id) + 1 + stamp_.size() / 2, 0);
      count_.resize(stamp_.size(), 0);
    }
    if (stamp_[id] != generation_) {
      stamp_[id] = generation_;
      count_[id] = 0;
    }
    return count_[id];
  }

 private:
  std::vector<std::uint32_t> stamp_;
  std::vector<int> count_;
  std::uint32_t generation_ = 0;
  int infinite_ = 0;
};

}  // namespace qualmesh::detail
