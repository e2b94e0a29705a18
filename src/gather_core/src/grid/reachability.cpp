#include "gather_core/grid/reachability.hpp"

#include <algorithm>

namespace gather {
namespace {

// Flood fill from `seed` over free cells with label 0, writing `label`.
// Returns the number of cells labelled. `stack` is reused scratch space.
std::size_t flood(const OccupancyGrid& g, std::size_t seed, uint32_t label, std::vector<uint32_t>& labels,
                  std::vector<std::size_t>& stack) {
  const auto& free = g.free_mask();
  const std::size_t w = static_cast<std::size_t>(g.width());
  const std::size_t n = g.size();
  std::size_t count = 0;
  stack.clear();
  stack.push_back(seed);
  labels[seed] = label;
  while (!stack.empty()) {
    const std::size_t i = stack.back();
    stack.pop_back();
    ++count;
    const std::size_t col = i % w;
    const std::size_t nb[4] = {col > 0 ? i - 1 : n, col + 1 < w ? i + 1 : n, i >= w ? i - w : n, i + w < n ? i + w : n};
    for (std::size_t j : nb) {
      if (j < n && free[j] && labels[j] == 0) {
        labels[j] = label;
        stack.push_back(j);
      }
    }
  }
  return count;
}

}  // namespace

Mask reachable_from(const OccupancyGrid& grid, Cell start) {
  Mask mask(grid.frame(), 0);
  if (!grid.is_free(start)) return mask;
  std::vector<uint32_t> labels(grid.size(), 0);
  std::vector<std::size_t> stack;
  flood(grid, grid.index(start), 1, labels, stack);
  std::transform(labels.begin(), labels.end(), mask.begin(), [](uint32_t l) { return l ? 1 : 0; });
  return mask;
}

FreeSpaceSummary summarize_free_space(const OccupancyGrid& grid, Cell start) {
  FreeSpaceSummary s;
  std::vector<uint32_t> labels(grid.size(), 0);
  std::vector<std::size_t> stack;
  const auto& free = grid.free_mask();
  if (grid.is_free(start)) s.reachable_cells = flood(grid, grid.index(start), 1, labels, stack);
  uint32_t next = 2;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!free[i]) continue;
    ++s.free_cells;
    if (labels[i] != 0) continue;
    const std::size_t size = flood(grid, i, next++, labels, stack);
    ++s.other_components;
    s.largest_other_cells = std::max(s.largest_other_cells, size);
  }
  return s;
}

}  // namespace gather
