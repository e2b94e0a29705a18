#pragma once
// Clearance: how far each cell is from the nearest cell a robot cannot enter.
#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

class ClearanceMap {
 public:
  // Exact Euclidean distance transform (Felzenszwalb-Huttenlocher) of the
  // grid's blocked cells (occupied, unknown, and everything outside the map).
  explicit ClearanceMap(const OccupancyGrid& grid);

  // Distance [m] from the centre of `c` to the centre of the nearest blocked
  // cell; 0 for blocked cells and cells off the map.
  double at(Cell c) const;
  // A lower bound [m] on the distance from the map point p to the nearest
  // blocked cell (the whole square, not its centre): clearance of p's cell
  // minus |p - that centre| minus half a cell diagonal. <= 0 when p is blocked.
  double free_distance(Point2 p) const;
  // True if a disc of `radius` [m] centred at p surely touches no blocked cell.
  // A lower bound [m] on free_distance(p) from p's cell alone (its
  // clearance less a whole cell diagonal, and 1 nm for rounding; 0 where p
  // is blocked): no distance from p to its cell's centre is worked out.
  double free_distance_floor(Point2 p) const;
  // The same as free_distance(p) >= radius, which it works out only when
  // the cell's clearance alone does not decide it.
  bool disc_free(Point2 p, double radius) const;

  const Field& values() const { return meters_; }  // [m], in the grid's frame
  const OccupancyGrid& grid() const { return grid_; }

 private:
  const OccupancyGrid& grid_;
  Field meters_;
};

}  // namespace gather
