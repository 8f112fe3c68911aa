// Stable counting sort: items grouped by a small integer key, in key order, each key's items in
// their own order. The per-frame hot paths group by cell (blob index), by node (relaxation
// labels), by cluster root (rigid-swap repair) and by view count (ghost filter) this way: linear
// in items plus keys, no comparisons, and the caller's buffers are reused from frame to frame.
#pragma once

#include <cstddef>
#include <vector>

namespace mocap {

// For items 0..count-1 with keys key(i) in [0, keys): calls place(i, slot) with each item's slot
// in the grouped order, items in increasing i. On return key k's slots are
// [(*begin)[k], (*begin)[k + 1]); *begin has keys + 1 entries, the last count.
template <typename Key, typename Place>
void CountingSort(int count, int keys, Key key, std::vector<int>* begin, Place place) {
  // Key k's count goes to begin[k + 2], the running sum makes begin[k + 1] its first slot, and
  // placing an item there advances it to key k + 1's first: begin[k] ends as key k's first slot.
  begin->assign(static_cast<std::size_t>(keys) + 2, 0);
  int* first = begin->data();
  for (int i = 0; i < count; ++i) ++first[key(i) + 2];
  for (int k = 2; k < keys + 2; ++k) first[k] += first[k - 1];
  for (int i = 0; i < count; ++i) place(i, first[key(i) + 1]++);
  begin->pop_back();
}

}  // namespace mocap
