// The scene study's small helpers shared by its steps (internal: included by lib/study's .cpp files only).
#pragma once

#include <omp.h>

#include <chrono>
#include <sstream>
#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "study/scene_study.hpp"

namespace contactnn::study::detail {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

inline std::vector<std::string> split_methods(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto first = item.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    out.push_back(item.substr(first, item.find_last_not_of(" \t") - first + 1));
  }
  return out;
}

inline std::string join(const std::vector<int>& sizes) {
  std::string out;
  for (const int s : sizes) out += (out.empty() ? "" : ",") + std::to_string(s);
  return out;
}

inline int feature_count_of(SurfaceKind surface) { return surface == SurfaceKind::kBilinear ? 8 : 16; }

inline std::string network_name(SurfaceKind surface, int hidden, int second_layer) {
  return std::to_string(feature_count_of(surface)) + "-" + std::to_string(hidden) +
         (second_layer > 0 ? "-" + std::to_string(second_layer) : std::string()) + "-2";
}

inline int team_size(const SceneStudyOptions& options) {
  return options.threads > 0 ? options.threads : omp_get_max_threads();
}

}  // namespace contactnn::study::detail
