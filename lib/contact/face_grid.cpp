#include "contact/face_grid.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "contact/parallel_lists.hpp"

namespace contactnn::contact {

namespace {

/// The most cells the grid may have for `faces` faces (header).
double cell_budget(std::size_t faces) { return 16.0 * static_cast<double>(faces) + 64.0; }

}  // namespace

void FaceGrid::build(std::span<const Vec3> box_lo, std::span<const Vec3> box_hi, double margin, double unit) {
  faces_ = box_lo.size();
  margin_ = margin;
  unit_ = unit;
  built_lo_.resize(faces_);
  built_hi_.resize(faces_);
  first_cell_.resize(faces_);
  last_cell_.resize(faces_);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // The inflated boxes, their hull and their mean side, over kChunks fixed runs of faces summed in order: the
  // same bits at any thread count (the grid's layout does not change the answers, but stays reproducible).
  constexpr std::size_t kChunks = 64;
  struct Part {
    Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 high = Vec3::Constant(-std::numeric_limits<double>::infinity());
    double side_sum = 0.0;
    std::size_t finite = 0;
  };
  std::array<Part, kChunks> parts;
#pragma omp parallel for schedule(static) if (faces_ >= 16384)
  for (std::size_t chunk = 0; chunk < kChunks; ++chunk) {
    Part& part = parts[chunk];
    for (std::size_t f = faces_ * chunk / kChunks; f < faces_ * (chunk + 1) / kChunks; ++f) {
      built_lo_[f] = box_lo[f] - Vec3::Constant(margin);
      built_hi_[f] = box_hi[f] + Vec3::Constant(margin);
      if (!built_lo_[f].allFinite() || !built_hi_[f].allFinite()) continue;
      part.low = part.low.cwiseMin(built_lo_[f]);
      part.high = part.high.cwiseMax(built_hi_[f]);
      part.side_sum += (built_hi_[f] - built_lo_[f]).maxCoeff();
      ++part.finite;
    }
  }
  low_ = Vec3::Constant(kInf);
  high_ = Vec3::Constant(-kInf);
  double side_sum = 0.0;
  std::size_t finite = 0;
  for (const Part& part : parts) {
    low_ = low_.cwiseMin(part.low);
    high_ = high_.cwiseMax(part.high);
    side_sum += part.side_sum;
    finite += part.finite;
  }
  offsets_.assign(2, 0);
  entries_.clear();
  dims_ = {1, 1, 1};
  if (finite == 0) {
    faces_ = 0;
    return;
  }
  const Vec3 extent = high_ - low_;
  cell_ =
      std::max(0.5 * side_sum / static_cast<double>(finite), 1e-300 * std::max(extent.maxCoeff(), 1e-300));
  // Cells of side cell_, grown until they fit the budget; at most 2^20 along an axis.
  for (;;) {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) cells *= std::min(std::floor(extent[k] / cell_) + 1.0, 1048576.0);
    if (cells <= cell_budget(finite)) break;
    cell_ *= std::max(1.01, std::cbrt(cells / cell_budget(finite)));
  }
  inverse_ = 1.0 / cell_;
  for (int k = 0; k < 3; ++k) {
    dims_[static_cast<std::size_t>(k)] =
        static_cast<int>(std::min(std::floor(extent[k] * inverse_) + 1.0, 1048576.0));
  }
  const std::size_t cells = static_cast<std::size_t>(dims_[0]) * static_cast<std::size_t>(dims_[1]) *
                            static_cast<std::size_t>(dims_[2]);
  // Each face's cells (in parallel), then counted and filled in face order (CSR).
#pragma omp parallel for schedule(static) if (faces_ >= 16384)
  for (std::size_t f = 0; f < faces_; ++f) {
    if (!built_lo_[f].allFinite() || !built_hi_[f].allFinite()) {
      first_cell_[f] = {1, 1, 1};  // an empty range: listed nowhere
      last_cell_[f] = {0, 0, 0};
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      first_cell_[f][static_cast<std::size_t>(k)] = cell_of(built_lo_[f][k], k);
      last_cell_[f][static_cast<std::size_t>(k)] = cell_of(built_hi_[f][k], k);
    }
  }
  fill_cells(cells);
}

std::vector<std::size_t> FaceGrid::row_split(std::size_t rows, std::size_t threads) const {
  // Rows split where about as many faces start before each split (a surface fills few of its grid's rows: an
  // even split of the rows would leave a thread with none of them).
  std::vector<std::size_t> split(threads + 1, rows);
  split[0] = 0;
  if (threads == 1) return split;
  std::vector<std::uint32_t> starting(rows, 0);  // the faces whose first cell is in each row
  std::size_t listed = 0;
  for (std::size_t f = 0; f < faces_; ++f) {
    if (first_cell_[f][0] > last_cell_[f][0]) continue;  // listed nowhere
    ++starting[static_cast<std::size_t>(first_cell_[f][2]) * static_cast<std::size_t>(dims_[1]) +
               static_cast<std::size_t>(first_cell_[f][1])];
    ++listed;
  }
  std::size_t before = 0, t = 1;
  for (std::size_t row = 0; row < rows && t < threads; ++row) {
    while (t < threads && before >= listed * t / threads) split[t++] = row;
    before += starting[row];
  }
  return split;
}

void FaceGrid::fill_cells(std::size_t cells) {
  // Counted and filled in face order (CSR), in parallel with the serial layout (fill_lists). The threads own
  // whole rows of cells (a y-row at each z), split where as many faces start (row_split).
  const std::size_t rows = static_cast<std::size_t>(dims_[1]) * static_cast<std::size_t>(dims_[2]);
  const auto row_cells = static_cast<std::size_t>(dims_[0]);
  const auto split = [&](std::size_t threads) {
    std::vector<std::size_t> bounds = row_split(rows, threads);
    for (std::size_t& b : bounds) b *= row_cells;
    return bounds;
  };
  // fn(cell) for each of face f's cells in [lo, hi) (whole rows), in the serial order.
  const auto own_cells = [&](std::size_t f, std::size_t lo, std::size_t hi, auto&& fn) {
    const std::size_t row_lo = lo / row_cells, row_hi = hi / row_cells;
    for (int k = first_cell_[f][2]; k <= last_cell_[f][2]; ++k) {
      for (int j = first_cell_[f][1]; j <= last_cell_[f][1]; ++j) {
        const std::size_t row =
            static_cast<std::size_t>(k) * static_cast<std::size_t>(dims_[1]) + static_cast<std::size_t>(j);
        if (row < row_lo || row >= row_hi) continue;
        for (int i = first_cell_[f][0]; i <= last_cell_[f][0]; ++i) fn(cell_index(i, j, k));
      }
    }
  };
  fill_lists(faces_, cells, faces_ >= 16384, split, own_cells, offsets_, entries_);
}

bool FaceGrid::holds(std::span<const Vec3> box_lo, std::span<const Vec3> box_hi) const {
  if (box_lo.size() != built_lo_.size()) return false;
  bool inside = true;
#pragma omp parallel for reduction(&& : inside) schedule(static) if (box_lo.size() >= 16384)
  for (std::size_t f = 0; f < box_lo.size(); ++f) {
    // A face listed nowhere (a non-finite box at the build) must stay so: its box must stay non-finite.
    const bool listed = built_lo_[f].allFinite() && built_hi_[f].allFinite();
    inside = inside && (listed ? (box_lo[f].array() >= built_lo_[f].array()).all() &&
                                     (box_hi[f].array() <= built_hi_[f].array()).all()
                               : !(box_lo[f].allFinite() && box_hi[f].allFinite()));
  }
  return inside;
}

int FaceGrid::face_near(const Vec3& x, std::span<const Vec3> centres, bool around) const {
  if (faces_ == 0 || !x.allFinite()) return -1;
  std::array<int, 3> at{};
  for (int k = 0; k < 3; ++k) at[static_cast<std::size_t>(k)] = cell_of(x[k], k);
  int best = -1;
  double nearest = std::numeric_limits<double>::infinity();
  const auto scan = [&](int i, int j, int k) {
    const std::size_t c = cell_index(i, j, k);
    for (std::uint32_t e = offsets_[c]; e < offsets_[c + 1]; ++e) {
      const std::uint32_t f = entries_[e];
      const double d = (centres[f] - x).squaredNorm();
      if (d < nearest || (d == nearest && static_cast<int>(f) < best)) {
        nearest = d;
        best = static_cast<int>(f);
      }
    }
  };
  scan(at[0], at[1], at[2]);
  if (best >= 0 || !around) return best;
  for (int k = std::max(at[2] - 1, 0); k <= std::min(at[2] + 1, dims_[2] - 1); ++k)
    for (int j = std::max(at[1] - 1, 0); j <= std::min(at[1] + 1, dims_[1] - 1); ++j)
      for (int i = std::max(at[0] - 1, 0); i <= std::min(at[0] + 1, dims_[0] - 1); ++i) scan(i, j, k);
  return best;
}

}  // namespace contactnn::contact
