// Ordering many items by a small integer key in linear time (a counting sort): the mesh's
// edges and the graph's arcs are grouped by their first vertex or node this way, and only
// the handful of items within each group is sorted by comparison. At 560k vertices this
// took the edge topology from 269 to 116 ms and the node graph from 346 to 234 ms, against
// one std::sort over every corner (record 0054).
#pragma once

#include <cstddef>
#include <vector>

namespace edgedeform {

struct Buckets {
  std::vector<int> offsets;  // bucket b holds order[offsets[b] .. offsets[b + 1])
  std::vector<int> order;    // item ids, by bucket; within a bucket in ascending id
};

// Items 0 .. key.size()-1 grouped by key (each in [0, n_buckets)).
Buckets bucket_order(const std::vector<int>& key, int n_buckets);

}  // namespace edgedeform
