// Internal to lib/dataset: the loop every random dataset shares. Row i draws from its own counter-based
// stream (seed, i) until an attempt gives a label worth keeping, so the set is the same for any thread count;
// draws and labelled candidates are tallied per row and summed after the loop (integer sums: order-free).
#pragma once

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "dataset/enumeration.hpp"
#include "dataset/labelled_set.hpp"
#include "dataset/labeller.hpp"
#include "dataset/progress_counter.hpp"
#include "dataset/random_stream.hpp"

namespace contactnn::dataset::detail {

/// One attempt: nothing that passed the filters (no label), or a labelled candidate and whether it is kept.
struct Attempt {
  std::optional<Label> label;
  bool keep = false;
};

/// Fills `count` rows of a `kind` set: for row i, `attempt(random)` with random = RandomStream(seed, i) until
/// one is kept (its canonical features, label and gap go in the row); more than `max_draws` attempts for a
/// row is InvalidArgument with `hopeless_message`. `summary`: grid_points = attempts, geometric_kept =
/// labelled candidates, status counts over those, the kept rows' iteration histogram, time.
template <class AttemptFn>
LabelledSet sample_rows(SurfaceKind kind, std::int64_t count, std::uint64_t seed, std::int64_t max_draws,
                        const AttemptFn& attempt, EnumerationSummary& summary, const ProgressFn& progress,
                        const std::string& hopeless_message) {
  const auto start_time = std::chrono::steady_clock::now();
  CONTACTNN_REQUIRE(count >= 1, "count must be >= 1, got " << count);
  struct RowTally {
    std::int64_t drawn = 0;
    std::int64_t labelled = 0;
    std::array<std::int64_t, kStatusCount> status{};
  };
  LabelledSet set;
  set.resize(count, kind);
  std::vector<RowTally> tally(static_cast<std::size_t>(count));
  ProgressCounter rows_done(progress, count, 256);
  std::atomic<bool> hopeless{false};
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t row = 0; row < count; ++row) {
    if (hopeless.load(std::memory_order_relaxed)) continue;
    RandomStream random(seed, static_cast<std::uint64_t>(row));
    RowTally& t = tally[static_cast<std::size_t>(row)];
    for (;;) {
      if (t.drawn >= max_draws) {
        hopeless = true;
        break;
      }
      ++t.drawn;
      const Attempt a = attempt(random);
      if (!a.label) continue;
      ++t.labelled;
      ++t.status[static_cast<std::size_t>(a.label->status)];
      if (!a.keep) continue;
      store_label(*a.label, static_cast<Eigen::Index>(row), set);
      break;
    }
    rows_done.row_done();
  }
  CONTACTNN_REQUIRE(!hopeless, hopeless_message);
  rows_done.finish();

  summary = EnumerationSummary{};
  for (const RowTally& t : tally) {
    summary.grid_points += t.drawn;
    summary.geometric_kept += t.labelled;
    for (int s = 0; s < kStatusCount; ++s)
      summary.status_counts[static_cast<std::size_t>(s)] += t.status[static_cast<std::size_t>(s)];
  }
  for (std::int64_t row = 0; row < count; ++row) {
    ++summary.iteration_histogram[static_cast<std::size_t>(std::min(set.iterations[row], 63))];
  }
  summary.kept = count;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return set;
}

}  // namespace contactnn::dataset::detail
