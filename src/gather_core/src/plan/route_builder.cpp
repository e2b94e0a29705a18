#include "gather_core/plan/route_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "gather_core/error.hpp"
#include "gather_core/fmm/path.hpp"
#include "gather_core/mission/tour.hpp"
#include "gather_core/numeric.hpp"
#include "gather_core/path/path_polisher.hpp"
#include "gather_core/radio/radio_model.hpp"
#include "gather_core/radix_queue.hpp"

namespace gather {
namespace plan {
namespace {

// A*'s cost and parent per cell, kept between searches: a search touches
// the cells around its leg only, and wiping grid-sized arrays for each leg
// cost more than the search (a cell counts only once stamped with the
// search's generation). One per thread (the sweep plans configurations in
// parallel).
struct AStarWork {
  struct Node {
    float g;
    uint32_t parent, stamp;
  };
  std::vector<Node> node;  // one cache line for what a step reads of a cell
  uint32_t generation = 0;
  // The open list: keys of (f, cell) (order_key), popped in the order of
  // (f, cell), ties by cell, from a radix heap: the heuristics are
  // consistent, so a search takes keys in ascending order (but for rounding).
  RadixQueue open;

  void begin(std::size_t cells) {
    if (node.size() != cells) node.assign(cells, Node{0.0f, 0, 0}), generation = 0;
    if (++generation == 0) {
      for (Node& n : node) n.stamp = 0;
      generation = 1;
    }
    open.clear();
  }
  float cost(std::size_t i) const {
    return node[i].stamp == generation ? node[i].g : std::numeric_limits<float>::infinity();
  }
  void set(std::size_t i, float cost, uint32_t from) { node[i] = Node{cost, from, generation}; }
  uint32_t parent(std::size_t i) const { return node[i].parent; }
};

// The 8-connected search on the route speed map (no diagonal step past a
// blocked corner) from `start` until `goal` is popped (or, with no goal,
// every reachable cell is final), ordered by cost + h(cell, row, col): A*
// with a consistent `h`, Dijkstra with h = 0. The costs and parents are
// left in `work`.
// `popped` (optional): counts the cells popped.
template <class Heuristic>
void search(const PlanContext& ctx, std::size_t start, std::size_t goal, AStarWork& work, Heuristic h,
            std::size_t* popped = nullptr) {
  const OccupancyGrid& grid = ctx.scenario.grid;
  const int w = grid.width(), rows = grid.height();
  work.begin(grid.size());
  work.set(start, 0.0f, 0);
  {
    const Cell s = grid.cell(start);
    work.open.push(order_key(h(start, s.row, s.col), static_cast<uint32_t>(start)));
  }
  static const int dr[8] = {0, 0, 1, -1, 1, 1, -1, -1}, dc[8] = {1, -1, 0, 0, 1, -1, 1, -1};
  std::ptrdiff_t offset[8];
  for (int k = 0; k < 8; ++k) offset[k] = static_cast<std::ptrdiff_t>(dr[k]) * w + dc[k];
  // The speed map holds 1 (roomy), tight_speed (reachable, not roomy) and
  // 0 (off the reachable space): read from the two masks (a byte a cell,
  // not the map's 8), each step's cost worked out once per kind of step
  // and pair of speeds, as the map's 1 / speed gave it.
  const uint8_t* reach = ctx.reachable.data();
  const uint8_t* roomy = ctx.roomy.data();
  const double pace[2] = {1.0 / ctx.tight_speed, 1.0};  // [roomy]
  float step_cost[2][2][2];                             // [diagonal][roomy from][roomy to]
  for (int d = 0; d < 2; ++d)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        step_cost[d][a][b] = static_cast<float>((d ? std::sqrt(2.0) : 1.0) * 0.5 * (pace[a] + pace[b]));
  while (!work.open.empty()) {
    const uint64_t e = work.open.pop();
    const float f = order_key_time(e);
    const auto i = static_cast<uint32_t>(e);
    if (i == goal) break;
    const int r = static_cast<int>(i / static_cast<uint32_t>(w)), c = static_cast<int>(i % static_cast<uint32_t>(w));
    const float gi = work.cost(i);
    if (f > gi + h(i, r, c) + 1e-4f) continue;  // stale entry
    if (popped) ++*popped;
    if (!reach[i]) continue;  // a start off the reachable space: no step out of it (the speed map's 0)
    const bool inner = r > 0 && c > 0 && r + 1 < rows && c + 1 < w;  // all 8 neighbours on the map
    const int roomy_i = roomy[i] != 0 ? 1 : 0;
    const auto at = static_cast<std::ptrdiff_t>(i);
    for (int k = 0; k < 8; ++k) {
      const int nr = r + dr[k], nc = c + dc[k];
      if (!inner && (nr < 0 || nc < 0 || nr >= rows || nc >= w)) continue;
      const auto j = static_cast<std::size_t>(at + offset[k]);
      if (!reach[j]) continue;
      const int diagonal = k >= 4 ? 1 : 0;
      // Past a corner: the cells beside the step (nr, c) and (r, nc).
      if (diagonal &&
          (!reach[static_cast<std::size_t>(at + offset[k] - dc[k])] || !reach[static_cast<std::size_t>(at + dc[k])]))
        continue;
      const float step = step_cost[diagonal][roomy_i][roomy[j] != 0 ? 1 : 0];
      if (gi + step < work.cost(j)) {
        work.set(j, gi + step, i);
        work.open.push(order_key(gi + step + h(j, nr, nc), static_cast<uint32_t>(j)));
      }
    }
  }
}

// The landmarks' costs (LegLandmarks), searched once: from the OC's cell,
// then from the cell farthest (by the least of the costs so far) from the
// landmarks before.
const LegLandmarks& landmarks(const PlanContext& ctx) {
  LegLandmarks& lm = *ctx.leg_landmarks;
  std::call_once(lm.once, [&]() {
    const OccupancyGrid& grid = ctx.scenario.grid;
    const std::size_t n = grid.size();
    constexpr auto kL = static_cast<std::size_t>(LegLandmarks::kCount);
    lm.cost.assign(n * kL, std::numeric_limits<float>::infinity());
    std::vector<float> nearest(n, std::numeric_limits<float>::infinity());  // least cost from the landmarks so far
    AStarWork work;
    std::size_t next = grid.index(ctx.oc_cell);
    for (std::size_t l = 0; l < kL; ++l) {
      search(ctx, next, static_cast<std::size_t>(-1), work, [](std::size_t, int, int) { return 0.0f; });
      float farthest = -1.0f;
      for (std::size_t i = 0; i < n; ++i) {
        const float d = work.cost(i);
        lm.cost[i * kL + l] = d;
        nearest[i] = std::min(nearest[i], d);
        if (nearest[i] < std::numeric_limits<float>::infinity() && nearest[i] > farthest)
          farthest = nearest[i], next = i;
      }
    }
  });
  return lm;
}

// The A* of a leg from cell `start` to cell `goal` into `work`, with the
// landmarks' bound or (`landmarks` false) the octile distance alone.
void leg_search(const PlanContext& ctx, std::size_t start, std::size_t goal, bool landmarks_on, AStarWork& work,
                std::size_t* popped = nullptr) {
  const Cell cb = ctx.scenario.grid.cell(goal);
  auto octile = [&](std::size_t, int r, int c) {
    const double dx = std::abs(c - cb.col), dy = std::abs(r - cb.row);
    return static_cast<float>(std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy));  // at speed 1
  };
  if (!landmarks_on) return search(ctx, start, goal, work, octile, popped);
  const LegLandmarks& lm = landmarks(ctx);
  constexpr auto kL = static_cast<std::size_t>(LegLandmarks::kCount);
  const float* to_goal = lm.cost.data() + goal * kL;
  const float* cost = lm.cost.data();
  search(
      ctx, start, goal, work,
      [&](std::size_t i, int r, int c) {
        float best = octile(i, r, c);
        const float* at = cost + i * kL;
        for (std::size_t l = 0; l < kL; ++l) {
          const float d = std::abs(at[l] - to_goal[l]);  // NaN if a landmark reaches neither, +inf if one
          if (d > best && d < std::numeric_limits<float>::infinity()) best = d;
        }
        return best;
      },
      popped);
}

// Shortest 8-connected path a -> b [m] on the route speed map by A*, its
// heuristic the octile distance (at speed 1), or the larger of it and the
// landmarks' bound (PlanContext::use_leg_landmarks). A leg between two meeting areas is short, and A*
// explores only around it, where an FMM march without a heuristic would
// flood a disc of the leg's length. Returns cell centres from a's cell to
// b's cell; empty if b cannot be reached.
std::vector<Point2> astar_leg(const PlanContext& ctx, Point2 a, Point2 b) {
  const OccupancyGrid& grid = ctx.scenario.grid;
  const std::size_t start = grid.index(grid.world_to_cell(a)), goal = grid.index(grid.world_to_cell(b));
  const std::pair<std::size_t, std::size_t> key{start, goal};
  LegPaths& kept = *ctx.leg_paths;
  std::vector<uint32_t> cells;
  bool found = false;
  {
    const std::lock_guard<std::mutex> lock(kept.mutex);
    const auto it = kept.cells.find(key);
    if (it != kept.cells.end()) cells = it->second, found = true;
  }
  if (!found) {
    thread_local AStarWork work;
    leg_search(ctx, start, goal, ctx.use_leg_landmarks, work);
    if (std::isfinite(work.cost(goal)))
      for (std::size_t i = goal;; i = work.parent(i)) {
        cells.push_back(static_cast<uint32_t>(i));
        if (i == start) break;
      }
    std::reverse(cells.begin(), cells.end());
    // The cells and, about, the map's node and the allocator's headers.
    const std::size_t bytes = cells.size() * sizeof(uint32_t) + 128;
    const std::lock_guard<std::mutex> lock(kept.mutex);
    ++kept.searched;
    if (kept.bytes + bytes <= LegPaths::kBytes && kept.cells.emplace(key, cells).second) kept.bytes += bytes;
  }
  std::vector<Point2> path;
  if (cells.empty()) return path;
  path.reserve(cells.size());
  for (uint32_t i : cells) path.push_back(grid.cell_center(grid.cell(i)));
  path.front() = a;
  path.back() = b;
  return path;
}

}  // namespace

double leg_search_cost(const PlanContext& ctx, Point2 a, Point2 b, bool landmarks_on, std::size_t* popped) {
  const OccupancyGrid& grid = ctx.scenario.grid;
  const Cell ca = grid.world_to_cell(a), cb = grid.world_to_cell(b);
  if (!grid.contains(ca) || !grid.contains(cb)) return kInf;
  AStarWork work;
  const std::size_t goal = grid.index(cb);
  leg_search(ctx, grid.index(ca), goal, landmarks_on, work, popped);
  const float c = work.cost(goal);
  return c < std::numeric_limits<float>::infinity() ? static_cast<double>(c) : kInf;
}

// Builds the closed route of one collector through the entry cells of its
// segments: geodesic legs from FMM, visiting order by mission::order_closed_tour,
// polished with OMPL.
CollectorRoute build_route(const PlanContext& ctx, fmm::FastMarching& fm, const WorkerGraph& graph,
                           const LabelImage& labels, const std::vector<SegmentId>& segments, CollectorId collector,
                           const PlannerOptions& opt, LegCache* legs) {
  const Scenario& s = ctx.scenario;
  const OccupancyGrid& grid = s.grid;
  CollectorRoute route;
  route.collector = collector;
  if (segments.empty()) {  // more collectors than segments to serve: this one stays at the OC
    route.waypoints = {s.oc};
    return route;
  }
  // The stops (the OC first) and their cells, the key of their legs (the OC: kOcStop).
  std::vector<Point2> pts{s.oc};
  std::vector<std::size_t> stop_cell{LegCache::kOcStop};
  for (SegmentId k : segments) {
    pts.push_back(grid.cell_center(graph.segment(k).entry));
    stop_cell.push_back(grid.index(graph.segment(k).entry));
  }
  const std::size_t n = pts.size();
  // Visiting order on straight-line distances (cheap, and the legs between
  // consecutive stops are short, so each leg's march stops early).
  std::vector<double> d(n * n, 0.0);  // row-major, point 0 = the OC
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) d[i * n + j] = distance(pts[i], pts[j]);
  const std::vector<int> order = mission::order_closed_tour(mission::TourDistances{d.data(), d.data(), n},
                                                            static_cast<int>(n) - 1, opt.exact_route_stops);
  std::vector<int> stops{0};
  stops.insert(stops.end(), order.begin(), order.end());
  stops.push_back(0);
  PolishOptions po;
  po.robot_radius = s.team.radius;
  po.smoothing_passes = static_cast<unsigned>(std::max(0, opt.smoothing_passes));
  route.waypoints = {pts[0]};
  route.min_clearance = kInf;
  fmm::SolveOptions so;
  so.labels = false;
  std::vector<std::size_t> leg_end;  // the waypoint each leg ends at
  for (std::size_t t = 0; t + 1 < stops.size(); ++t) {
    const auto from = static_cast<std::size_t>(stops[t]), to = static_cast<std::size_t>(stops[t + 1]);
    const std::pair<std::size_t, std::size_t> key{stop_cell[from], stop_cell[to]};
    const PolishedPath* polished = nullptr;
    PolishedPath built;
    if (legs) {
      const auto it = legs->legs.find(key);
      if (it != legs->legs.end()) polished = &it->second;
    }
    if (!polished) {
      const Point2 a = pts[from], b = pts[to];
      std::vector<Point2> leg;
      if (to == 0) {  // back to the OC: down the OC's own field
        leg = fmm::descend(ctx.oc_field, a);
      } else if (from == 0) {  // out of the OC: the same, reversed
        leg = fmm::descend(ctx.oc_field, b);
        std::reverse(leg.begin(), leg.end());
      } else {  // between two meeting areas: A* (a march from b as the fallback)
        leg = astar_leg(ctx, a, b);
        if (leg.empty()) {
          so.targets.assign(1, grid.world_to_cell(a));
          fm.solve({fmm::Source::at_point(b)}, so);
          leg = fmm::descend(fm, a);
        }
      }
      // Each leg is polished on its own, so the route goes through every
      // meeting area exactly (and shortcuts never jump across the loop).
      built = polish_path(leg, ctx.clearance, po);
      polished = legs ? &legs->legs.emplace(key, std::move(built)).first->second : &built;
    }
    route.waypoints.insert(route.waypoints.end(), polished->points.begin() + 1, polished->points.end());
    leg_end.push_back(route.waypoints.size() - 1);
    route.length += polished->length;
    route.min_clearance = std::min(route.min_clearance, polished->min_clearance);
  }
  route.period = route.length / s.team.speed;

  // Arc length of every waypoint, then each meeting area at the route point
  // nearest to its segment's entry cell, in visiting order.
  route.arcs = fmm::path_arcs(route.waypoints);
  const std::vector<double>& arc = route.arcs;
  // The nearest route point past the meeting before: the route goes through
  // each stop at the end of its leg, so the search ends there once it found
  // the stop itself (nothing after it can be nearer by the 1e-9 m a point
  // must win by); else it goes on to the route's end.
  double from_m = 0.0;
  std::size_t first = 0;
  for (std::size_t t = 0; t < order.size(); ++t) {
    const int stop = order[t];
    const SegmentId seg = segments[static_cast<std::size_t>(stop - 1)];
    const Point2 target = pts[static_cast<std::size_t>(stop)];
    MeetingArea m;
    m.segment = seg;
    double best = kInf;
    while (first + 1 < route.waypoints.size() && arc[first + 1] < from_m) ++first;
    auto nearest_on = [&](std::size_t i) {
      // Nearest point on segment i..i+1.
      const Point2 a = route.waypoints[i], b = route.waypoints[i + 1];
      double u = 0.0;
      const Point2 p = nearest_on_piece(target, a, b, &u);
      const double e = distance(p, target);
      if (e < best - 1e-9)
        best = e, m.point = p, m.arc_m = arc[i] + u * std::sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
    };
    std::size_t i = first;
    for (; i < leg_end[t] && i + 1 < route.waypoints.size(); ++i) nearest_on(i);
    if (best >= 1e-9)
      for (; i + 1 < route.waypoints.size(); ++i)
        if (arc[i + 1] >= from_m) nearest_on(i);
    from_m = m.arc_m;
    route.meetings.push_back(m);
    route.segments.push_back(seg);
  }
  // Passes: stretches of the route within PlannerOptions::pass_radius_m of a
  // served segment's cells, sampled every pass_step_m; each stretch counts
  // once, at its middle.
  {
    const int rc = std::max(1, static_cast<int>(std::ceil(opt.pass_radius_m / grid.resolution())));
    // The disc is probed every ~pass_probe_m, not every cell.
    const int stride = std::max(1, static_cast<int>(std::lround(opt.pass_probe_m / grid.resolution())));
    // Offsets are multiples of the stride, so the centre cell is always probed
    // (a radius under the stride probes the centre alone).
    const int from = -(rc / stride) * stride;
    const double step = opt.pass_step_m;
    // Position in `segments` and in route.meetings of each served segment.
    PerSegment<int> index_of(graph.segments.count(), -1), meeting_of(graph.segments.count(), -1);
    for (std::size_t i = 0; i < segments.size(); ++i) index_of[segments[i]] = static_cast<int>(i);
    for (std::size_t i = 0; i < route.segments.size(); ++i) meeting_of[route.segments[i]] = static_cast<int>(i);
    auto seg_index = [&](int32_t label) { return label > 0 ? index_of[SegmentId(label)] : -1; };
    // Per sample only the segments next to it and those whose stretch is
    // open are looked at (a long route serves many segments).
    std::vector<double> open_since(segments.size(), -1.0);
    std::vector<uint8_t> near(segments.size(), 0);
    std::vector<int> near_now, open_now, still_open;
    auto close = [&](int k, double at) {
      route.meetings[static_cast<std::size_t>(meeting_of[segments[static_cast<std::size_t>(k)]])].passes.push_back(
          0.5 * (open_since[static_cast<std::size_t>(k)] + at));
      open_since[static_cast<std::size_t>(k)] = -1.0;
    };
    const double total = arc.back();
    fmm::ArcWalker walk(route.waypoints, arc);
    for (double at = 0.0;; at = std::min(total, at + step)) {
      const Point2 p = walk.at(at);
      const Cell c = grid.world_to_cell(p);
      near_now.clear();
      for (int dr = from; dr <= rc; dr += stride)
        for (int dc = from; dc <= rc; dc += stride) {
          const Cell q{c.row + dr, c.col + dc};
          if (!grid.contains(q) || dr * dr + dc * dc > rc * rc) continue;
          const int k = seg_index(labels[grid.index(q)]);
          if (k >= 0 && !near[static_cast<std::size_t>(k)])
            near[static_cast<std::size_t>(k)] = 1, near_now.push_back(k);
        }
      for (const int k : near_now)
        if (open_since[static_cast<std::size_t>(k)] < 0)
          open_since[static_cast<std::size_t>(k)] = at, open_now.push_back(k);
      // Stretches that end here: no longer near, or the route ends.
      still_open.clear();
      for (const int k : open_now)
        if (!near[static_cast<std::size_t>(k)] || at >= total)
          close(k, at);
        else
          still_open.push_back(k);
      open_now.swap(still_open);
      for (const int k : near_now) near[static_cast<std::size_t>(k)] = 0;
      if (at >= total) break;
    }
    for (MeetingArea& m : route.meetings)
      if (m.passes.empty()) m.passes.push_back(m.arc_m);  // the entry point itself
  }
  // Uploads: every point where the route comes (back) into the OC's coverage.
  bool inside = true;  // it starts at the OC
  for (std::size_t i = 0; i < route.waypoints.size(); ++i) {
    const Cell c = grid.world_to_cell(route.waypoints[i]);
    const bool in = grid.contains(c) && ctx.coverage[grid.index(c)];
    if (in && !inside) route.coverage_entries.push_back(arc[i]);
    inside = in;
  }
  if (route.coverage_entries.empty() || route.coverage_entries.back() < route.length)
    route.coverage_entries.push_back(route.length);
  return route;
}

}  // namespace plan
}  // namespace gather
