#include "gather_core/mission/world.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "gather_core/error.hpp"
#include "gather_core/grid/clearance.hpp"
#include "gather_core/grid/reachability.hpp"
#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace mission {

namespace {
// [m] a home keeps this much beyond two robot radii off a lane (a robot
// driving down the middle of it passes one parked there).
constexpr double kLaneHalf = 0.3;
}  // namespace

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

std::vector<Cell> World::oc_worker_homes(const std::vector<std::vector<Cell>>& segments, double clearance) const {
  const OccupancyGrid& grid = scenario.grid;
  std::vector<Cell> homes;
  homes.reserve(segments.size());
  if (!(clearance > 0)) {
    for (const std::vector<Cell>& cells : segments) homes.push_back(oc_worker_home(cells));
    return homes;
  }
  // Room inside the coverage: to the nearest wall or cell out of touch with
  // the OC (a robot that stops near its home, or steps aside there, stays
  // in touch). Computed on the coverage's bounding box (ClearanceMap counts
  // the box's edge as out, as every cell beyond it is): an agent on a robot
  // keeps to its memory budget.
  int r0 = grid.height(), r1 = -1, c0 = grid.width(), c1 = -1;
  for (std::size_t i = 0; i < coverage.size(); ++i)
    if (coverage[i]) {
      const Cell c = grid.cell(i);
      r0 = std::min(r0, c.row), r1 = std::max(r1, c.row), c0 = std::min(c0, c.col), c1 = std::max(c1, c.col);
    }
  const int bw = std::max(0, c1 - c0 + 1), bh = std::max(0, r1 - r0 + 1);
  std::vector<int8_t> values(static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh), 100);
  std::vector<uint8_t> open(values.size(), 0);
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      if (covered(Cell{r, c})) {
        const std::size_t k =
            static_cast<std::size_t>(r - r0) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(c - c0);
        values[k] = 0, open[k] = 1;
      }
  const OccupancyGrid box(bw, bh, grid.resolution(), grid.origin(), std::move(values), std::move(open));
  const ClearanceMap box_room(box);
  auto room_at = [&](Cell q) { return covered(q) ? box_room.at(Cell{q.row - r0, q.col - c0}) : 0.0; };
  auto clear_of_others = [&](Cell c, double apart) {
    const Point2 p = grid.cell_center(c);
    for (Cell h : homes) {
      if (h.row < 0) continue;
      const Point2 q = grid.cell_center(h);
      if (std::hypot(p.x - q.x, p.y - q.y) < apart) return false;
    }
    return true;
  };
  // The lanes: the way from each exit the workers take out of the coverage
  // (a plain home on its border) to the OC, through the middle of the
  // passages (a shortest way that pays for want of room between walls),
  // where it is narrow (less than `clearance` to the nearest wall: a
  // corridor, a tunnel, a door). A robot parked on one stands in
  // the way of every robot of that side; homes keep kLaneHalf + two radii
  // off them where they can.
  const double res = grid.resolution();
  const std::size_t bn = static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh);
  auto box_index = [&](Cell q) {
    return static_cast<std::size_t>(q.row - r0) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(q.col - c0);
  };
  auto on_border = [&](Cell q) {
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc)
        if (std::abs(dr) + std::abs(dc) == 1 && !covered(Cell{q.row + dr, q.col + dc})) return true;
    return false;
  };
  std::vector<Cell> plains;
  plains.reserve(segments.size());
  for (const std::vector<Cell>& cells : segments) plains.push_back(oc_worker_home(cells));
  std::vector<uint8_t> lane(bn, 0);
  if (covered(oc_cell)) {
    // Room between walls (the coverage's edge aside: it stops no robot), on
    // the box widened by `clearance` (off the map counts as wall).
    const int m = static_cast<int>(std::ceil(clearance / grid.resolution())) + 1;
    const int ww = bw + 2 * m, wh = bh + 2 * m;
    std::vector<int8_t> wall_values(static_cast<std::size_t>(ww) * static_cast<std::size_t>(wh), 100);
    std::vector<uint8_t> wall_open(wall_values.size(), 0);
    for (int r = r0 - m; r <= r1 + m; ++r)
      for (int c = c0 - m; c <= c1 + m; ++c)
        if (grid.contains(Cell{r, c}) && grid.free_mask()[grid.index(Cell{r, c})]) {
          const std::size_t k = static_cast<std::size_t>(r - r0 + m) * static_cast<std::size_t>(ww) +
                                static_cast<std::size_t>(c - c0 + m);
          wall_values[k] = 0, wall_open[k] = 1;
        }
    const OccupancyGrid wall_box(ww, wh, grid.resolution(), grid.origin(), std::move(wall_values),
                                 std::move(wall_open));
    const ClearanceMap wall_room(wall_box);
    auto width_at = [&](Cell q) { return wall_room.at(Cell{q.row - r0 + m, q.col - c0 + m}); };
    std::vector<double> cost(bn, std::numeric_limits<double>::infinity());
    std::vector<uint32_t> parent(bn, 0);
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open_set;
    cost[box_index(oc_cell)] = 0.0;
    open_set.push({0.0, static_cast<uint32_t>(box_index(oc_cell))});
    while (!open_set.empty()) {
      const auto [d, k] = open_set.top();
      open_set.pop();
      if (d > cost[k]) continue;
      const Cell q{r0 + static_cast<int>(k / static_cast<std::size_t>(bw)),
                   c0 + static_cast<int>(k % static_cast<std::size_t>(bw))};
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const Cell n{q.row + dr, q.col + dc};
          if ((dr == 0 && dc == 0) || !covered(n)) continue;
          const std::size_t j = box_index(n);
          const double step = (dr != 0 && dc != 0 ? std::sqrt(2.0) : 1.0) * res;
          const double nd = d + step * clearance / std::max(width_at(n), 2 * res);
          if (nd < cost[j])
            cost[j] = nd, parent[j] = static_cast<uint32_t>(k), open_set.push({nd, static_cast<uint32_t>(j)});
        }
    }
    const double half = kLaneHalf + 2 * scenario.team.radius;
    const int reach = static_cast<int>(std::ceil(half / res));
    const long reach2 = static_cast<long>(std::floor(half * half / (res * res) + 1e-9));  // exact in cells
    const std::size_t oc_k = box_index(oc_cell);
    std::vector<uint8_t> traced(bn, 0);
    for (Cell p : plains) {
      if (p.row < 0 || !on_border(p)) continue;
      for (std::size_t k = box_index(p); !traced[k] && std::isfinite(cost[k]); k = parent[k]) {
        traced[k] = 1;
        const Cell q{r0 + static_cast<int>(k / static_cast<std::size_t>(bw)),
                     c0 + static_cast<int>(k % static_cast<std::size_t>(bw))};
        if (width_at(q) < clearance)
          for (int dr = -reach; dr <= reach; ++dr)
            for (int dc = -reach; dc <= reach; ++dc) {
              const Cell n{q.row + dr, q.col + dc};
              if (covered(n) && static_cast<long>(dr) * dr + static_cast<long>(dc) * dc <= reach2)
                lane[box_index(n)] = 1;
            }
        if (k == oc_k) break;  // the OC: the way's end (it has no parent)
      }
    }
  }
  auto in_lane = [&](Cell q) { return covered(q) && lane[box_index(q)] != 0; };
  // Less room, and closer to the others, where the coverage is crowded:
  // the room halves (and the spacing with it) down to two cells. One
  // breadth-first search a worker, from its plain home through the free
  // space reachable from the OC (past a pocket of coverage, 8-connected, a
  // fixed order): the nearest cell of each level off the lanes, the
  // roomiest level that has one; where none is off the lanes, on them.
  std::vector<double> levels;
  for (double c = clearance; c >= 2 * grid.resolution(); c *= 0.5) levels.push_back(c);
  std::vector<uint8_t> seen(grid.size());
  std::vector<uint32_t> queue;  // grid indices
  std::vector<Cell> found;
  auto search = [&](Cell plain, bool off_lanes) {
    found.assign(levels.size(), Cell{-1, -1});
    if (plain.row < 0 || levels.empty()) return;
    std::fill(seen.begin(), seen.end(), 0);
    queue.assign(1, static_cast<uint32_t>(grid.index(plain)));
    seen[grid.index(plain)] = 1;
    for (std::size_t i = 0; i < queue.size() && found[0].row < 0; ++i) {
      const Cell q = grid.cell(queue[i]);
      const double r = room_at(q);
      if (!off_lanes || !in_lane(q))
        for (std::size_t k = 0; k < levels.size(); ++k)  // roomiest first
          if (r >= levels[k] && found[k].row < 0 && clear_of_others(q, 2 * levels[k])) found[k] = q;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const Cell n{q.row + dr, q.col + dc};
          if ((dr == 0 && dc == 0) || !reaches(n) || seen[grid.index(n)]) continue;
          seen[grid.index(n)] = 1;
          queue.push_back(static_cast<uint32_t>(grid.index(n)));
        }
    }
  };
  for (Cell plain : plains) {
    search(plain, true);
    auto best = std::find_if(found.begin(), found.end(), [](Cell c) { return c.row >= 0; });
    if (best == found.end()) {
      search(plain, false);
      best = std::find_if(found.begin(), found.end(), [](Cell c) { return c.row >= 0; });
    }
    homes.push_back(best != found.end() ? *best : plain);
  }
  return homes;
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
