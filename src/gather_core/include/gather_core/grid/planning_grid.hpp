#pragma once
// A coarser grid for planning and simulation on large maps.
//
// The planner's cost grows with the number of cells (27 partitions, routes,
// marches), so a map with more than `max_cells` cells is planned on a grid
// whose cells are blocks of f x f map cells. A block is free only when all
// of its cells are free (walls and unknown space are never thinned or
// opened; narrow gaps may close). The factor is lowered while the coarse
// grid would lose part of the reachable space (a door closed by the
// coarsening) or put the OC on a non-free block.
#include <cstddef>
#include <cstdint>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

// Blocks of factor x factor cells (the last row/column of blocks may stick
// out of the map; the missing cells count as unknown). Value: 100 if a cell
// is occupied, else -1 if one is unknown, else the largest value. Same
// origin, resolution x factor. factor >= 1.
OccupancyGrid coarsen(const OccupancyGrid& grid, int factor);

struct PlanningGrid {
  int factor = 1;     // 1: the map's own grid
  double kept = 1.0;  // share of the map's reachable cells still next to coarse reachable space
};

// The factor for a map: the smallest f with cells / f^2 <= max_cells (0 = no
// limit), lowered until the coarse grid keeps `min_kept` (a fraction in (0, 1]) of the reachable
// space (a map cell counts as kept when its block or a neighbouring block is
// reachable from the OC's block) and the OC's block is free.
// The rule of choose_planning_grid from a factor on, for a caller that
// knows the map's reachable space (4-connected to the OC's cell) and wants
// the coarse grid itself: the largest f <= `factor` (and >= 2) whose coarse
// grid keeps `min_kept` and has the OC's block free, with that grid and its
// space reachable from the OC's block; factor 1 (and no grid) when none.
struct CoarseGrid {
  int factor = 1;
  double kept = 1.0;
  OccupancyGrid grid;
  Mask reachable;
};
CoarseGrid coarsest_kept(const OccupancyGrid& grid, Point2 oc, const Mask& reachable, int factor, double min_kept);

PlanningGrid choose_planning_grid(const OccupancyGrid& grid, Point2 oc, std::size_t max_cells, double min_kept = 0.98);

}  // namespace gather
