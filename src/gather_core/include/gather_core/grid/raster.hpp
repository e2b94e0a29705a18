#pragma once
// A value per cell of a map-aligned grid, and the frame that places the grid
// in the map. The ROS map convention throughout: cells row-major, row 0 at the
// lowest y (the bottom of an image), origin = lower-left corner of cell (0,0).
// Label images, distance fields and masks travel between stages as rasters so
// that their size and placement go with their values.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gather_core/error.hpp"

namespace gather {

// A grid cell. `row` grows with y, `col` grows with x.
struct Cell {
  int row = 0;
  int col = 0;
  friend bool operator==(Cell a, Cell b) { return a.row == b.row && a.col == b.col; }
  friend bool operator!=(Cell a, Cell b) { return !(a == b); }
};

// A point in the map frame [m].
struct Point2 {
  double x = 0.0;
  double y = 0.0;
};

// Straight-line distance [m].
inline double distance(Point2 a, Point2 b) { return std::hypot(a.x - b.x, a.y - b.y); }
// The point of the straight piece a-b nearest to p; `u` (if given) gets
// where it lies on the piece, in [0, 1] from a to b (0 on a piece of no
// length).
inline Point2 nearest_on_piece(Point2 p, Point2 a, Point2 b, double* u = nullptr) {
  const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  const double t = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  if (u) *u = t;
  return Point2{a.x + t * dx, a.y + t * dy};
}

// Size and placement of a grid: width x height cells of `resolution` [m/cell],
// cell (0,0)'s lower-left corner at `origin` [m].
struct GridFrame {
  int width = 0;            // [cells]
  int height = 0;           // [cells]
  double resolution = 1.0;  // [m/cell]
  Point2 origin{};          // [m]

  std::size_t size() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  bool contains(Cell c) const { return c.row >= 0 && c.col >= 0 && c.row < height && c.col < width; }
  std::size_t index(Cell c) const { return static_cast<std::size_t>(c.row) * static_cast<std::size_t>(width) + c.col; }
  Cell cell(std::size_t index) const {
    return Cell{static_cast<int>(index / static_cast<std::size_t>(width)),
                static_cast<int>(index % static_cast<std::size_t>(width))};
  }
  // Cell containing a map point [m]; may lie outside the grid (check contains()).
  // A point beyond +-1e9 cells, or not a number, gives a cell off every map
  // (no overflow in the conversion).
  Cell world_to_cell(Point2 p) const {
    return Cell{cell_index(std::floor((p.y - origin.y) / resolution)),
                cell_index(std::floor((p.x - origin.x) / resolution))};
  }
  static int cell_index(double v) {
    if (!(std::abs(v) < 1e9)) return v > 0 ? 1000000000 : -1000000000;
    return static_cast<int>(v);
  }
  // Centre of a cell in the map frame [m].
  Point2 cell_center(Cell c) const {
    return Point2{origin.x + (c.col + 0.5) * resolution, origin.y + (c.row + 0.5) * resolution};
  }
  double cell_area() const { return resolution * resolution; }  // [m^2]
  bool same_size(const GridFrame& o) const { return width == o.width && height == o.height; }
  friend bool operator==(const GridFrame& a, const GridFrame& b) {
    return a.same_size(b) && a.resolution == b.resolution && a.origin.x == b.origin.x && a.origin.y == b.origin.y;
  }
  friend bool operator!=(const GridFrame& a, const GridFrame& b) { return !(a == b); }
  std::string size_text() const { return std::to_string(width) + "x" + std::to_string(height); }
};

// One T per cell of a frame, row-major. Reads like the vector it holds
// (operator[], size(), begin(), data()) so hot loops keep their flat indexing.
template <class T>
class Raster {
 public:
  Raster() = default;
  explicit Raster(const GridFrame& frame, T fill = T{}) : frame_(frame), values_(frame.size(), fill) {}
  // Throws std::invalid_argument when values.size() != frame.size().
  Raster(const GridFrame& frame, std::vector<T> values) : frame_(frame), values_(std::move(values)) {
    if (values_.size() != frame_.size())
      throw std::invalid_argument("raster of " + frame_.size_text() + " cells given " + std::to_string(values_.size()) +
                                  " values");
  }

  const GridFrame& frame() const { return frame_; }
  int width() const { return frame_.width; }
  int height() const { return frame_.height; }
  std::size_t size() const { return values_.size(); }
  bool empty() const { return values_.empty(); }
  // One value per cell of the frame (false once released).
  bool filled() const { return values_.size() == frame_.size(); }

  T& operator[](std::size_t i) { return values_[i]; }
  const T& operator[](std::size_t i) const { return values_[i]; }
  // The value of cell c; c must lie in the frame.
  T& at(Cell c) { return values_[frame_.index(c)]; }
  const T& at(Cell c) const { return values_[frame_.index(c)]; }

  const std::vector<T>& values() const { return values_; }
  std::vector<T>& values() { return values_; }
  typename std::vector<T>::iterator begin() { return values_.begin(); }
  typename std::vector<T>::iterator end() { return values_.end(); }
  typename std::vector<T>::const_iterator begin() const { return values_.begin(); }
  typename std::vector<T>::const_iterator end() const { return values_.end(); }
  T* data() { return values_.data(); }
  const T* data() const { return values_.data(); }

  // The same values placed by another frame of the same size (a label image
  // read from a PNG, which stores no placement, takes its grid's frame).
  // Throws std::invalid_argument when the sizes differ.
  void reframe(const GridFrame& frame) {
    if (!frame.same_size(frame_))
      throw std::invalid_argument("raster of " + frame_.size_text() + " cells cannot take a frame of " +
                                  frame.size_text());
    frame_ = frame;
  }
  // Frees the values (an agent that keeps only its own segment's cells).
  void release() { std::vector<T>().swap(values_); }

  friend bool operator==(const Raster& a, const Raster& b) { return a.frame_ == b.frame_ && a.values_ == b.values_; }
  friend bool operator!=(const Raster& a, const Raster& b) { return !(a == b); }

 private:
  GridFrame frame_;
  std::vector<T> values_;
};

// The one check of a raster handed to a stage with its grid: throws
// gather::Error(where, "<what> is WxH cells holding N values, the grid
// W'xH'") unless `raster` holds one value per cell of a frame of `frame`'s
// size (a released raster keeps its frame but no values).
template <class T>
void require_same_size(const Raster<T>& raster, const GridFrame& frame, const std::string& where,
                       const std::string& what) {
  if (raster.frame().same_size(frame) && raster.filled()) return;
  throw Error(where, what + " is " + raster.frame().size_text() + " cells holding " + std::to_string(raster.size()) +
                         " values, the grid " + frame.size_text());
}

// 0 = no segment, k = segment k (1..N_w); or room ids for ground truth.
using LabelImage = Raster<int32_t>;
// A distance or time per cell ([m] or [s], as the producer says).
using Field = Raster<float>;
// 1 = in, 0 = out.
using Mask = Raster<uint8_t>;

}  // namespace gather
