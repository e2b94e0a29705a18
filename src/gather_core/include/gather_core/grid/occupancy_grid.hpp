#pragma once
// A 2-D occupancy grid in the ROS map convention: cells row-major, row 0 at the
// lowest y (the bottom of the image), origin = lower-left corner of cell (0,0).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gather_core/grid/raster.hpp"

namespace gather {

class OccupancyGrid {
 public:
  OccupancyGrid() = default;
  // `values` are nav_msgs/OccupancyGrid values (-1 unknown, 0..100 occupancy),
  // `free` marks traversable cells (1) - unknown cells are never traversable.
  // resolution [m/cell] > 0; origin [m]. Throws std::invalid_argument on size mismatch.
  OccupancyGrid(int width, int height, double resolution, Point2 origin, std::vector<int8_t> values,
                std::vector<uint8_t> free);

  const GridFrame& frame() const { return frame_; }
  int width() const { return frame_.width; }
  int height() const { return frame_.height; }
  std::size_t size() const { return values_.size(); }
  double resolution() const { return frame_.resolution; }  // [m/cell]
  Point2 origin() const { return frame_.origin; }          // [m]

  bool contains(Cell c) const { return frame_.contains(c); }
  std::size_t index(Cell c) const { return frame_.index(c); }
  Cell cell(std::size_t index) const { return frame_.cell(index); }
  int8_t value(Cell c) const { return values_[index(c)]; }
  bool is_free(Cell c) const { return contains(c) && free_[index(c)] != 0; }

  // Cell containing a map-frame point [m]; may lie outside the grid (check contains()).
  Cell world_to_cell(Point2 p) const { return frame_.world_to_cell(p); }
  // Centre of a cell in the map frame [m].
  Point2 cell_center(Cell c) const { return frame_.cell_center(c); }

  const std::vector<int8_t>& values() const { return values_; }
  const std::vector<uint8_t>& free_mask() const { return free_; }
  std::size_t free_cells() const;
  double cell_area() const { return frame_.cell_area(); }  // [m^2]

 private:
  GridFrame frame_;
  std::vector<int8_t> values_;
  std::vector<uint8_t> free_;
};

}  // namespace gather
