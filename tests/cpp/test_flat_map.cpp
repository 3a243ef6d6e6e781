// FlatMap (core/src/refine/flat_map.h), the open-addressing map behind the input complex's segment index and its
// acute-angle caches and each facet's map to its 2D vertices: it answers as std::unordered_map with first-insert-wins does, through growth, for keys that
// collide in their low or high bits, for key 0 and for the largest key.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <unordered_map>

#include "refine/flat_map.h"

namespace qualmesh::detail {
namespace {

TEST(FlatMap, AgreesWithUnorderedMapThroughGrowth) {
  FlatMap<std::uint32_t> map;
  std::unordered_map<std::uint64_t, std::uint32_t> reference;
  std::mt19937_64 rng(7);
  EXPECT_EQ(map.find(0), nullptr);  // empty: no table yet
  for (std::uint32_t i = 0; i < 20000; ++i) {
    // Three key families: random, multiples of 2^32 (equal low bits) and small (equal high bits), plus 0 and ~0.
    const std::uint64_t key = i == 0 ? 0 : i == 1 ? ~std::uint64_t(0)
                              : i % 3 == 0 ? rng() : i % 3 == 1 ? (std::uint64_t(i) << 32) : std::uint64_t(i);
    if (!map.find(key)) map.insert(key, i);
    reference.emplace(key, i);
    ASSERT_EQ(map.size(), reference.size());
  }
  for (const auto& [key, value] : reference) {
    const std::uint32_t* found = map.find(key);
    ASSERT_NE(found, nullptr) << key;
    EXPECT_EQ(*found, value) << key;
  }
  std::size_t absent = 0;
  for (int i = 0; i < 20000; ++i) {
    const std::uint64_t key = rng();
    if (!reference.count(key)) {
      EXPECT_EQ(map.find(key), nullptr) << key;
      ++absent;
    }
  }
  EXPECT_GT(absent, 19000u);
}

TEST(FlatMap, ReserveKeepsEntriesAndFirstInsertWins) {
  FlatMap<std::uint8_t> map;
  map.insert(42, 1);
  map.reserve(1000);  // grows the table: the entry must survive the rehash
  ASSERT_NE(map.find(42), nullptr);
  EXPECT_EQ(*map.find(42), 1);
  map.insert(42, 0);  // a duplicate key (the caller's find() would have stopped it): the first stays visible
  EXPECT_EQ(*map.find(42), 1);
  EXPECT_EQ(map.find(43), nullptr);
}

TEST(FlatMap, SetReplacesOrAdds) {
  FlatMap<std::uint32_t> map;
  map.set(5, 1);  // into an empty map
  map.set(5, 2);  // replaced, not added
  EXPECT_EQ(map.size(), 1u);
  EXPECT_EQ(*map.find(5), 2u);
  for (std::uint32_t k = 0; k < 1000; ++k) map.set(k << 20, k);  // through growth; 0 << 20 is key 0
  for (std::uint32_t k = 0; k < 1000; ++k) map.set(k << 20, k + 1);
  EXPECT_EQ(map.size(), 1001u);
  for (std::uint32_t k = 0; k < 1000; ++k) ASSERT_EQ(*map.find(std::uint64_t(k) << 20), k + 1);
  EXPECT_EQ(*map.find(5), 2u);
}

}  // namespace
}  // namespace qualmesh::detail
