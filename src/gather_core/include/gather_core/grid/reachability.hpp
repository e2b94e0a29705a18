#pragma once
// Connected free space (4-connected, the same neighbourhood FMM uses).
#include <cstdint>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

// In the grid's frame: 1 for every free cell 4-connected to `start`, 0
// elsewhere. All zeros if `start` is not a free cell.
Mask reachable_from(const OccupancyGrid& grid, Cell start);

struct FreeSpaceSummary {
  std::size_t free_cells = 0;
  std::size_t reachable_cells = 0;      // in the component of the start cell
  std::size_t other_components = 0;     // free components the start cannot reach
  std::size_t largest_other_cells = 0;  // size of the largest of those
};

FreeSpaceSummary summarize_free_space(const OccupancyGrid& grid, Cell start);

}  // namespace gather
