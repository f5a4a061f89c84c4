// Compressed lists (CSR: offsets and entries) of the items at each key, filled in parallel with the layout a
// serial fill gives: each key lists its items in item order at any thread count. The face grid's cells and
// the faces at each node (face_grid.cpp, node_faces.cpp).
#pragma once

#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace contactnn::contact {

/// offsets (keys + 1) and entries of the lists of `items` items over `keys` keys. The keys are split among
/// the threads at split(threads) (threads + 1 bounds from 0 to keys, called once); each thread walks every
/// item in order and counts and fills only its own keys' lists, so no two threads write the same list.
/// own_keys(item, lo, hi, fn) calls fn(key) for each of the item's keys in [lo, hi), in the item's order.
/// Threads only where `parallel`. Index: the offsets' and entries' integer type.
template <class Index, class Split, class OwnKeys>
void fill_lists(std::size_t items, std::size_t keys, bool parallel, Split&& split, OwnKeys&& own_keys,
                std::vector<Index>& offsets, std::vector<Index>& entries) {
  offsets.resize(keys + 1);
  offsets[0] = 0;
  entries.clear();
  std::vector<Index> ends;         // each thread's count, then the offset its keys start at
  std::vector<std::size_t> parts;  // thread t's keys: [parts[t], parts[t + 1])
#pragma omp parallel if (parallel)
  {
    const auto threads = static_cast<std::size_t>(omp_get_num_threads());
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
#pragma omp single
    {
      ends.assign(threads + 1, 0);
      parts = split(threads);
    }
    const std::size_t lo = parts[t], hi = parts[t + 1];
    const auto first = static_cast<std::ptrdiff_t>(lo), last = static_cast<std::ptrdiff_t>(hi);
    // This thread's keys' counts in offsets[key + 1], then their running sums.
    std::fill(offsets.begin() + first + 1, offsets.begin() + last + 1, Index{0});
    for (std::size_t item = 0; item < items; ++item)
      own_keys(item, lo, hi, [&](std::size_t key) { ++offsets[key + 1]; });
    Index sum = 0;
    for (std::size_t key = lo; key < hi; ++key) {
      sum += offsets[key + 1];
      offsets[key + 1] = sum;
    }
    ends[t + 1] = sum;
#pragma omp barrier
#pragma omp single
    {
      for (std::size_t k = 1; k <= threads; ++k) ends[k] += ends[k - 1];
      entries.resize(static_cast<std::size_t>(ends[threads]));
    }
    for (std::size_t key = lo; key < hi; ++key) offsets[key + 1] += ends[t];
#pragma omp barrier
    // The fill: each key's next free entry, from its start (offsets[lo] is the thread before's last sum).
    std::vector<Index> at(offsets.begin() + first, offsets.begin() + last);
    for (std::size_t item = 0; item < items; ++item) {
      own_keys(item, lo, hi, [&](std::size_t key) {
        entries[static_cast<std::size_t>(at[key - lo]++)] = static_cast<Index>(item);
      });
    }
  }
}

}  // namespace contactnn::contact
