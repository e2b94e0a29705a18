#pragma once
// The goals the OC requests, cycle after cycle: G cells drawn uniformly over
// the free space reachable from the OC (std::mt19937_64 seeded with the run's
// seed; every cycle's goals drawn up front). The analytic simulator and the
// OC role draw them with this one function, so the same seed gives the same
// goals in `gather sim`, `gather run` and a multi-process mission.
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/mission/world.hpp"

namespace gather {
namespace mission {

struct DrawnGoal {
  int cycle = 0;
  Cell cell;
};

// cycles x per_request goals, cycle-major (goal id = index). Throws
// gather::Error when cycles < 0 or per_request < 0.
std::vector<DrawnGoal> draw_goals(const World& world, unsigned seed, int cycles, int per_request);

}  // namespace mission
}  // namespace gather
