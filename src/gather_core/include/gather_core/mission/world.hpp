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
  // Where the workers of the OC wait on robots, one home per segment
  // (`segments[k]`: the cells of worker k's segment, row-major; the order
  // of the workers, e.g. by agent id, decides who comes first): the cell
  // nearest its plain home (oc_worker_home; by 8-connected steps through the
  // free space, so past a pocket of coverage) with `clearance` [m] of room
  // in the coverage (to the nearest wall or cell out of the coverage: a
  // robot that stops near its home, or steps aside there, stays in touch
  // with the OC) and 2 x `clearance` from the homes of the workers before
  // it (parked robots leave room to pass between them), off the lanes where
  // it can: the narrow parts of the ways from the coverage's exits the
  // workers take to the OC, 0.3 m + two robot radii either side. Where no
  // cell has that, half the room at half the spacing, and so on down to two
  // cells; then the plain home. {-1, -1} for a segment that reaches no coverage.
  // Computes the coverage's clearance once.
  std::vector<Cell> oc_worker_homes(const std::vector<std::vector<Cell>>& segments, double clearance) const;
};

}  // namespace mission
}  // namespace gather
