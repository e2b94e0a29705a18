#pragma once
// A 2-D occupancy grid in the ROS map convention: cells row-major, row 0 at the
// lowest y (the bottom of the image), origin = lower-left corner of cell (0,0).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

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

class OccupancyGrid {
 public:
  OccupancyGrid() = default;
  // `values` are nav_msgs/OccupancyGrid values (-1 unknown, 0..100 occupancy),
  // `free` marks traversable cells (1) - unknown cells are never traversable.
  // resolution [m/cell] > 0; origin [m]. Throws std::invalid_argument on size mismatch.
  OccupancyGrid(int width, int height, double resolution, Point2 origin, std::vector<int8_t> values,
                std::vector<uint8_t> free);

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t size() const { return values_.size(); }
  double resolution() const { return resolution_; }  // [m/cell]
  Point2 origin() const { return origin_; }          // [m]

  bool contains(Cell c) const { return c.row >= 0 && c.col >= 0 && c.row < height_ && c.col < width_; }
  std::size_t index(Cell c) const { return static_cast<std::size_t>(c.row) * width_ + c.col; }
  Cell cell(std::size_t index) const {
    return Cell{static_cast<int>(index / width_), static_cast<int>(index % width_)};
  }
  int8_t value(Cell c) const { return values_[index(c)]; }
  bool is_free(Cell c) const { return contains(c) && free_[index(c)] != 0; }

  // Cell containing a map-frame point [m]; may lie outside the grid (check contains()).
  Cell world_to_cell(Point2 p) const;
  // Centre of a cell in the map frame [m].
  Point2 cell_center(Cell c) const;

  const std::vector<int8_t>& values() const { return values_; }
  const std::vector<uint8_t>& free_mask() const { return free_; }
  std::size_t free_cells() const;
  double cell_area() const { return resolution_ * resolution_; }  // [m^2]

 private:
  int width_ = 0;
  int height_ = 0;
  double resolution_ = 1.0;
  Point2 origin_{};
  std::vector<int8_t> values_;
  std::vector<uint8_t> free_;
};

}  // namespace gather
