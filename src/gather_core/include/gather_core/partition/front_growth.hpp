#pragma once
// Labelled fronts for the partitions: a first-order Fast Marching march on a
// region of the grid with what the segmentations need and fmm::FastMarching
// does not offer: a start time per front (additive weights that balance
// areas), fronts confined to a label image, a front that stops after a given
// number of cells, and an "only where it gets closer" march for incremental
// distance-to-a-set updates.
//
// Each front is its own Eikonal solution (a cell's update uses only neighbours
// of the front that reaches it), and a cell takes the label of the front that
// reached it first. A cell's label is inherited from an accepted 4-neighbour of
// the same front, so every label region is 4-connected to its source.
//
// Layout: padded flat arrays (1-cell border of obstacles); no allocation per
// march once the queue has grown; arrays are reset through a touched list.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gather_core/grid/raster.hpp"
#include "gather_core/radix_queue.hpp"

namespace gather {
namespace partition {

class FrontGrowth {
 public:
  // `region`: 1 = the fronts may cover the cell; its frame gives the size and
  // the resolution [m/cell]. Unit speed: times are in metres. Throws
  // gather::Error on an empty frame.
  explicit FrontGrowth(const Mask& region);

  // Slowness [s/m] per cell (row-major); empty = 1 everywhere. Must be > 0.
  void set_slowness(const std::vector<float>& slowness);

  struct Front {
    std::size_t cell;    // row-major index, must be in the region
    double start = 0.0;  // [s] time the front starts (an additive weight)
  };

  // Grows every front over the region. `labels` (row-major, resized) gets
  // k + 1 for cells first reached by front k, 0 elsewhere; a source cell always
  // keeps its own label. `times` (optional) gets the arrival times [s].
  // `confine` (optional, row-major): front k only enters cells with
  // confine[cell] == k + 1.
  void grow(const std::vector<Front>& fronts, std::vector<int32_t>& labels, std::vector<float>* times = nullptr,
            const std::vector<int32_t>* confine = nullptr);

  // Lowers dist[cell] (row-major [s], +inf = far) to the arrival time of one
  // front from `cell`, marching only where it improves dist. `lowered`
  // (optional) gets the cells whose dist it lowered (row-major indices).
  void lower(std::size_t cell, std::vector<float>& dist, std::vector<uint32_t>* lowered = nullptr);

  // --- quota growth (BAP) ------------------------------------------------
  // Weight of each cell in quotas and counts (row-major; e.g. the fine cells
  // a coarse cell stands for); empty = 1 per cell.
  void set_weights(const std::vector<uint32_t>& weights);
  // Starts a new round: every region cell is available.
  void reset_available();
  bool available(std::size_t cell) const { return avail_[pad(cell)] != 0; }
  // Grows one front from `seed` over available cells until it holds `quota`
  // (weight of) cells: a first-order FMM with an area stop (what is left of
  // the available cells may fall apart into pieces). Taken cells get `label`
  // in `labels` (row-major) and stop being available; `taken_cells`
  // (optional) gets them (row-major), in order. Returns the weight taken
  // (< quota when the front's piece of available cells is smaller).
  std::size_t grow_quota(std::size_t seed, std::size_t quota, int32_t label, std::vector<int32_t>& labels,
                         std::vector<uint32_t>* taken_cells = nullptr);
  // Gives every still available cell `label` (the last segment).
  std::size_t take_rest(int32_t label, std::vector<int32_t>& labels);

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  std::size_t pad(std::size_t cell) const {
    return (cell / static_cast<std::size_t>(width_) + 1) * stride_ + cell % static_cast<std::size_t>(width_) + 1;
  }
  std::size_t unpad(std::size_t p) const {
    return (p / stride_ - 1) * static_cast<std::size_t>(width_) + p % stride_ - 1;
  }
  std::size_t cell_weight(std::size_t p) const { return weight_.empty() ? 1 : weight_[p]; }
  float cost(std::size_t p) const { return slowness_.empty() ? res_ : res_ * slowness_[p]; }
  // First-order Eikonal update of p from accepted neighbours with label L.
  inline float update(std::size_t p, int32_t label) const;  // defined (and used) in front_growth.cpp
  void reset_touched();

  int width_, height_;
  std::size_t stride_;
  float res_;
  std::vector<uint8_t> region_;   // padded
  std::vector<uint8_t> avail_;    // padded, quota rounds
  std::vector<float> slowness_;   // padded, empty = unit
  std::vector<uint32_t> weight_;  // padded, empty = 1
  std::vector<float> time_;       // padded
  std::vector<int32_t> label_;    // padded
  std::vector<uint8_t> state_;    // padded: 0 far, 1 band, 2 accepted, 3 pinned source
  std::vector<uint32_t> touched_;
  struct Entry {
    float t;
    uint32_t p;
  };
  // lower()'s queue, in exact (time, cell) order: keys order_key(time, cell).
  gather::RadixQueue queue_;
  std::vector<Entry> sources_;
  std::vector<std::vector<uint32_t>> buckets_;
  float min_slowness_ = 1.0f, max_slowness_ = 1.0f;
};

}  // namespace partition
}  // namespace gather
