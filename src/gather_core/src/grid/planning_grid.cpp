#include "gather_core/grid/planning_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "gather_core/grid/reachability.hpp"

namespace gather {

OccupancyGrid coarsen(const OccupancyGrid& grid, int f) {
  if (f < 1) throw std::invalid_argument("coarsen: factor must be >= 1");
  if (f == 1) return grid;
  const int w = (grid.width() + f - 1) / f, h = (grid.height() + f - 1) / f;
  std::vector<int8_t> values(static_cast<std::size_t>(w) * h);
  std::vector<uint8_t> free(values.size());
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      bool occupied = false, unknown = false, all_free = true;
      int8_t top = 0;
      for (int dr = 0; dr < f; ++dr)
        for (int dc = 0; dc < f; ++dc) {
          const Cell q{r * f + dr, c * f + dc};
          if (!grid.contains(q)) {
            unknown = true, all_free = false;
            continue;
          }
          const int8_t v = grid.value(q);
          if (v < 0)
            unknown = true;
          else
            top = std::max(top, v);
          occupied = occupied || (v >= 0 && !grid.is_free(q));
          all_free = all_free && grid.is_free(q);
        }
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      values[i] = occupied ? int8_t{100} : unknown ? int8_t{-1} : top;
      free[i] = all_free ? 1 : 0;
    }
  return OccupancyGrid(w, h, grid.resolution() * f, grid.origin(), std::move(values), std::move(free));
}

namespace {

// Share of the map's reachable cells next to coarse reachable space.
double kept_share(const OccupancyGrid& grid, const Mask& reachable, std::size_t reachable_cells,
                  const OccupancyGrid& coarse, const Mask& coarse_reachable, int f) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < reachable.size(); ++i) {
    if (!reachable[i]) continue;
    const Cell c = grid.cell(i);
    const Cell b{c.row / f, c.col / f};
    bool near = false;
    for (int dr = -1; dr <= 1 && !near; ++dr)
      for (int dc = -1; dc <= 1 && !near; ++dc) {
        const Cell n{b.row + dr, b.col + dc};
        near = coarse.contains(n) && coarse_reachable[coarse.index(n)];
      }
    kept += near;
  }
  return reachable_cells ? static_cast<double>(kept) / static_cast<double>(reachable_cells) : 1.0;
}

}  // namespace

CoarseGrid coarsest_kept(const OccupancyGrid& grid, Point2 oc, const Mask& reachable, int factor, double min_kept) {
  const Cell oc_cell = grid.world_to_cell(oc);
  const std::size_t reachable_cells = static_cast<std::size_t>(std::count(reachable.begin(), reachable.end(), 1));
  auto oc_block_free = [&](int k) {  // without coarsening the whole map
    const Cell b{oc_cell.row / k * k, oc_cell.col / k * k};
    for (int dr = 0; dr < k; ++dr)
      for (int dc = 0; dc < k; ++dc)
        if (!grid.is_free(Cell{b.row + dr, b.col + dc})) return false;
    return true;
  };
  for (int f = factor; f >= 2; --f) {
    if (!oc_block_free(f)) continue;
    CoarseGrid out;
    out.grid = coarsen(grid, f);
    out.reachable = reachable_from(out.grid, out.grid.world_to_cell(oc));
    out.kept = kept_share(grid, reachable, reachable_cells, out.grid, out.reachable, f);
    if (out.kept >= min_kept) {
      out.factor = f;
      return out;
    }
  }
  return CoarseGrid{};
}

PlanningGrid choose_planning_grid(const OccupancyGrid& grid, Point2 oc, std::size_t max_cells, double min_kept) {
  PlanningGrid best;
  if (max_cells == 0 || grid.size() <= max_cells) return best;
  // The smallest f whose blocks (counting those that stick out) fit the limit.
  int f = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(grid.size()) / static_cast<double>(max_cells))));
  auto blocks = [&](int k) {
    return static_cast<std::size_t>((grid.width() + k - 1) / k) * static_cast<std::size_t>((grid.height() + k - 1) / k);
  };
  while (blocks(f) > max_cells) ++f;
  const CoarseGrid c = coarsest_kept(grid, oc, reachable_from(grid, grid.world_to_cell(oc)), f, min_kept);
  if (c.factor > 1) best.factor = c.factor, best.kept = c.kept;
  return best;
}

}  // namespace gather
