#pragma once
// Multi-wall log-distance radio model (scenario section `radio`):
//   received [dBm] = tx - ref_loss - 10 * exponent * log10(d / 1 m) - wall_loss * min(walls, max_walls)
// A wall is a run of consecutive non-free cells (occupied or unknown) crossed
// by the straight segment between the two points. A link exists when
// received >= sensitivity. Distances below the 1 m reference count as 1 m.
#include <cstdint>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {

class RadioModel {
 public:
  // Keeps a reference to `grid`: it must outlive the model.
  RadioModel(const OccupancyGrid& grid, const RadioParams& params);

  // Walls crossed by the segment a-b [m] (runs of non-free cells; the cells of
  // a and b themselves count if they are not free). Points outside the grid:
  // the part of the segment outside counts as free space.
  int walls_between(Point2 a, Point2 b) const;
  // Received power at b of a transmission from a [dBm].
  double received_dbm(Point2 a, Point2 b) const;
  // received_dbm(a, b) >= sensitivity, counting walls only as far as it matters.
  bool linked(Point2 a, Point2 b) const { return linked(a, b, distance(a, b)); }
  // The same, with their distance d = distance(a, b) [m] known.
  bool linked(Point2 a, Point2 b, double d) const;

  // Largest distance a link can span without walls [m].
  double free_space_range() const { return free_range_m_; }

  // Coverage of a transmitter at `tx` [m]: 1 for every free cell whose centre
  // is linked to tx, 0 elsewhere, on the grid's frame. The first form writes
  // into `mask` (it takes the grid's frame), so repeated calls reuse its memory.
  void coverage(Point2 tx, Mask& mask) const;
  Mask coverage(Point2 tx) const {
    Mask m;
    coverage(tx, m);
    return m;
  }

  const RadioParams& params() const { return params_; }

 private:
  // Received power [dBm] over d_m [m] through `walls` walls.
  double received_for(double d_m, int walls) const;
  double received_without_walls(double d_m) const;
  int affordable_walls(double clear_dbm) const;
  // Walls along a-b in cell units, stopping once `stop_at` walls are counted.
  int count_walls(double ax, double ay, double bx, double by, int stop_at) const;

  const OccupancyGrid& grid_;
  RadioParams params_;
  double free_range_m_ = 0.0;
};

}  // namespace gather
