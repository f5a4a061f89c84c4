#include "contact/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "contact/face_surface.hpp"
#include "core/error.hpp"

namespace contactnn::contact {

SurfaceTracker::SurfaceTracker(const SearchOptions& options, TrackingOptions tracking)
    : options_(options), tracking_(tracking) {
  CONTACTNN_REQUIRE(std::isfinite(tracking.margin_relative) && tracking.margin_relative >= 0.0,
                    "tracking margin " << tracking.margin_relative << " is not a finite non-negative number");
  CONTACTNN_REQUIRE(
      std::isfinite(tracking.grid_margin_relative) && tracking.grid_margin_relative >= 0.0,
      "tracking grid margin " << tracking.grid_margin_relative << " is not a finite non-negative number");
}

void SurfaceTracker::reset() {
  ids_.clear();
  anchors_.clear();
  drift_at_build_.clear();
  lists_.clear();
  hints_.clear();
  answers_.clear();
  near_.clear();
  box_drift_ = 0.0;
  centres_.clear();
  radii_.clear();
  drift_ = 0.0;
  faces_ = -1;
  grid_ = FaceGrid{};
  topology_.reset();
}

std::vector<NodeSegmentPair> SurfaceTracker::step(const mesh::SurfaceMesh& master,
                                                  std::span<const Vec3> master_normals,
                                                  std::span<const long> slave_ids,
                                                  std::span<const Vec3> slave_positions,
                                                  TrackingCounts* counts) {
  std::vector<NodeSegmentPair> pairs;
  step(master, master_normals, slave_ids, slave_positions, pairs, counts);
  return pairs;
}

void SurfaceTracker::step(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                          std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                          std::vector<NodeSegmentPair>& pairs, TrackingCounts* counts) {
  step(master, master_normals, slave_ids, slave_positions, contacts_, counts);
  to_pairs(master, master_normals, options_, contacts_, slave_positions, pairs);
}

void SurfaceTracker::step(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                          std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                          std::vector<Contact>& pairs, TrackingCounts* counts) {
  CONTACTNN_REQUIRE(slave_ids.size() == slave_positions.size(),
                    slave_ids.size() << " slave ids for " << slave_positions.size() << " positions");
  if (options_.narrow == NarrowPhase::kReference) {
    step_lists(master, master_normals, slave_ids, slave_positions, pairs, counts);
  } else {
    step_hints(master, master_normals, slave_ids, slave_positions, pairs, counts);
  }
}

void SurfaceTracker::reorder() {
  // near_ and answers_ follow the order the nodes are searched in (read in sequence: by node, a million
  // slave ids in random order cost a cache miss each): each node's entries move from its place in the
  // previous order to its place in the new.
  const std::size_t n = order_.size();
  place_.resize(n);
  near_scratch_.resize(n);
  answers_scratch_.resize(n);
#pragma omp parallel for schedule(static) if (n >= 65536)
  for (std::size_t k = 0; k < n; ++k) place_[previous_order_[k]] = static_cast<std::uint32_t>(k);
#pragma omp parallel for schedule(static) if (n >= 65536)
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t from = place_[order_[k]];
    near_scratch_[k] = near_[from];
    answers_scratch_[k] = answers_[from];
  }
  near_.swap(near_scratch_);
  answers_.swap(answers_scratch_);
}

std::array<double, 2> SurfaceTracker::extrapolated(const mesh::SurfaceMesh& master, int face,
                                                   const std::array<double, 2>& before,
                                                   const std::array<double, 2>& last) const {
  std::array<double, 2> next{};
  if (master.face_corners(face).size() != 4) {
    // A triangle's domain r, s >= 0, r + s <= 1: the extrapolated point clamped to r, s >= 0, then scaled
    // onto r + s = 1 where beyond it. (Its last point instead cost the tri6 sheet's tracked search a second
    // Newton step at most nodes: 1.98 steps a node against a quad8's 1.00.)
    for (std::size_t k = 0; k < 2; ++k) next[k] = std::max(2.0 * last[k] - before[k], 0.0);
    const double sum = next[0] + next[1];
    if (!std::isfinite(sum)) return last;
    if (sum > 1.0) next = {next[0] / sum, next[1] / sum};
    return next;
  }
  // A quadrilateral's domain is a square: the extrapolated point clamped into it.
  const ParamDomain d = param_domain(detail::kind_of(master, options_, face));
  for (std::size_t k = 0; k < 2; ++k) {
    const double x = 2.0 * last[k] - before[k];
    next[k] = std::isfinite(x) ? std::clamp(x, d.lo, d.hi) : last[k];
  }
  return next;
}

void SurfaceTracker::step_hints(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                                std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                                std::vector<Contact>& pairs, TrackingCounts* counts) {
  const std::size_t n = slave_ids.size();
  // The same slave points as the last step (compared in parallel: a million ids are 8 MB a step).
  bool same = master.face_count() == faces_ && n == ids_.size();
  if (same) {
#pragma omp parallel for reduction(&& : same) schedule(static) if (n >= 65536)
    for (std::size_t i = 0; i < n; ++i) same = same && slave_ids[i] == ids_[i];
  }
  if (!same) {
    reset();
    ids_.assign(slave_ids.begin(), slave_ids.end());
    hints_.assign(n, FaceHint{});
    answers_.assign(n, {0.0, 0.0});
    faces_ = master.face_count();
  }
  // Step 1: the grid kept while every face stays inside its box at the build, inflated by the margin.
  const SurfaceSearcher searcher(master, master_normals, options_, &grid_, tracking_.grid_margin_relative,
                                 &topology_, &storage_);
  // Rule 5's drift: the largest movement of a face's box, summed over the states.
  box_drift_ = same ? box_drift_ + searcher.box_drift() : 0.0;
  if (!same || !std::isfinite(box_drift_)) {
    near_.assign(n, NearFaces{});
    box_drift_ = 0.0;
  }
  // Rule 5's lists at a state whose faces' boxes moved by at most 0.05 of a grid cell since the last (half a
  // list's smallest budget: a list then lasts states). Where the master moves more per increment, every list
  // would be made again at every state, at a larger radius than the grid's own query (replay's decks, whose
  // tools move at each increment, took 3-10% longer): the grid gathers every node's faces.
  const bool listed = !same || searcher.box_drift() <= 0.05 * grid_.cell();
  pairs.resize(n);
  // The nodes in Morton order, kept while the grid is (the order serves the caches, not the answers).
  if (!same || order_.size() != n || searcher.grid_rebuilt()) {
    const bool kept = same && order_.size() == n;
    if (kept) previous_order_.assign(order_.begin(), order_.end());
    spatial_order(slave_positions, order_, order_scratch_);
    if (kept) reorder();
  }
  const std::uint32_t* order = order_.data();
  long fresh = 0, tracked = 0, list_faces = 0;
#pragma omp parallel reduction(+ : fresh, tracked, list_faces) if (n >= 512)
  {
    std::vector<std::pair<double, int>> candidates;
    std::vector<std::pair<std::uint32_t, double>> scratch;
    // Runs of 256 nodes: each thread writes its nodes' answers, hints and lists in long runs (with runs of 64
    // the threads shared a cache line of them every 64 nodes, and 2 threads were 1.7x one on the large
    // history's tracked search; 2.0x now).
#pragma omp for schedule(dynamic, 256)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = order[k];
      // Steps 2-3: the previous face first, from the previous point.
      const FaceHint* hint = hints_[i].face >= 0 ? &hints_[i] : nullptr;
      Contact& contact = pairs[i];
      searcher.nearest_fresh(slave_ids[i], slave_positions[i], candidates, scratch, contact, hint,
                             listed ? &near_[k] : nullptr, box_drift_);
      if (contact.status == PairStatus::kFound) {
        // Rule 2's start at the next increment: on the same face as at the last, the point extrapolated from
        // the last two answers (a steady motion's next answer; one Newton step fewer), else this answer.
        const bool same_face = hint != nullptr && hint->face == contact.face;
        // Member by member: a FaceHint built aside and copied was read back across its own stores (a
        // store-forwarding stall, 3% of the large history's tracked search).
        FaceHint& next = hints_[i];
        next.param =
            same_face ? extrapolated(master, contact.face, answers_[k], contact.param) : contact.param;
        next.face = contact.face;
        next.warm = true;
        answers_[k] = contact.param;
      } else {
        hints_[i] = FaceHint{};
      }
      fresh += hint == nullptr;
      tracked += hint != nullptr;
      list_faces += static_cast<long>(candidates.size());
    }
  }
  if (counts != nullptr) *counts = {fresh, tracked, tracked, list_faces, searcher.grid_rebuilt() ? 1 : 0};
}

void SurfaceTracker::step_lists(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                                std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                                std::vector<Contact>& pairs, TrackingCounts* counts) {
  const SurfaceSearcher searcher(master, master_normals, options_);
  const double unit = searcher.unit();
  const std::vector<Vec3>& centres = searcher.centres();
  const std::vector<double>& radii = searcher.radii();
  const std::size_t n = slave_ids.size();

  // Step 2's drift; a new surface or new slave nodes start over.
  const bool same = centres.size() == centres_.size() &&
                    std::equal(slave_ids.begin(), slave_ids.end(), ids_.begin(), ids_.end());
  if (!same) {
    reset();
    ids_.assign(slave_ids.begin(), slave_ids.end());
    anchors_.assign(n, Vec3::Zero());
    drift_at_build_.assign(n, 0.0);
    lists_.assign(n, {});
    hints_.assign(n, FaceHint{});
  } else {
    // In the searcher's unit (exact: a power of two): a norm of world lengths near 1e-200 underflowed to 0,
    // and a list stayed valid however far its faces had moved.
    double largest = 0.0;
    for (std::size_t f = 0; f < centres.size(); ++f) {
      largest = std::max(largest,
                         ((centres[f] - centres_[f]) / unit).norm() + std::abs(radii[f] - radii_[f]) / unit);
    }
    drift_ += largest * unit;
  }
  centres_ = centres;
  radii_ = radii;

  const double capture = searcher.capture();
  const double margin = tracking_.margin_relative * capture;
  pairs.resize(n);
  spatial_order(slave_positions, order_, order_scratch_);
  const std::uint32_t* order = order_.data();
  long fresh = 0, tracked = 0, warm = 0, list_faces = 0;
  // A parallel region costs microseconds: only for enough nodes (the answers do not depend on it).
#pragma omp parallel reduction(+ : fresh, tracked, warm, list_faces) if (n >= 512)
  {
    std::vector<std::pair<double, int>> candidates, list_build;
    std::vector<std::pair<std::uint32_t, double>> scratch;
#pragma omp for schedule(dynamic, 64)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = order[k];
      const Vec3& slave = slave_positions[i];
      std::vector<std::pair<double, int>>& list = lists_[i];
      const double moved = ((slave - anchors_[i]) / unit).norm() * unit + (drift_ - drift_at_build_[i]);
      const bool valid = same && slave.allFinite() && anchors_[i].allFinite() && moved <= margin;
      candidates.clear();
      SurfaceSearcher::Bounds bounds = SurfaceSearcher::Bounds::kLooseSorted;
      if (!valid) {
        // Step 1: a fresh list.
        searcher.faces_within(slave, capture + margin, list_build, scratch, true);
        std::sort(list_build.begin(), list_build.end());
        list.assign(list_build.begin(), list_build.end());
        list_build.clear();
        anchors_[i] = slave;
        drift_at_build_[i] = drift_;
        // This increment's candidates: the fresh search's (each face's own bound).
        for (const auto& c : list) {
          const double bound = searcher.lower_bound(slave, c.second);
          if (bound <= capture) candidates.emplace_back(bound, c.second);
        }
        bounds = SurfaceSearcher::Bounds::kExact;
        ++fresh;
      } else {
        // Step 3's bounds, sorted as the list: those beyond the capture distance end it.
        for (const auto& c : list) {
          const double bound = c.first - moved;
          if (bound > capture) break;
          candidates.emplace_back(bound, c.second);
        }
        ++tracked;
      }
      list_faces += static_cast<long>(list.size());
      // Step 3: the previous face first from its previous point.
      const FaceHint* hint = hints_[i].face >= 0 ? &hints_[i] : nullptr;
      warm += hint != nullptr;
      pairs[i] = searcher.nearest_contact(slave_ids[i], slave, candidates, hint, bounds);
      hints_[i] =
          pairs[i].status == PairStatus::kFound ? FaceHint{pairs[i].face, pairs[i].param} : FaceHint{};
    }
  }
  if (counts != nullptr) *counts = {fresh, tracked, warm, list_faces, 0};
}

}  // namespace contactnn::contact
