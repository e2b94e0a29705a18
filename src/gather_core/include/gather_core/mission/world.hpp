#pragma once
// What executing a plan needs to know of the map, computed once from the
// scenario (on its planning grid): the OC's cell, the free space reachable
// from it, the OC's radio coverage and the way back into it. The planner's
// context (plan::PlanContext) extends it; the analytic simulator and every
// agent role use it as it is, so an agent process carries no planning data.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace mission {

struct World {
  // Keeps a reference to `scenario`, which must outlive the world. Throws
  // gather::Error (naming the scenario file) when no free space is reachable
  // from the OC.
  explicit World(const Scenario& scenario);

  const Scenario& scenario;
  Cell oc_cell;
  Mask reachable;  // free cells 4-connected to the OC
  std::size_t reachable_cells = 0;
  double reachable_area = 0.0;        // [m^2]
  Mask coverage;                      // reachable cells linked to the OC by radio
  std::vector<Cell> coverage_border;  // coverage cells next to a non-covered cell (or the map edge)
  // Labelled unit-speed march from coverage_border: the way back into the
  // coverage from any cell (time = distance [m]; label k = coverage_border[k]).
  fmm::FastMarching coverage_field;

  bool covered(Cell c) const { return scenario.grid.contains(c) && coverage[scenario.grid.index(c)] != 0; }
  bool reaches(Cell c) const { return scenario.grid.contains(c) && reachable[scenario.grid.index(c)] != 0; }

  // The reachable cell where a robot at `p` [m] stands: its own cell, or
  // (a pose on a wall, off the map, inside an inflated obstacle: real
  // localisation does that) a nearest reachable cell within `radius_m` [m]
  // (the first square ring of cells around it that holds one); its own cell
  // when there is none (callers check reaches()).
  Cell standing_cell(Point2 p, double radius_m = 2.0) const;

  // Where a worker delivering to the OC waits for requests: the coverage
  // cell nearest its segment (`cells`, in row-major order), where it comes
  // back to from the segment's nearest cell (that cell itself when it is
  // covered). {-1, -1} when no cell of the segment reaches the coverage.
  // The worker policy and the planner's estimate both use it.
  Cell oc_worker_home(const std::vector<Cell>& cells) const;
  // The coverage cell nearest `from` (a coverage cell; by 8-connected steps
  // through the coverage) with at least `clearance` [m] to the nearest
  // blocked cell: `from` itself when it has that room, `from` when no cell
  // has. Computes the map's clearance (not kept).
  Cell roomy_near(Cell from, double clearance) const;
};

}  // namespace mission
}  // namespace gather
