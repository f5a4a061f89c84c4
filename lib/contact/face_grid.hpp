// The surface search's broad phase: a uniform grid of cells over the faces' bounding boxes (a bucket sort in
// the manner of OpenRadioss's i7buce), each face listed in every cell its box overlaps.
//
// A query lists every face whose box comes within `reach` of a point: the faces of the cells that the cube
// x +- reach overlaps (inflated by a relative 1e-9, so that rounding cannot leave a face out), each face once
// (a face is reported from the first cell of its own range inside the query's). A superset: the caller
// computes each face's own bound. A query costs the cells it visits; a k-d tree over the face centres cost
// 27 times the cell lookup on the large history (results/cgal.md), and its reach had to add the largest
// face's radius.
//
// The cell size is half the faces' mean box side (at least 1e-300 of the extent), grown where the cells would
// outnumber 16 x faces + 64 (a small body far from a large one): a cell then holds more faces, never fewer.
// Half a side: a tracked node's query (a reach of its gap) reads a cell of a few faces; at a whole side, the
// large history's tracked search and the tri3 block's (bench_cgal) took 7-10% longer.
// Boxes may be inflated by a margin when the grid is built (tracking.hpp reuses a grid while every face's
// box stays inside its inflated box at the build: a movement budget).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/surface_point.hpp"

namespace contactnn::contact {

using geometry::Vec3;

class FaceGrid {
 public:
  /// The grid of faces f with boxes [box_lo[f] - margin, box_hi[f] + margin]; a non-finite box is listed in
  /// no cell (its face is never a candidate). Resets what was built before; its storage reused.
  /// `unit` is the length unit the boxes are in (kept for the caller's check: unit()).
  void build(std::span<const Vec3> box_lo, std::span<const Vec3> box_hi, double margin, double unit = 1.0);
  [[nodiscard]] bool empty() const { return faces_ == 0; }
  [[nodiscard]] double margin() const { return margin_; }
  /// The side of a cell (the unit of the boxes).
  [[nodiscard]] double cell() const { return cell_; }
  [[nodiscard]] double unit() const { return unit_; }
  /// Whether every face f's box lies inside the box it had at the build, inflated by the margin (then the
  /// grid still lists every face near a point: the queries stay exact).
  [[nodiscard]] bool holds(std::span<const Vec3> box_lo, std::span<const Vec3> box_hi) const;
  /// The boxes the grid was last built for or found to hold, by the caller's stamp (FaceIndex::generation):
  /// boxes of the same stamp are those boxes, bit for bit, so the grid holds them without a look.
  void held(std::uint64_t stamp) { held_ = stamp; }
  [[nodiscard]] std::uint64_t held() const { return held_; }

  /// fn(face) once for every face whose (build-time, inflated) box comes within `reach` of x, and maybe a
  /// few more; nothing for a non-finite x.
  template <class Fn>
  void for_faces_near(const Vec3& x, double reach, Fn&& fn) const {
    if (faces_ == 0 || !x.allFinite() || !(reach >= 0.0)) return;
    const double r = reach * (1.0 + 1e-9) + 1e-9 * cell_;
    std::array<int, 3> lo{}, hi{};
    for (int k = 0; k < 3; ++k) {
      if (x[k] + r < low_[k] || x[k] - r > high_[k]) return;
      lo[static_cast<std::size_t>(k)] = cell_of(x[k] - r, k);
      hi[static_cast<std::size_t>(k)] = cell_of(x[k] + r, k);
    }
    if (lo == hi) {
      // One cell: each of its faces once, without the test below.
      const std::size_t c = cell_index(lo[0], lo[1], lo[2]);
      for (std::uint32_t e = offsets_[c]; e < offsets_[c + 1]; ++e) fn(static_cast<int>(entries_[e]));
      return;
    }
    for (int k = lo[2]; k <= hi[2]; ++k) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const std::size_t c = cell_index(i, j, k);
          for (std::uint32_t e = offsets_[c]; e < offsets_[c + 1]; ++e) {
            const std::uint32_t f = entries_[e];
            const std::array<int, 3>& first = first_cell_[f];
            // Once: from the first cell of the face's range within the query's.
            if (i == std::max(first[0], lo[0]) && j == std::max(first[1], lo[1]) &&
                k == std::max(first[2], lo[2])) {
              fn(static_cast<int>(f));
            }
          }
        }
      }
    }
  }

  /// A face listed in x's cell (the one whose box centre is nearest x), else in one of the 26 cells around
  /// it; -1 when none is (or x is not finite). Any face does for the search's first reach; a near one
  /// gathers fewer candidates.
  /// With `around` false, only x's own cell (-1 where it lists none).
  [[nodiscard]] int face_near(const Vec3& x, std::span<const Vec3> centres, bool around = true) const;

 private:
  std::uint64_t held_ = 0;
  /// offsets_ and entries_ from first_cell_ and last_cell_ for `cells` cells (build's last step).
  void fill_cells(std::size_t cells);
  /// The rows of cells (a y-row at each z) split among `threads` threads: thread t fills rows [split[t],
  /// split[t + 1]), about as many faces starting in each part.
  [[nodiscard]] std::vector<std::size_t> row_split(std::size_t rows, std::size_t threads) const;
  /// Cell (i, j, k)'s index in offsets_ (x fastest).
  [[nodiscard]] std::size_t cell_index(int i, int j, int k) const {
    return static_cast<std::size_t>((static_cast<long>(k) * dims_[1] + j) * static_cast<long>(dims_[0]) + i);
  }
  [[nodiscard]] int cell_of(double v, int k) const {
    const double t = std::floor((v - low_[k]) * inverse_);
    const int last = dims_[static_cast<std::size_t>(k)] - 1;
    return t <= 0.0 ? 0 : t >= static_cast<double>(last) ? last : static_cast<int>(t);
  }

  std::size_t faces_ = 0;
  double margin_ = 0.0;
  double unit_ = 0.0;
  Vec3 low_ = Vec3::Zero(), high_ = Vec3::Zero();  ///< the inflated boxes' extent
  double cell_ = 1.0, inverse_ = 1.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::uint32_t> offsets_;  ///< cell c's faces: entries_[offsets_[c] .. offsets_[c + 1])
  std::vector<std::uint32_t> entries_;
  std::vector<std::array<int, 3>> first_cell_;  ///< the lowest cell of each face's range
  std::vector<std::array<int, 3>> last_cell_;   ///< the highest (build only)
  std::vector<Vec3> built_lo_, built_hi_;       ///< the boxes at the build, inflated
};

}  // namespace contactnn::contact
