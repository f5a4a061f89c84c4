// Internal to lib/dataset: the progress of a parallel loop over a set's rows, told to a ProgressFn.
#pragma once

#include <omp.h>

#include <atomic>
#include <chrono>
#include <cstdint>

#include "dataset/enumeration.hpp"

namespace contactnn::dataset::detail {

/// Counts the rows the threads finish and tells `progress` (if any) from thread 0 alone, every `every` rows
/// (a power of 2) and at most twice a second; finish() tells it total of total.
class ProgressCounter {
 public:
  ProgressCounter(const ProgressFn& progress, std::int64_t total, std::int64_t every)
      : progress_(progress), total_(total), mask_(every - 1) {}

  void row_done() {
    const std::int64_t finished = ++done_;
    if (progress_ && omp_get_thread_num() == 0 && (finished & mask_) == 0) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last_report_ > std::chrono::milliseconds(500)) {
        last_report_ = now;
        progress_(finished, total_);
      }
    }
  }

  void finish() const {
    if (progress_) progress_(total_, total_);
  }

 private:
  const ProgressFn& progress_;
  std::int64_t total_, mask_;
  std::atomic<std::int64_t> done_{0};
  std::chrono::steady_clock::time_point last_report_ = std::chrono::steady_clock::now();
};

}  // namespace contactnn::dataset::detail
