#pragma once
// Fast Marching solver of the Eikonal equation |grad T| = 1/F on the
// 4-connected occupancy grid: arrival times T [s] of fronts started at one or
// more sources, travelling at speed F [m/s] (unit speed: T in meters), with a
// label per cell naming the source whose front arrived first.
//
// A `FastMarching` object is a reusable workspace bound to one map: the first
// solve() sizes its arrays, later solves on the same map allocate nothing
// (unless a larger queue or target list is needed than ever before).
// Results (time(), label(), ...) are those of the last solve().
//
// Memory: 1 B/cell traversability mask + 4 B/cell float32 times + 4 B/cell
// int32 labels (only once a solve asked for labels) + 4 B/cell float32 cost
// (only with a speed map) + <= 0.5 B/cell reset list; the arrays carry a
// 2-cell border. See docs/fmm.md for the measured figures.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace fmm {
namespace detail {
struct MarchGrid;  // src/fmm/stencil.hpp
}  // namespace detail

constexpr double kUnreached = std::numeric_limits<double>::infinity();

enum class Order { kFirst = 1, kSecond = 2 };

// Priority queue of the narrow band.
// kBuckets: a circular bucket queue of width `bucket_width` cells; the cells of
//   one bucket are expanded in FIFO order and a cell improved after its
//   expansion is expanded again (label correcting). With the first-order
//   update this ends at the same fixed point as exact FMM, at O(1) per cell.
//   Not for second order, whose update is not monotone (the result would
//   depend on the bucket width).
// kSortedBuckets: the same buckets, each sorted once when its turn comes and
//   merged with a small heap of the cells queued into it meanwhile: exact time
//   order, so classical FMM results, at about half the cost of one heap.
// kHeap: classical FMM with one binary heap (reference for tests and benches).
// kAuto: kBuckets at first order, kSortedBuckets at second order.
enum class QueueKind { kAuto, kBuckets, kSortedBuckets, kHeap };

// Where a front starts: the centre of a cell, or a point in the map frame [m].
// The source cell gets the time |p - centre| / F, its 8 neighbours the exact
// straight-line time |p - centre_n| / F (diagonal ones only when both cells
// between them are free), so the front starts round and sub-cell exact.
struct Source {
  bool is_point = false;
  Cell cell{};     // used when !is_point
  Point2 point{};  // [m], map frame; used when is_point

  static Source at_cell(Cell c) { return Source{false, c, Point2{}}; }
  static Source at_point(Point2 p) { return Source{true, Cell{}, p}; }
};

struct SolveOptions {
  Order order = Order::kFirst;
  // Stop once every cell with T <= max_time [s] is final; later cells stay +inf.
  double max_time = kUnreached;
  // Stop once all these cells are final (other cells keep their time if it is
  // final, +inf otherwise). Empty: run until every reachable cell is reached.
  std::vector<Cell> targets;
  // Track which source reached each cell first (costs 4 B/cell and 20-50% time).
  bool labels = true;
  // Per-source factor (> 0) on the speed map: front i travels at
  // front_speed[i] * F (e.g. to balance partition areas). Empty: all 1.
  // Needs labels (a cell's speed is that of the front leading into it).
  std::vector<double> front_speed;
  // Labels: an expanded cell takes the label of the cell this many cells back
  // along its characteristic (when the way is free), instead of its earliest
  // neighbour's only. 0 = neighbour only (fastest, drifts near collisions).
  int label_look_back = 6;
  QueueKind queue = QueueKind::kAuto;
  // Bucket width [cells crossed at the fastest speed]; 0 = the measured best
  // (2 for kBuckets, 0.02 for kSortedBuckets). Changes speed, not the result
  // (except kBuckets at second order, see QueueKind).
  double bucket_width = 0.0;
};

// Counters of the last solve (for benchmarks and tests).
struct SolveStats {
  std::size_t expanded = 0;    // cells taken from the queue and expanded
  std::size_t pushed = 0;      // queue insertions (seeds included)
  bool stopped_early = false;  // stopped by targets or max_time
};

class FastMarching {
 public:
  FastMarching() = default;
  // Binds the workspace to the grid's size, resolution, origin and free mask
  // (copied; the grid need not outlive the workspace). Unit speed (1 m/s).
  explicit FastMarching(const OccupancyGrid& grid);
  // Binds the workspace to another grid: `frame` and its free mask
  // (row-major, 1 = free, frame.size() values), keeping the memory of the
  // arrays it already holds (for a caller that marches on many small grids
  // in turn, as the planner on each segment's window). Unit speed; the
  // last solve's results are gone. Throws gather::Error on a grid too large.
  void bind(const GridFrame& frame, const std::vector<uint8_t>& free);

  // Speed map [m/s], a value per cell of the grid (row 0 = bottom); 0 =
  // obstacle. Cells that are not free in the grid stay obstacles whatever
  // their speed. Throws gather::Error when its frame is not of the grid's
  // size, or on a negative / non-finite speed.
  void set_speed(const Raster<double>& speed);
  // Back to unit speed (T in meters).
  void set_unit_speed();
  bool unit_speed() const { return cost_.empty(); }

  // Reserves the working lists so that later solves with at most `targets`
  // targets and fronts of at most `front` cells a bucket allocate nothing
  // (for control loops that must not allocate; see WorkerPolicy). Allocates.
  void reserve_work(std::size_t targets, std::size_t front);

  // Runs the march. Sources are labelled by their index in `sources`.
  // Throws gather::Error when `sources` is empty, a source is off the map or in
  // an obstacle, a target is off the map, or the options are invalid
  // (front_speed of the wrong size, not > 0, or without labels).
  const SolveStats& solve(const std::vector<Source>& sources, const SolveOptions& options = {});

  // --- results of the last solve -------------------------------------------
  // Arrival time [s] at the centre of `c`; kUnreached when unreached, off the
  // map or an obstacle.
  double time(Cell c) const;
  // Index of the source that reached `c` first; -1 when unreached (or when the
  // last solve had labels off).
  int label(Cell c) const;
  bool reached(Cell c) const { return time(c) < kUnreached; }
  // Arrival time [s] at a map-frame point [m]: the best of T(n) + |p - centre_n| / F
  // over the point's cell and its 4 neighbours; kUnreached if none is reached.
  double time_at(Point2 p) const;
  // The times [s] (+inf unreached) and labels (-1 unreached) of every cell,
  // on the grid's frame. The copy_ forms reuse `out`'s memory (it takes the
  // grid's frame).
  Raster<double> times() const;
  LabelImage labels() const;
  void copy_times(Raster<double>& out) const;
  void copy_labels(LabelImage& out) const;
  // The grid's frame (size, resolution [m/cell], origin [m]).
  GridFrame frame() const { return GridFrame{width_, height_, resolution_, origin_}; }
  // Cells with a finite time (a scan of the grid).
  std::size_t count_reached() const;
  const std::vector<Source>& sources() const { return sources_; }
  const SolveStats& stats() const { return stats_; }

  // --- geometry ------------------------------------------------------------
  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return resolution_; }  // [m/cell]
  Point2 origin() const { return origin_; }          // [m]
  bool contains(Cell c) const { return c.row >= 0 && c.col >= 0 && c.row < height_ && c.col < width_; }
  // Free in the grid and, with a speed map, of positive speed.
  bool traversable(Cell c) const {
    return contains(c) && mask_[padded(c)] != 0 && (cost_.empty() || cost_[padded(c)] < kInfCost);
  }
  // Speed [m/s] of a cell (0 for obstacles and off the map).
  double speed(Cell c) const;
  // Bytes held by the workspace arrays (capacity, not size).
  std::size_t working_bytes() const;

  // --- padded flat layout (for path extraction and other hot loops) -------
  // Index of a cell in the padded arrays: (row + 2) * stride() + col + 2.
  std::size_t padded(Cell c) const {
    return static_cast<std::size_t>(c.row + kPad) * stride_ + static_cast<std::size_t>(c.col + kPad);
  }
  std::size_t stride() const { return stride_; }
  const float* padded_times() const { return times_.data(); }  // [s], +inf unreached / border
  // Seconds per meter of travel in cell `c` (1/F), +inf for obstacles.
  double slowness(Cell c) const;

  // A cell whose time was set directly from a source (not by the march).
  struct Seed {
    uint32_t index;  // padded index
    int32_t source;  // index into sources()
    float time;      // [s] the time the source gave it
  };
  const std::vector<Seed>& seeds() const { return seeds_; }

  static constexpr int kPad = 2;
  static constexpr float kInfCost = std::numeric_limits<float>::infinity();

 private:
  // The marches (bucket_march.cpp, heap_march.cpp), one instantiation per
  // combination of flags; solve() picks one from their tables.
  using March = void (FastMarching::*)(const SolveOptions&);
  template <bool kUnit, bool kLabels, bool kSecond, bool kExact>
  void march_buckets(const SolveOptions& options);
  template <bool kUnit, bool kLabels, bool kSecond>
  void march_heap(const SolveOptions& options);
  struct BucketMarches;
  struct HeapMarches;
  static March bucket_march(bool unit, bool labels, bool second, bool exact);
  static March heap_march(bool unit, bool labels, bool second);
  inline detail::MarchGrid march_grid(bool labels, int look_back);  // defined in src/fmm/stencil.hpp
  void reset_times();
  void seed(const std::vector<Source>& sources, bool labels);
  void note_touched(uint32_t p) {
    if (touched_overflow_) return;
    if (touched_.size() < touched_limit_)
      touched_.push_back(p);
    else
      touched_overflow_ = true;
  }
  float cost_at(std::size_t p) const { return cost_.empty() ? unit_cost_ : cost_[p]; }

  int width_ = 0;
  int height_ = 0;
  std::size_t stride_ = 0;
  double resolution_ = 1.0;
  Point2 origin_{};
  float unit_cost_ = 1.0f;  // seconds per cell at unit speed = resolution
  float min_cost_ = 1.0f;   // [s per cell] at the fastest speed
  float max_cost_ = 1.0f;   // [s per cell] at the slowest positive speed

  std::vector<uint8_t> mask_;    // padded, 1 = free in the grid
  std::vector<float> cost_;      // padded [s per cell] = resolution / F (+inf at F = 0); empty at unit speed
  std::vector<float> times_;     // padded [s]
  std::vector<int32_t> labels_;  // padded; valid where times_ is finite and labels_on_
  bool labels_on_ = false;

  std::vector<uint32_t> touched_;  // cells made finite by the last solve (reset list)
  bool touched_overflow_ = true;   // too many to list: reset everything
  std::size_t touched_limit_ = 0;

  std::vector<std::vector<uint32_t>> buckets_;
  struct HeapEntry {
    float key;
    uint32_t index;
  };
  std::vector<HeapEntry> heap_;
  std::vector<uint64_t> sorted_;  // kSortedBuckets: the current bucket, sorted
  std::vector<uint64_t> bheap_;   // kSortedBuckets: cells queued into the current bucket
  std::vector<uint32_t> late_;
  std::vector<uint32_t> targets_;

  std::vector<float> inv_front_speed_;  // 1 / SolveOptions::front_speed of the current solve
  std::vector<Source> sources_;
  std::vector<Seed> seeds_;
  SolveStats stats_;
};

}  // namespace fmm
}  // namespace gather
