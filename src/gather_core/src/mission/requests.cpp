#include "gather_core/mission/requests.hpp"

#include <random>

#include "gather_core/error.hpp"

namespace gather {
namespace mission {

std::vector<DrawnGoal> draw_goals(const World& world, unsigned seed, int cycles, int per_request) {
  if (cycles < 0 || per_request < 0) throw Error("mission", "cycles and goals per request must be >= 0");
  const OccupancyGrid& grid = world.scenario.grid;
  std::vector<uint32_t> reachable;
  reachable.reserve(world.reachable_cells);
  for (std::size_t i = 0; i < world.reachable.size(); ++i)
    if (world.reachable[i]) reachable.push_back(static_cast<uint32_t>(i));
  std::vector<DrawnGoal> goals;
  goals.reserve(static_cast<std::size_t>(cycles) * static_cast<std::size_t>(per_request));
  std::mt19937_64 rng(seed);
  const uint64_t n = reachable.size();  // modulo bias < n / 2^64: negligible
  for (int c = 0; c < cycles; ++c)
    for (int i = 0; i < per_request; ++i)
      goals.push_back(DrawnGoal{c, grid.cell(reachable[static_cast<std::size_t>(rng() % n)])});
  return goals;
}

}  // namespace mission
}  // namespace gather
