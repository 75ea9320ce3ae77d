#include "base/bucket_order.h"

#include <cstddef>

namespace edgedeform {

Buckets bucket_order(const std::vector<int>& key, int n_buckets) {
  Buckets b;
  b.offsets.assign(static_cast<std::size_t>(n_buckets) + 1, 0);
  for (int k : key) ++b.offsets[static_cast<std::size_t>(k) + 1];
  for (int i = 0; i < n_buckets; ++i) b.offsets[static_cast<std::size_t>(i) + 1] += b.offsets[static_cast<std::size_t>(i)];
  b.order.resize(key.size());
  std::vector<int> cursor(b.offsets.begin(), b.offsets.end() - 1);
  for (std::size_t item = 0; item < key.size(); ++item)
    b.order[static_cast<std::size_t>(cursor[static_cast<std::size_t>(key[item])]++)] = static_cast<int>(item);
  return b;
}

}  // namespace edgedeform
