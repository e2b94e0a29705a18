#include "gather_core/mission/world.hpp"

#include <algorithm>
#include <cmath>

#include "gather_core/error.hpp"
#include "gather_core/grid/clearance.hpp"
#include "gather_core/grid/reachability.hpp"
#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace mission {

World::World(const Scenario& s) : scenario(s), coverage_field(s.grid) {
  const OccupancyGrid& grid = s.grid;
  oc_cell = grid.world_to_cell(s.oc);
  reachable = reachable_from(grid, oc_cell);
  reachable_cells = static_cast<std::size_t>(std::count(reachable.begin(), reachable.end(), 1));
  reachable_area = reachable_cells * grid.cell_area();
  if (reachable_cells == 0) throw Error(s.path, "no free space is reachable from the OC");
  const RadioModel radio(grid, s.radio);
  coverage = radio.coverage(s.oc);
  for (std::size_t i = 0; i < coverage.size(); ++i) coverage[i] = coverage[i] && reachable[i];
  coverage[grid.index(oc_cell)] = 1;
  // The way back into the coverage: one labelled march from its border cells.
  std::vector<fmm::Source> sources;
  const int w = grid.width(), h = grid.height();
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      if (!coverage[i]) continue;
      const bool border = (c == 0 || !coverage[i - 1]) || (c + 1 == w || !coverage[i + 1]) ||
                          (r == 0 || !coverage[i - static_cast<std::size_t>(w)]) ||
                          (r + 1 == h || !coverage[i + static_cast<std::size_t>(w)]);
      if (!border) continue;
      coverage_border.push_back(Cell{r, c});
      sources.push_back(fmm::Source::at_cell(Cell{r, c}));
    }
  fmm::SolveOptions so;
  so.labels = true;
  so.label_look_back = 0;
  coverage_field.solve(sources, so);
}

Cell World::standing_cell(Point2 p, double radius_m) const {
  const OccupancyGrid& grid = scenario.grid;
  const Cell c = grid.world_to_cell(p);
  if (reaches(c)) return c;
  // Square rings of cells around c, growing: in the first ring that holds a
  // reachable cell, the one nearest c (ties: the first in row-major order).
  const int rings = static_cast<int>(std::ceil(radius_m / grid.resolution()));
  for (int k = 1; k <= rings; ++k) {
    Cell best{-1, -1};
    long best_d = -1;
    for (int dr = -k; dr <= k; ++dr)
      for (int dc = -k; dc <= k; ++dc) {
        if (std::max(std::abs(dr), std::abs(dc)) != k) continue;
        const Cell n{c.row + dr, c.col + dc};
        const long d = static_cast<long>(dr) * dr + static_cast<long>(dc) * dc;
        if (reaches(n) && (best_d < 0 || d < best_d)) best = n, best_d = d;
      }
    if (best_d >= 0) return best;
  }
  return c;
}

Cell World::roomy_near(Cell from, double clearance) const {
  const OccupancyGrid& grid = scenario.grid;
  if (!covered(from)) return from;
  const ClearanceMap room(grid);
  // Breadth-first through the coverage, 8-connected, in a fixed order.
  std::vector<uint8_t> seen(grid.size(), 0);
  std::vector<Cell> queue{from};
  seen[grid.index(from)] = 1;
  for (std::size_t i = 0; i < queue.size(); ++i) {
    const Cell c = queue[i];
    if (room.at(c) >= clearance) return c;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const Cell n{c.row + dr, c.col + dc};
        if ((dr == 0 && dc == 0) || !covered(n) || seen[grid.index(n)]) continue;
        seen[grid.index(n)] = 1;
        queue.push_back(n);
      }
  }
  return from;
}

Cell World::oc_worker_home(const std::vector<Cell>& cells) const {
  double best = fmm::kUnreached;
  Cell from{-1, -1};
  for (Cell c : cells) {
    const double d = covered(c) ? 0.0 : coverage_field.time(c);
    if (d < best) best = d, from = c;
  }
  if (!(best < fmm::kUnreached)) return Cell{-1, -1};
  if (covered(from)) return from;
  const int label = coverage_field.label(from);
  return label < 0 ? Cell{-1, -1} : coverage_border[static_cast<std::size_t>(label)];
}

}  // namespace mission
}  // namespace gather
