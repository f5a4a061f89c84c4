#include "contact/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/error.hpp"

namespace contactnn::contact {

SurfaceTracker::SurfaceTracker(const SearchOptions& options, TrackingOptions tracking)
    : options_(options), tracking_(tracking) {
  CONTACTNN_REQUIRE(std::isfinite(tracking.margin_relative) && tracking.margin_relative >= 0.0,
                    "tracking margin " << tracking.margin_relative << " is not a finite non-negative number");
}

void SurfaceTracker::reset() {
  ids_.clear();
  anchors_.clear();
  drift_at_build_.clear();
  lists_.clear();
  hints_.clear();
  centres_.clear();
  radii_.clear();
  drift_ = 0.0;
}

std::vector<NodeSegmentPair> SurfaceTracker::step(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                                                  std::span<const long> slave_ids,
                                                  std::span<const Vec3> slave_positions, TrackingCounts* counts) {
  CONTACTNN_REQUIRE(slave_ids.size() == slave_positions.size(),
                    slave_ids.size() << " slave ids for " << slave_positions.size() << " positions");
  const SurfaceSearcher searcher(master, master_normals, options_);
  const std::vector<Vec3>& centres = searcher.centres();
  const std::vector<double>& radii = searcher.radii();
  const std::size_t n = slave_ids.size();

  // Step 2's drift; a new surface or new slave nodes start over.
  const bool same = centres.size() == centres_.size() && std::equal(slave_ids.begin(), slave_ids.end(), ids_.begin(), ids_.end());
  if (!same) {
    reset();
    ids_.assign(slave_ids.begin(), slave_ids.end());
    anchors_.assign(n, Vec3::Zero());
    drift_at_build_.assign(n, 0.0);
    lists_.assign(n, {});
    hints_.assign(n, FaceHint{});
  } else {
    double largest = 0.0;
    for (std::size_t f = 0; f < centres.size(); ++f) {
      largest = std::max(largest, (centres[f] - centres_[f]).norm() + std::abs(radii[f] - radii_[f]));
    }
    drift_ += largest;
  }
  centres_ = centres;
  radii_ = radii;

  const double capture = searcher.capture();
  const double margin = tracking_.margin_relative * capture;
  std::vector<NodeSegmentPair> pairs(n);
  long fresh = 0, tracked = 0, warm = 0, list_faces = 0;
  // A parallel region costs microseconds: only for enough nodes (the answers do not depend on it).
#pragma omp parallel reduction(+ : fresh, tracked, warm, list_faces) if (n >= 512)
  {
    std::vector<std::pair<double, int>> candidates;
    std::vector<std::pair<std::uint32_t, double>> scratch;
#pragma omp for schedule(dynamic, 64)
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& slave = slave_positions[i];
      std::vector<int>& list = lists_[i];
      const bool valid = same && slave.allFinite() && anchors_[i].allFinite() &&
                         (slave - anchors_[i]).norm() + (drift_ - drift_at_build_[i]) <= margin;
      candidates.clear();
      if (!valid) {
        // Step 1: a fresh list.
        searcher.faces_within(slave, capture + margin, candidates, scratch);
        list.clear();
        for (const auto& c : candidates) list.push_back(c.second);
        std::sort(list.begin(), list.end());
        anchors_[i] = slave;
        drift_at_build_[i] = drift_;
        ++fresh;
      } else {
        for (int f : list) candidates.emplace_back(searcher.lower_bound(slave, f), f);
        ++tracked;
      }
      list_faces += static_cast<long>(list.size());
      // Step 3: the faces within the capture distance now, the previous face first from its previous point.
      std::erase_if(candidates, [&](const std::pair<double, int>& c) { return c.first > capture; });
      const FaceHint* hint = hints_[i].face >= 0 ? &hints_[i] : nullptr;
      warm += hint != nullptr;
      pairs[i] = searcher.nearest(slave_ids[i], slave, candidates, hint);
      hints_[i] = pairs[i].status == PairStatus::kFound ? FaceHint{pairs[i].segment, pairs[i].face_param} : FaceHint{};
    }
  }
  if (counts != nullptr) *counts = {fresh, tracked, warm, list_faces};
  return pairs;
}

}  // namespace contactnn::contact
