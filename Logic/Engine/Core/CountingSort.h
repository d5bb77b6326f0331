#pragma once
/// @file CountingSort.h
/// @brief Items grouped by a small integer key in linear time, stable: the CSR layouts of the refinement solver
/// and the keypoint grid of the guided matching.
#include <numeric>
#include <vector>

namespace tissuemosaic {

/// The items of key k are order[begin[k]] .. order[begin[k + 1] - 1], in item order.
struct Buckets {
  std::vector<int> begin;  ///< keys + 1
  std::vector<int> order;  ///< count
};

/// Groups items 0 .. count - 1 by key(i), which must lie in [0, keys).
template <class Key>
Buckets bucketByKey(int count, int keys, const Key& key) {
  std::vector<int> keyOf(static_cast<std::size_t>(count));  // key() once per item
  Buckets buckets;
  buckets.begin.assign(static_cast<std::size_t>(keys) + 1, 0);
  for (int i = 0; i < count; ++i) {
    keyOf[static_cast<std::size_t>(i)] = key(i);
    ++buckets.begin[static_cast<std::size_t>(keyOf[static_cast<std::size_t>(i)]) + 1];
  }
  std::partial_sum(buckets.begin.begin(), buckets.begin.end(), buckets.begin.begin());
  buckets.order.resize(static_cast<std::size_t>(count));
  std::vector<int> next(buckets.begin.begin(), buckets.begin.end() - 1);
  for (int i = 0; i < count; ++i) {
    buckets.order[static_cast<std::size_t>(next[static_cast<std::size_t>(keyOf[static_cast<std::size_t>(i)])]++)] = i;
  }
  return buckets;
}

}  // namespace tissuemosaic
