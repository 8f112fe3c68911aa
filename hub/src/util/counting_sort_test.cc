// Counting sort: the grouping std::stable_sort makes, with each key's range in *begin.
#include "util/counting_sort.h"

#include <algorithm>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(CountingSort, GroupsByKeyKeepingOrderWithinAKey) {
  std::mt19937 random(3);
  std::vector<int> begin = {7, 7, 7};  // a reused buffer: its old contents must not matter
  for (int round = 0; round < 200; ++round) {
    const int keys = 1 + static_cast<int>(random() % 40);
    const int count = static_cast<int>(random() % 300);
    std::vector<int> key(count);
    // Some rounds crowd a few keys, others spread over all of them.
    const int used = round % 2 == 0 ? std::min(keys, 3) : keys;
    for (int& k : key) k = static_cast<int>(random() % used) * (keys / used);
    std::vector<int> order(count, -1), placed_in_order;
    CountingSort(
        count, keys, [&](int i) { return key[i]; }, &begin,
        [&](int i, int slot) {
          order[slot] = i;
          placed_in_order.push_back(i);
        });
    std::vector<int> expected(count);
    std::iota(expected.begin(), expected.end(), 0);
    std::stable_sort(expected.begin(), expected.end(), [&](int a, int b) { return key[a] < key[b]; });
    ASSERT_EQ(order, expected);
    std::vector<int> ascending(count);
    std::iota(ascending.begin(), ascending.end(), 0);
    EXPECT_EQ(placed_in_order, ascending);
    ASSERT_EQ(begin.size(), static_cast<size_t>(keys) + 1);
    EXPECT_EQ(begin.front(), 0);
    EXPECT_EQ(begin.back(), count);
    for (int k = 0; k < keys; ++k) {
      for (int slot = begin[k]; slot < begin[k + 1]; ++slot) ASSERT_EQ(key[order[slot]], k);
    }
  }
}

TEST(CountingSort, NoItems) {
  std::vector<int> begin;
  CountingSort(
      0, 5, [](int) { return 0; }, &begin, [](int, int) { ADD_FAILURE() << "nothing to place"; });
  EXPECT_EQ(begin, std::vector<int>(6, 0));
}

}  // namespace
}  // namespace mocap
