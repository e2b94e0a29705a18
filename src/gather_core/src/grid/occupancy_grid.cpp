#include "gather_core/grid/occupancy_grid.hpp"

#include <algorithm>
#include <stdexcept>

namespace gather {

OccupancyGrid::OccupancyGrid(int width, int height, double resolution, Point2 origin, std::vector<int8_t> values,
                             std::vector<uint8_t> free)
    : frame_{width, height, resolution, origin}, values_(std::move(values)), free_(std::move(free)) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("grid size must be positive");
  if (!(resolution > 0.0)) throw std::invalid_argument("grid resolution must be > 0");
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (values_.size() != n || free_.size() != n)
    throw std::invalid_argument("grid data size does not match width*height");
}

std::size_t OccupancyGrid::free_cells() const {
  return static_cast<std::size_t>(std::count_if(free_.begin(), free_.end(), [](uint8_t f) { return f != 0; }));
}

}  // namespace gather
