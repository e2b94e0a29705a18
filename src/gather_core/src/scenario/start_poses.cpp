#include "gather_core/scenario/start_poses.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include "gather_core/error.hpp"

namespace gather {

std::vector<Point2> start_poses(const OccupancyGrid& grid, Point2 oc, int n, double spacing,
                                const std::vector<Point2>& taken) {
  std::vector<Point2> poses;
  const Cell start = grid.world_to_cell(oc);
  if (!grid.is_free(start)) throw Error("start poses", "the OC is not on a free cell");
  std::vector<uint8_t> seen(grid.size(), 0);
  std::deque<std::size_t> queue{grid.index(start)};
  seen[grid.index(start)] = 1;
  const double min_d2 = spacing * spacing;
  auto apart = [&](Point2 p, const std::vector<Point2>& others) {
    return std::none_of(others.begin(), others.end(), [&](const Point2& q) {
      return (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y) < min_d2;
    });
  };
  auto far_enough = [&](Point2 p) {
    return std::hypot(p.x - oc.x, p.y - oc.y) >= spacing && apart(p, poses) && apart(p, taken);
  };
  while (!queue.empty() && static_cast<int>(poses.size()) < n) {
    const Cell c = grid.cell(queue.front());
    queue.pop_front();
    const Point2 p = grid.cell_center(c);
    if (far_enough(p)) poses.push_back(p);
    const Cell nb[4] = {{c.row, c.col - 1}, {c.row, c.col + 1}, {c.row - 1, c.col}, {c.row + 1, c.col}};
    for (Cell m : nb) {
      if (grid.is_free(m) && !seen[grid.index(m)]) {
        seen[grid.index(m)] = 1;
        queue.push_back(grid.index(m));
      }
    }
  }
  if (static_cast<int>(poses.size()) < n)
    throw Error("start poses", "the free space reachable from the OC holds only " + std::to_string(poses.size()) +
                                   " agents " + std::to_string(spacing) + " m apart, the team has " +
                                   std::to_string(n));
  return poses;
}

}  // namespace gather
