#include "gather_core/grid/occupancy_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gather {

OccupancyGrid::OccupancyGrid(int width, int height, double resolution, Point2 origin, std::vector<int8_t> values,
                             std::vector<uint8_t> free)
    : width_(width),
      height_(height),
      resolution_(resolution),
      origin_(origin),
      values_(std::move(values)),
      free_(std::move(free)) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("grid size must be positive");
  if (!(resolution > 0.0)) throw std::invalid_argument("grid resolution must be > 0");
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (values_.size() != n || free_.size() != n)
    throw std::invalid_argument("grid data size does not match width*height");
}

Cell OccupancyGrid::world_to_cell(Point2 p) const {
  return Cell{static_cast<int>(std::floor((p.y - origin_.y) / resolution_)),
              static_cast<int>(std::floor((p.x - origin_.x) / resolution_))};
}

Point2 OccupancyGrid::cell_center(Cell c) const {
  return Point2{origin_.x + (c.col + 0.5) * resolution_, origin_.y + (c.row + 0.5) * resolution_};
}

std::size_t OccupancyGrid::free_cells() const {
  return static_cast<std::size_t>(std::count_if(free_.begin(), free_.end(), [](uint8_t f) { return f != 0; }));
}

}  // namespace gather
