// A map from 64-bit keys to small values (not bool: std::vector<bool> has no element address), with open
// addressing and linear probing in flat arrays; nothing is ever erased.
// The input complex's hot lookups use it: elements_meet_acute's answers by element pair, which pumping, sliver
// insertion and the improvement pass ask for again and again, and find_segment, which subsegment_of asks for every
// edge between two input vertices (on a CAD surface every node is one); and each facet's map from the ids of its
// input and segment vertices to their 2D vertices, which every subfacet test reads. With std::unordered_map, the
// lookups of elements_meet_acute alone were 4% of pump carter's run at --size 44.13 and 8% of bunny00.off's with
// --encroaching steiner (perf). Not thread-safe, like the rest of the refinement state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace qualmesh::detail {

template <typename Value>
class FlatMap {
 public:
  // The value stored for `key`, or nullptr.
  const Value* find(std::uint64_t key) const {
    const std::size_t i = position(key);
    return i == kAbsent ? nullptr : &values_[i];
  }
  // Stores `value` for a key that find() does not hold.
  void insert(std::uint64_t key, const Value& value) {
    if (2 * (size_ + 1) > keys_.size()) grow(2 * (size_ + 1));
    std::size_t i = slot(key);
    while (used_[i]) i = (i + 1) & mask_;
    keys_[i] = key;
    values_[i] = value;
    used_[i] = 1;
    ++size_;
  }
  // Stores `value` for `key`, replacing the value stored before.
  void set(std::uint64_t key, const Value& value) {
    const std::size_t i = position(key);
    if (i == kAbsent) insert(key, value);
    else values_[i] = value;
  }
  // Room for `n` keys without growing.
  void reserve(std::size_t n) {
    if (2 * n > keys_.size()) grow(2 * n);
  }
  std::size_t size() const { return size_; }

 private:
  static constexpr std::size_t kAbsent = ~std::size_t(0);
  // The slot holding `key`, or kAbsent.
  std::size_t position(std::uint64_t key) const {
    if (keys_.empty()) return kAbsent;
    for (std::size_t i = slot(key);; i = (i + 1) & mask_) {
      if (!used_[i]) return kAbsent;
      if (keys_[i] == key) return i;
    }
  }
  std::size_t slot(std::uint64_t key) const { return std::size_t((key * 0x9E3779B97F4A7C15ull) >> shift_); }
  void grow(std::size_t at_least) {
    std::size_t capacity = 8;  // small: every facet has a map, most of them with a few keys
    while (capacity < at_least) capacity *= 2;
    std::vector<std::uint64_t> keys = std::move(keys_);
    std::vector<Value> values = std::move(values_);
    std::vector<std::uint8_t> used = std::move(used_);
    keys_.assign(capacity, 0);
    values_.assign(capacity, Value());
    used_.assign(capacity, 0);
    mask_ = capacity - 1;
    shift_ = 64;
    for (std::size_t c = capacity; c > 1; c >>= 1) --shift_;
    size_ = 0;
    for (std::size_t i = 0; i < keys.size(); ++i)
      if (used[i]) insert(keys[i], values[i]);
  }
  std::vector<std::uint64_t> keys_;
  std::vector<Value> values_;
  std::vector<std::uint8_t> used_;
  std::size_t mask_ = 0;
  int shift_ = 64;
  std::size_t size_ = 0;
};

}  // namespace qualmesh::detail
