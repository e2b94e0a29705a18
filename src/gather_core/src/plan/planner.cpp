#include "gather_core/plan/planner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <thread>

#include "gather_core/error.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/fmm/path.hpp"
#include "gather_core/grid/reachability.hpp"
#include "gather_core/mission/segment_window.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/mission/worker_policy.hpp"
#include "gather_core/path/path_polisher.hpp"
#include "gather_core/plan/collector_groups.hpp"
#include "gather_core/plan/loop_schedule.hpp"
#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace plan {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Expected length [m] of a tour from a depot through n random goals of a
// region and back to where the data is delivered, whose cells lie at mean
// distance `out` [m] from the depot and `back` [m] from the delivery place:
// L(n) = out + back + c S (n - 1) / sqrt(n) for n >= 1. One goal costs the
// trip out and back; a second adds about the mean distance between two
// random points (0.5214 sqrt(A) in an open square of area A; the formula
// gives 0.50 sqrt(A)); for many goals it tends to the
// Beardwood-Halton-Hammersley law c sqrt(n A). S is the region's effective
// side: sqrt(A) for an open square, and in general its measured mean
// walking distance between two cells over 0.5214, so that walls and doors
// (rooms of one segment joined through a corridor) lengthen the walks
// between goals as they do on the map. (BHH alone, with the Euclidean side,
// assumes a central depot, open space and many goals: with 1-3 goals per
// segment and the depot at the segment's edge it came out ~40% short of the
// simulated tours; with the Euclidean side and one mean distance for both
// legs, ~10% short of the simulated latency.) Fractional n < 1 scales the
// trip out and back.
struct TourModel {
  double area = 0.0;  // [m^2]
  double side = 0.0;  // [m] effective side S
  double out = 0.0;   // [m] mean distance from the depot to the region's cells
  double back = 0.0;  // [m] mean distance from the region's cells to the delivery place
  double c = 0.7124;
  // Quantiles of the distance from the depot to the region's cells
  // (WorkerSegment::home_quantiles; empty: unknown).
  std::vector<double> out_quantiles;
  double trip() const { return out + back; }
  // The share F(d) of the region's cells within `d` [m] of the depot, from
  // the quantiles (linear between them); without quantiles, d / out up to 1.
  double within(double d) const {
    const std::size_t n = out_quantiles.size();
    if (n < 2) return out > 0 ? std::clamp(d / out, 0.0, 1.0) : 1.0;
    if (d < out_quantiles.front()) return 0.0;
    if (d >= out_quantiles.back()) return 1.0;
    const std::size_t i = static_cast<std::size_t>(
        std::upper_bound(out_quantiles.begin(), out_quantiles.end(), d) - out_quantiles.begin() - 1);
    const double lo = out_quantiles[i], hi = out_quantiles[i + 1];
    return (static_cast<double>(i) + (hi > lo ? (d - lo) / (hi - lo) : 1.0)) / static_cast<double>(n - 1);
  }
  double length(double n) const {
    if (n <= 0) return 0.0;
    if (n < 1) return trip() * n;
    return trip() + c * side * (n - 1.0) / std::sqrt(n);
  }
  // Of a tour through k goals, the number it measures within `budget` [m]
  // of leaving the depot: the first, when any of the k lies within reach
  // (probability 1 - (1 - F)^k, F = within(budget)), then one every
  // c S / sqrt(k) of the budget left past the mean distance `out` (the
  // goals lie that far apart along the tour, so with many goals and little
  // time the first few are reached sooner than a tour through that few
  // random goals would reach them); never more than the k F goals within
  // reach. Continuous in the budget.
  double measured(double k, double budget) const {
    if (k <= 0 || budget <= 0) return 0.0;
    const double f = within(budget), first = 1.0 - std::pow(1.0 - f, k);
    if (side <= 0) return k * f;
    return std::min(k * f, first + std::max(0.0, budget - out) * std::sqrt(k) / (c * side));
  }
  // The trip [m] that measures the first n goals of an optimal tour through
  // k goals and comes back: length(k) when n = k.
  double partial_length(double n, double k) const {
    if (n <= 0) return 0.0;
    if (n < 1 || k <= 1) return trip() * std::min(n, 1.0);
    return trip() + c * side * (n - 1.0) / std::sqrt(k);
  }
  // Largest number of goals (<= want) whose tour fits in `budget` [m].
  double goals_within(double budget, double want) const {
    if (budget <= 0) return 0.0;
    if (budget <= trip()) return std::min(want, trip() > 0 ? budget / trip() : want);
    if (side <= 0) return want;
    const double q = (budget - trip()) / (c * side);
    const double u = 0.5 * (q + std::sqrt(q * q + 4.0));  // sqrt(n): u^2 - q u - 1 = 0
    return std::clamp(u * u, 0.0, want);
  }
};

// The mean distance between two random points of an open square of side 1.
constexpr double kSquarePairDistance = 0.5214;

// An OC worker's first trip: from the OC's cell, where it starts the
// mission, instead of its home.
TourModel first_trip(const WorkerSegment& seg, TourModel m) {
  m.out = seg.mean_oc_distance;
  m.out_quantiles = seg.oc_quantiles;
  return m;
}

// The tour model of a segment's goals, from where its worker starts them:
// its home in the OC's coverage, back to the coverage (OC workers), or the
// segment's entry and back to it (workers of collectors).
TourModel tour_model(const WorkerSegment& seg, bool from_coverage, double c) {
  TourModel m;
  m.area = seg.area;
  m.side = seg.mean_pair_distance > 0 ? seg.mean_pair_distance / kSquarePairDistance : std::sqrt(seg.area);
  m.c = c;
  const double approach = seg.touches_coverage ? 0.0 : seg.coverage_distance;
  if (from_coverage) {
    m.out = seg.mean_home_distance;
    m.out_quantiles = seg.home_quantiles;
    m.back = seg.mean_coverage_distance;
  } else {
    m.out = m.back = std::max(0.0, seg.mean_coverage_distance - approach);
  }
  return m;
}

double dist(Point2 a, Point2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// Order of the meeting points (indices into `d`, 0 = the OC) of a closed tour
// from the OC: exact by dynamic programming up to 12 points, else nearest
// neighbour followed by 2-opt. `d` is a symmetric matrix of geodesic lengths.
std::vector<int> tour_order(const std::vector<std::vector<double>>& d) {
  const int n = static_cast<int>(d.size()) - 1;  // meeting points
  std::vector<int> order;
  if (n <= 0) return order;
  if (n <= 12) {
    const int full = 1 << n;
    std::vector<double> best(static_cast<std::size_t>(full) * n, kInf);
    std::vector<int> prev(best.size(), -1);
    for (int j = 0; j < n; ++j) best[(1u << j) * n + j] = d[0][j + 1];
    for (int mask = 1; mask < full; ++mask)
      for (int j = 0; j < n; ++j) {
        const double b = best[static_cast<std::size_t>(mask) * n + j];
        if (!(mask & (1 << j)) || b == kInf) continue;
        for (int k = 0; k < n; ++k) {
          if (mask & (1 << k)) continue;
          const std::size_t to = static_cast<std::size_t>(mask | (1 << k)) * n + k;
          if (b + d[j + 1][k + 1] < best[to]) best[to] = b + d[j + 1][k + 1], prev[to] = j;
        }
      }
    int last = 0;
    double total = kInf;
    for (int j = 0; j < n; ++j) {
      const double t = best[static_cast<std::size_t>(full - 1) * n + j] + d[j + 1][0];
      if (t < total) total = t, last = j;
    }
    int mask = full - 1;
    while (last >= 0) {
      order.push_back(last + 1);
      const int p = prev[static_cast<std::size_t>(mask) * n + last];
      mask &= ~(1 << last);
      last = p;
    }
    std::reverse(order.begin(), order.end());
    return order;
  }
  std::vector<uint8_t> used(static_cast<std::size_t>(n) + 1, 0);
  int at = 0;
  for (int step = 0; step < n; ++step) {
    int next = -1;
    for (int k = 1; k <= n; ++k)
      if (!used[k] && (next < 0 || d[at][k] < d[at][next])) next = k;
    used[next] = 1;
    order.push_back(next);
    at = next;
  }
  auto at_pos = [&](int i) { return i < 0 || i >= n ? 0 : order[i]; };
  for (bool improved = true; improved;) {
    improved = false;
    for (int i = 0; i < n - 1; ++i)
      for (int j = i + 1; j < n; ++j) {
        const double before = d[at_pos(i - 1)][at_pos(i)] + d[at_pos(j)][at_pos(j + 1)];
        const double after = d[at_pos(i - 1)][at_pos(j)] + d[at_pos(i)][at_pos(j + 1)];
        if (after + 1e-9 < before) {
          std::reverse(order.begin() + i, order.begin() + j + 1);
          improved = true;
        }
      }
  }
  return order;
}

// Shortest 8-connected path a -> b [m] on the route speed map by A* (octile
// heuristic; no diagonal step past a blocked corner). A leg between two
// meeting areas is short, and A* explores only around it, where an FMM march
// without a heuristic would flood a disc of the leg's length. Returns cell
// centres from a's cell to b's cell; empty if b cannot be reached.
std::vector<Point2> astar_leg(const PlanContext& ctx, Point2 a, Point2 b) {
  const OccupancyGrid& grid = ctx.scenario.grid;
  const int w = grid.width();
  const Cell ca = grid.world_to_cell(a), cb = grid.world_to_cell(b);
  const std::size_t start = grid.index(ca), goal = grid.index(cb);
  std::vector<float> g(grid.size(), std::numeric_limits<float>::infinity());
  std::vector<uint32_t> parent(grid.size(), 0);
  using Entry = std::pair<float, uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  const auto& speed = ctx.route_speed;
  auto h = [&](std::size_t i) {
    const double dx = std::abs(static_cast<int>(i % w) - cb.col), dy = std::abs(static_cast<int>(i / w) - cb.row);
    return static_cast<float>(std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy));  // at speed 1
  };
  g[start] = 0.0f;
  open.emplace(h(start), static_cast<uint32_t>(start));
  static const int dr[8] = {0, 0, 1, -1, 1, 1, -1, -1}, dc[8] = {1, -1, 0, 0, 1, -1, 1, -1};
  while (!open.empty()) {
    const auto [f, i] = open.top();
    open.pop();
    if (i == goal) break;
    if (f > g[i] + h(i) + 1e-4f) continue;  // stale entry
    const Cell c = grid.cell(i);
    for (int k = 0; k < 8; ++k) {
      const Cell n{c.row + dr[k], c.col + dc[k]};
      if (!grid.contains(n)) continue;
      const std::size_t j = grid.index(n);
      if (speed[j] <= 0) continue;
      const bool diagonal = k >= 4;
      if (diagonal && (speed[grid.index(Cell{c.row + dr[k], c.col})] <= 0 || speed[grid.index(Cell{c.row, c.col + dc[k]})] <= 0))
        continue;
      const float step = static_cast<float>((diagonal ? std::sqrt(2.0) : 1.0) * 0.5 * (1.0 / speed[i] + 1.0 / speed[j]));
      if (g[i] + step < g[j]) {
        g[j] = g[i] + step;
        parent[j] = i;
        open.emplace(g[j] + h(j), static_cast<uint32_t>(j));
      }
    }
  }
  std::vector<Point2> path;
  if (!std::isfinite(g[goal])) return path;
  for (std::size_t i = goal;; i = parent[i]) {
    path.push_back(grid.cell_center(grid.cell(i)));
    if (i == start) break;
  }
  std::reverse(path.begin(), path.end());
  path.front() = a;
  path.back() = b;
  return path;
}

// Builds the closed route of one collector through the entry cells of its
// segments: geodesic legs from FMM, visiting order by exact/2-opt tour,
// polished with OMPL.
CollectorRoute build_route(const PlanContext& ctx, fmm::FastMarching& fm, const WorkerGraph& graph,
                           const std::vector<int32_t>& labels, const std::vector<int>& segments, int collector,
                           const PlannerOptions& opt) {
  const Scenario& s = ctx.scenario;
  const OccupancyGrid& grid = s.grid;
  CollectorRoute route;
  route.collector = collector;
  if (segments.empty()) {  // more collectors than segments to serve: this one stays at the OC
    route.waypoints = {s.oc};
    return route;
  }
  std::vector<Point2> pts{s.oc};
  for (int k : segments) pts.push_back(grid.cell_center(graph.segment(k).entry));
  const std::size_t n = pts.size();
  // Visiting order on straight-line distances (cheap, and the legs between
  // consecutive stops are short, so each leg's march stops early).
  std::vector<std::vector<double>> d(n, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) d[i][j] = dist(pts[i], pts[j]);
  const std::vector<int> order = tour_order(d);
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
  for (std::size_t t = 0; t + 1 < stops.size(); ++t) {
    const Point2 a = pts[static_cast<std::size_t>(stops[t])], b = pts[static_cast<std::size_t>(stops[t + 1])];
    std::vector<Point2> leg;
    if (stops[t + 1] == 0) {  // back to the OC: down the OC's own field
      leg = fmm::descend(ctx.oc_field, a);
    } else if (stops[t] == 0) {  // out of the OC: the same, reversed
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
    const PolishedPath polished = polish_path(leg, ctx.clearance, po);
    route.waypoints.insert(route.waypoints.end(), polished.points.begin() + 1, polished.points.end());
    route.length += polished.length;
    route.min_clearance = std::min(route.min_clearance, polished.min_clearance);
  }
  route.period = route.length / s.team.speed;

  // Arc length of every waypoint, then each meeting area at the route point
  // nearest to its segment's entry cell, in visiting order.
  const std::vector<double> arc = fmm::path_arcs(route.waypoints);
  double from_s = 0.0;
  for (int stop : order) {
    const int seg = segments[static_cast<std::size_t>(stop - 1)];
    const Point2 target = pts[static_cast<std::size_t>(stop)];
    MeetingArea m;
    m.segment = seg;
    double best = kInf;
    for (std::size_t i = 0; i + 1 < route.waypoints.size(); ++i) {
      if (arc[i + 1] < from_s) continue;
      // Nearest point on segment i..i+1.
      const Point2 a = route.waypoints[i], b = route.waypoints[i + 1];
      const double len2 = (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y);
      const double t = len2 > 0 ? std::clamp(((target.x - a.x) * (b.x - a.x) + (target.y - a.y) * (b.y - a.y)) / len2, 0.0, 1.0) : 0.0;
      const Point2 p{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
      const double e = dist(p, target);
      if (e < best - 1e-9) best = e, m.point = p, m.route_s = arc[i] + t * std::sqrt(len2);
    }
    from_s = m.route_s;
    route.meetings.push_back(m);
    route.segments.push_back(seg);
  }
  // Passes: stretches of the route within kPassRadius of a served segment's
  // cells, sampled every half metre; each stretch counts once, at its middle.
  {
    constexpr double kPassRadius = 1.0;  // [m] a worker this close hands data over on the move
    const int rc = std::max(1, static_cast<int>(std::ceil(kPassRadius / grid.resolution())));
    // The disc is probed every ~0.2 m, not every cell: 1 m +- 0.2 m is close
    // enough for "next to", at a twentieth of the lookups on 5 cm maps.
    const int stride = std::max(1, static_cast<int>(std::lround(0.2 / grid.resolution())));
    const double step = 0.5;
    std::vector<double> open_since(segments.size(), -1.0);
    std::vector<int> index_of(static_cast<std::size_t>(graph.segments.size()) + 1, -1);  // label -> position in `segments`
    for (std::size_t i = 0; i < segments.size(); ++i) index_of[static_cast<std::size_t>(segments[i])] = static_cast<int>(i);
    auto seg_index = [&](int32_t label) { return label > 0 ? index_of[static_cast<std::size_t>(label)] : -1; };
    std::vector<uint8_t> near(segments.size());
    const double total = arc.back();
    for (double at = 0.0;; at = std::min(total, at + step)) {
      const Point2 p = fmm::point_at_arc(route.waypoints, arc, at);
      std::fill(near.begin(), near.end(), 0);
      const Cell c = grid.world_to_cell(p);
      for (int dr = -rc; dr <= rc; dr += stride)
        for (int dc = -rc; dc <= rc; dc += stride) {
          const Cell q{c.row + dr, c.col + dc};
          if (!grid.contains(q) || dr * dr + dc * dc > rc * rc) continue;
          const int k = seg_index(labels[grid.index(q)]);
          if (k >= 0) near[static_cast<std::size_t>(k)] = 1;
        }
      for (std::size_t k = 0; k < segments.size(); ++k) {
        if (near[k] && open_since[k] < 0) open_since[k] = at;
        if ((!near[k] || at >= total) && open_since[k] >= 0) {
          route.meetings[static_cast<std::size_t>(std::find(route.segments.begin(), route.segments.end(), segments[k]) -
                                                  route.segments.begin())]
              .passes.push_back(0.5 * (open_since[k] + at));
          open_since[k] = -1.0;
        }
      }
      if (at >= total) break;
    }
    for (MeetingArea& m : route.meetings)
      if (m.passes.empty()) m.passes.push_back(m.route_s);  // the entry point itself
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

// Distance [m] along the route from arc position `s` to where it next enters
// the OC's coverage (the route ends at the OC, inside it).
double upload_after(const CollectorRoute& r, double s) {
  for (const double u : r.coverage_entries)
    if (u >= s) return u - s;
  return std::max(0.0, r.length - s);
}

// Stretches [m, arc] of the route on which the collector is in radio
// contact with its worker: linked to the segment's centroid (where a
// touring worker typically is) or to a pass point (where it goes to hand
// over, and waits), probed every 0.5 m, plus the planned passes. The
// simulator's collector takes data whenever the link holds, so these, not
// only the passes, are where data changes hands. (Averaging the contact of
// cells spread over the segment instead came out further from the
// simulator: its workers walk towards a pass once they have data.)
using Stretches = std::vector<std::pair<double, double>>;
Stretches contact_stretches(const CollectorRoute& r, const MeetingArea& m, Point2 centroid, const RadioModel& radio) {
  const std::vector<double> arc = fmm::path_arcs(r.waypoints);
  std::vector<Point2> from{centroid};
  for (const double pass : m.passes) from.push_back(fmm::point_at_arc(r.waypoints, arc, pass));
  const double range = radio.free_space_range();
  Stretches stretches;
  double open = -1.0;
  constexpr double kStep = 0.5;
  for (double s = 0.0;; s = std::min(r.length, s + kStep)) {
    const Point2 p = fmm::point_at_arc(r.waypoints, arc, s);
    bool linked = false;
    for (const Point2& f : from) linked = linked || (dist(f, p) <= range && radio.linked(f, p));
    if (linked && open < 0) open = s;
    if ((!linked || s >= r.length) && open >= 0) stretches.emplace_back(open, s), open = -1.0;
    if (s >= r.length) break;
  }
  for (const double pass : m.passes) stretches.emplace_back(pass, pass);
  return stretches;
}

// The estimate runs the execution protocol (docs/simulator.md) over the
// mission's cycles on expected quantities instead of random goals: the
// number of a segment's goals in a request is binomial (G goals, each in the
// segment with probability A_k / A), and a tour through n of them takes
// TourModel's length. It follows each worker's decisions as the simulator
// does and returns its goals delivered and their refresh times, averaged
// over the goal count (goal-weighted, as the simulator's mean is: requests
// with more goals take longer and weigh more).
struct WorkerRun {
  double delivered = 0.0;  // goals over all cycles
  double refresh_sum = 0.0;  // sum of delivered_at - requested_at over them [s]
  // The deliveries of each area (tile) of the segment to the OC.
  std::vector<AreaDeliveries> areas;
  void add(double goals, double refresh) { delivered += goals, refresh_sum += goals * refresh; }
};

// The mean over a worker's areas of their intervals.
double mean_interval(const std::vector<AreaDeliveries>& areas, double horizon) {
  if (areas.empty()) return horizon;
  double sum = 0.0;
  for (const AreaDeliveries& a : areas) sum += a.interval(horizon);
  return sum / static_cast<double>(areas.size());
}

// P(n goals of G in a segment holding share p of the space), n = 0..; the
// tail beyond a 1e-9 remainder is dropped.
std::vector<double> goal_count_pmf(int G, double p) {
  p = std::clamp(p, 0.0, 1.0);
  std::vector<double> pmf(static_cast<std::size_t>(G) + 1, 0.0);
  if (p <= 0.0 || p >= 1.0) {
    pmf[p <= 0.0 ? 0 : static_cast<std::size_t>(G)] = 1.0;
    return pmf;
  }
  // In log space: (1 - p)^G underflows for large G (1000 goals, p = 0.55).
  const double lg = std::lgamma(G + 1.0), lp = std::log(p), lq = std::log1p(-p);
  double total = 0.0;
  for (int n = 0; n <= G; ++n) {
    const double ln = lg - std::lgamma(n + 1.0) - std::lgamma(G - n + 1.0) + n * lp + (G - n) * lq;
    pmf[static_cast<std::size_t>(n)] = ln > -40.0 ? std::exp(ln) : 0.0;
    total += pmf[static_cast<std::size_t>(n)];
  }
  for (double& x : pmf) x /= total;
  while (pmf.size() > 1 && pmf.back() == 0.0) pmf.pop_back();
  return pmf;
}

// A worker delivering to the OC: whenever it is inside the coverage it
// learns the newest request (waiting for the next one if it has served them
// all), goes into its segment, measures the request's goals it can within a
// period (the expiry rule), comes back and delivers. Requests issued
// meanwhile, but the newest, expire. `tour` starts from its home, `first`
// from the OC's cell, where it starts the mission and learns request 0.
// Deliveries of an area (`areas`: the tiles of the segment; `pmf`: the
// segment's goal count a request): its goals outside the coverage are
// delivered together on the return (one delivery when the request has at
// least one there), those inside it one by one as they are measured
// (spread over the loop).
WorkerRun run_oc_worker(const TourModel& tour, const TourModel& first, const std::vector<double>& pmf, double v,
                        double T, int cycles, const std::vector<AreaDeliveries>& areas) {
  WorkerRun run;
  run.areas = areas;
  // Of k goals, it measures those its tour reaches within a period of
  // learning the request (mission::request_deadline; the way back is not
  // counted): measured[k], on a trip of trip_s[k] [s]; and the expected
  // trip (loop [s]) and goals. Index 0: the first request's trip.
  struct Trips {
    std::vector<double> measured, trip_s;
    double loop = 0.0, goals = 0.0;
  };
  auto trips_of = [&](const TourModel& m) {
    Trips t;
    t.measured.assign(pmf.size(), 0.0), t.trip_s.assign(pmf.size(), 0.0);
    for (std::size_t k = 1; k < pmf.size(); ++k) {
      t.measured[k] = m.measured(static_cast<double>(k), v * T);
      t.trip_s[k] = m.partial_length(t.measured[k], static_cast<double>(k)) / v;
      t.loop += pmf[k] * t.trip_s[k];
      t.goals += pmf[k] * t.measured[k];
    }
    return t;
  };
  const Trips trips[2] = {trips_of(first), trips_of(tour)};
  // Goals and latency: the worker's lateness (when it is back in the
  // coverage after request r's issue) is a random walk, not its mean: a
  // loop longer than T makes it late for the next request, a shorter one
  // lets it wait; a lateness of a whole period or more means a newer request
  // was issued meanwhile, and request r is skipped. Its distribution is
  // carried over the cycles on bins of T / kBins (a loop of mean close to T
  // skips requests that the mean alone never would).
  constexpr int kBins = 64;
  const double bin = T / kBins;
  std::vector<double> late(2 * kBins + 2, 0.0), next_late(late.size());
  late[0] = 1.0;
  for (int r = 0; r < cycles; ++r) {
    const Trips& trip = trips[r == 0 ? 0 : 1];
    std::fill(next_late.begin(), next_late.end(), 0.0);
    auto put = [&](double lateness, double p) {
      const double b = std::max(0.0, lateness) / bin + 0.5;
      next_late[b >= static_cast<double>(next_late.size() - 1) ? next_late.size() - 1 : static_cast<std::size_t>(b)] += p;
    };
    for (std::size_t b = 0; b < late.size(); ++b) {
      const double p = late[b], lambda = static_cast<double>(b) * bin;
      if (p <= 0.0) continue;
      if (lambda >= T - 1e-9) {  // skipped: back after request r + 1 was issued
        put(lambda - T, p);
        continue;
      }
      for (std::size_t k = 0; k < pmf.size(); ++k) {
        if (pmf[k] <= 0.0) continue;
        if (trip.measured[k] > 0.0) run.add(p * pmf[k] * trip.measured[k], lambda + trip.trip_s[k]);
        put(lambda + trip.trip_s[k] - T, p * pmf[k]);
      }
    }
    late.swap(next_late);
  }
  // Interval: the deliveries on the mean timeline (a trip delivers the
  // request it served; skips are in the timeline's own jumps). A trip
  // measures n_k = measured[k] of the segment's k goals: the nearest to its
  // home, so a goal is measured when it lies in the nearest fraction n_k / k
  // of the segment. A goal falls in an area's part outside the coverage
  // (share f of the segment) and is measured with probability
  // f s(n_k / k), s(x) the part's share among the nearest fraction x
  // (AreaDeliveries::nearest_share), so a trip carries one of the part's
  // goals with probability sum_k P(k) (1 - (1 - f s)^k); likewise it
  // measures k f' s'(n_k / k) goals of the covered part, each delivered as
  // it is measured. (The first trip, from the OC's cell, ranks the cells as
  // from the home: the OC is in the coverage too.) A worker whose segment
  // lies partly in the coverage learns a request wherever it is there, not
  // only at its home, and starts that tour from there: with weight w, the
  // covered share of the segment, a trip serves every part alike
  // (s(x) = x), with weight 1 - w nearest-first from the home.
  double covered = 0.0;
  for (const AreaDeliveries& a : run.areas) covered += a.covered_m2;
  const double w = tour.area > 0 ? std::clamp(covered / tour.area, 0.0, 1.0) : 0.0;
  auto share = [w](const std::array<float, AreaDeliveries::kRankBins>& rank, double x) {
    return (1.0 - w) * AreaDeliveries::nearest_share(rank, x) + w * std::clamp(x, 0.0, 1.0);
  };
  std::vector<double> carries[2], inside[2];
  for (int h = 0; h < 2; ++h) {
    carries[h].assign(run.areas.size(), 0.0), inside[h].assign(run.areas.size(), 0.0);
    for (std::size_t i = 0; i < run.areas.size(); ++i) {
      const AreaDeliveries& a = run.areas[i];
      const double f = tour.area > 0 ? std::clamp((a.area_m2 - a.covered_m2) / tour.area, 0.0, 1.0) : 0.0;
      const double f_in = tour.area > 0 ? std::clamp(a.covered_m2 / tour.area, 0.0, 1.0) : 0.0;
      for (std::size_t k = 1; k < pmf.size(); ++k) {
        const double x = trips[h].measured[k] / static_cast<double>(k);
        const double out = f * share(a.rank_out, x);
        carries[h][i] += pmf[k] * (1.0 - std::pow(1.0 - out, static_cast<double>(k)));
        inside[h][i] += pmf[k] * static_cast<double>(k) * f_in * share(a.rank_in, x);
      }
    }
  }
  double t = 0.0;  // the worker is inside the coverage at t
  for (int next = 0; next < cycles;) {
    const int req = std::max(next, std::min(cycles - 1, static_cast<int>(std::floor(t / T + 1e-9))));
    t = std::max(t, req * T);
    next = req + 1;
    const int h = req == 0 ? 0 : 1;
    const double loop = trips[h].loop;
    if (trips[h].goals <= 0.0) continue;
    for (std::size_t j = 0; j < run.areas.size(); ++j) {
      AreaDeliveries& a = run.areas[j];
      a.delivery(t + loop, carries[h][j]);
      const double in = inside[h][j];
      for (int i = 1; i <= static_cast<int>(std::ceil(in)); ++i)
        a.delivery(t + loop * i / (std::ceil(in) + 1.0), std::min(1.0, in - (i - 1)));
    }
    t += loop;
  }
  return run;
}

// A worker of a collector: request r reaches it when the collector, leaving
// the OC on its first departure at or after r T, passes the meeting area
// (arc s); the next request to reach it supersedes it. It measures what fits
// until then, goals evenly along its tour, and hands each goal over at the
// first pass next to its segment after measuring it; the collector uploads
// where its route next enters the coverage.
// A hand-over of n goals takes transfer_s(n) = n * per_goal [s] of link; it
// must end within a contact stretch, less the policy's guard
// (mission::handover_guard), so a worker hands over at most
// floor((longest stretch - guard) / per_goal) goals a request.
WorkerRun run_collector_worker(const CollectorRoute& r, const MeetingArea& m, const Stretches& contact,
                               const TourModel& model, const std::vector<double>& pmf, double v, double T, int cycles,
                               const std::vector<AreaDeliveries>& areas, double per_goal) {
  WorkerRun run;
  run.areas = areas;
  const LoopSchedule sched(r.period, T);
  // The collector picks the request up at its first departure at or after
  // the issue, or where its route re-enters the coverage midway if that
  // comes first; it hands it over at the meeting area after that.
  auto pickup = [&](double t) {
    double first = sched.next_departure(t);
    for (const double u : r.coverage_entries) first = std::min(first, sched.next_at(u / v, t));
    return first;
  };
  auto arrival = [&](int req) { return sched.next_at(m.route_s / v, pickup(req * T)); };
  // When a goal measured at `ready` reaches the OC in a hand-over that needs
  // `need` [s] of link: handed over in the first contact stretch of the
  // collector that still holds that long after then, uploaded where its
  // route next enters the coverage.
  auto delivered_at = [&](double ready, double need) {
    double best = kInf;
    for (const auto& [a, b] : contact) {
      const double guard = mission::handover_guard((b - a) / v);
      if ((b - a) / v < need + guard - 1e-9) continue;
      const double loop_start = sched.next_at(b / v, ready + need + guard) - b / v;
      const double handover = std::max(ready, loop_start + a / v) + need;
      best = std::min(best, handover + upload_after(r, (handover - loop_start) * v) / v);
    }
    return best;
  };
  double longest = 0.0;
  for (const auto& [a, b] : contact) longest = std::max(longest, (b - a) / v);
  const double capacity = per_goal > 0.0 ? std::floor((longest - mission::handover_guard(longest)) / per_goal + 1e-9)
                                         : kInf;
  std::vector<double> at;  // upload times of one goal count's samples
  at.reserve(16);
  for (int req = 0; req < cycles; ++req) {
    const double learn = arrival(req);
    // Valid for a period after it arrived, or until the next one arrives
    // (mission::request_deadline).
    const double fits = std::min(capacity, model.goals_within(v * (std::min(arrival(req + 1), learn + T) - learn),
                                                              static_cast<double>(pmf.size())));
    for (std::size_t k = 1; k < pmf.size(); ++k) {
      const double n = std::min(static_cast<double>(k), fits);
      if (n <= 0.0) continue;
      const double tour = model.length(n) / v, need = n * per_goal;
      constexpr int kSamples = 8;
      double sum = 0.0;
      for (int i = 1; i <= kSamples; ++i) sum += delivered_at(learn + tour * i / kSamples, need) - req * T;
      run.add(pmf[k] * n, sum / kSamples);
      // Deliveries: the uploads that carry some of the n goals (spread
      // evenly along the tour; each of goals_n samples stands for n /
      // goals_n goals); an upload carrying m goals of the segment carries
      // one of an area holding share f of it with probability 1 - (1 - f)^m;
      // weighted by P(k goals).
      const int goals_n = static_cast<int>(std::min(16.0, std::ceil(n)));
      at.clear();
      for (int i = 1; i <= goals_n; ++i) {
        const double t = delivered_at(learn + tour * i / goals_n, need);
        if (std::isfinite(t)) at.push_back(t);
      }
      std::sort(at.begin(), at.end());
      const double per_sample = n / std::max(1, goals_n);
      for (std::size_t i = 0; i < at.size();) {
        std::size_t j = i;
        while (j < at.size() && at[j] - at[i] <= 1e-3) ++j;
        const double goals_in = per_sample * static_cast<double>(j - i);
        for (AreaDeliveries& a : run.areas)
          a.delivery(at[i], pmf[k] * (1.0 - std::pow(std::max(0.0, 1.0 - a.area_m2 / model.area), goals_in)), pmf[k]);
        i = j;
      }
    }
  }
  return run;
}

// One worker's estimate in configuration cfg (its segment's association
// and, for a worker of a collector, that collector's route).
WorkerEstimate estimate_worker(const PlanContext& ctx, const ConfigurationPlan& cfg, const WorkerSegment& seg,
                               const RadioModel& radio, const PlannerOptions& opt) {
  const Scenario& s = ctx.scenario;
  const double v = s.team.speed, T = ctx.cycle_period, c = opt.tsp_constant;
  const double G = s.mission.goals_per_request;
  const int cycles = std::max(1, s.mission.cycles);
  WorkerEstimate w;
  w.segment = seg.id;
  w.collector = cfg.collector_of_segment[static_cast<std::size_t>(seg.id - 1)];
  w.expected_goals = G * seg.area / ctx.reachable_area;
  const std::vector<double> pmf = goal_count_pmf(static_cast<int>(G), seg.area / ctx.reachable_area);
  WorkerRun run;
  run.areas = cfg.area_parts[static_cast<std::size_t>(seg.id - 1)];  // no deliveries unless a run below finds some
  if (w.collector < 0) {
    const TourModel model = tour_model(seg, true, c);
    w.tour_s = model.length(w.expected_goals) / v;
    run = run_oc_worker(model, first_trip(seg, model), pmf, v, T, cycles,
                        cfg.area_parts[static_cast<std::size_t>(seg.id - 1)]);
  } else {
    const CollectorRoute& r = cfg.routes[static_cast<std::size_t>(w.collector)];
    const auto m = std::find_if(r.meetings.begin(), r.meetings.end(),
                                [&](const MeetingArea& a) { return a.segment == seg.id; });
    const TourModel model = tour_model(seg, false, c);
    w.tour_s = model.length(w.expected_goals) / v;
    if (m != r.meetings.end())
      run = run_collector_worker(r, *m, contact_stretches(r, *m, seg.centroid_m, radio), model, pmf, v, T, cycles,
                                 cfg.area_parts[static_cast<std::size_t>(seg.id - 1)], transfer_s(s, 1));
  }
  w.delivered_goals = run.delivered / cycles;
  w.refresh_s = run.delivered > 0 ? run.refresh_sum / run.delivered : 0.0;
  w.interval_s = mean_interval(run.areas, cycles * T);
  w.areas = std::move(run.areas);
  return w;
}

// The configuration's figures from its workers' estimates. The interval is
// the mean over the world's areas (ctx.areas: every tile with reachable
// space, weighted by it, as mission::interval_stats weighs them; a tile
// split between segments gets the deliveries of each, which counts an
// upload carrying goals of both parts twice; a tile no estimate reaches
// counts the whole mission).
void combine(Estimates& e, const PlanContext& ctx) {
  e.goals = 0.0;
  double weighted = 0.0;
  for (const WorkerEstimate& w : e.workers) e.goals += w.delivered_goals, weighted += w.delivered_goals * w.refresh_s;
  e.refresh_s = e.goals > 0 ? weighted / e.goals : 0.0;
  std::map<int64_t, AreaDeliveries> tiles;  // area_m2: the tile's whole reachable area
  for (const auto& [id, m2] : ctx.areas.area) tiles[id].area_m2 = m2;
  for (const WorkerEstimate& w : e.workers)
    for (const AreaDeliveries& a : w.areas) tiles[a.area].merge(a);
  const int cycles = std::max(1, ctx.scenario.mission.cycles);
  const double horizon = cycles * ctx.cycle_period;
  double sum = 0.0, weights = 0.0;
  for (const auto& [id, t] : tiles) sum += t.area_m2 * t.interval(horizon), weights += t.area_m2;
  e.interval_s = weights > 0 ? sum / weights : horizon;
}

Estimates estimate(const PlanContext& ctx, const ConfigurationPlan& cfg, const PlannerOptions& opt) {
  const RadioModel radio(ctx.scenario.grid, ctx.scenario.radio);
  Estimates e;
  for (const WorkerSegment& seg : cfg.graph.segments) e.workers.push_back(estimate_worker(ctx, cfg, seg, radio, opt));
  combine(e, ctx);
  return e;
}

// How well a configuration serves the OC, for decisions inside one
// configuration (the utility U compares configurations by min-max
// normalisation over the sweep, which a single configuration does not
// have): J = (beta N / G - alpha T_refresh / T) / (alpha + beta), goals
// per cycle on the scale of a request's goals G, the refresh time on the
// scale of the request period T. Larger is better.
double score(const Estimates& e, const PlanContext& ctx) {
  const PlannerParams& pp = ctx.scenario.planner;
  const double G = std::max(1, ctx.scenario.mission.goals_per_request), T = ctx.cycle_period;
  // No goal delivered: as bad as a refresh of all the mission's cycles.
  const double refresh = e.goals > 0 ? e.refresh(pp.refresh) : T * std::max(1, ctx.scenario.mission.cycles);
  return (pp.beta * e.goals / G - pp.alpha * refresh / T) / (pp.alpha + pp.beta);
}

// The segments collector c serves, ascending.
std::vector<int> segments_of(const ConfigurationPlan& cfg, int c) {
  std::vector<int> segs;
  for (const WorkerSegment& seg : cfg.graph.segments)
    if (cfg.collector_of_segment[static_cast<std::size_t>(seg.id - 1)] == c) segs.push_back(seg.id);
  return segs;
}

// Association as a decision (seed sec. 3.1: the planner decides "with whom
// the workers must communicate, a collector or the OC", balancing "the time
// of the collectors and of the workers' estimated trajectories").
// The groups grown by group_segments are the starting point; then
//  1. balance: while a collector's route is longer than the request period
//     (its loop would carry out only the newest of the requests issued
//     meanwhile, and skip the others), one of its segments goes to the OC:
//     the one whose move leaves the best score J. A route that cannot be
//     trimmed under T leaves the collector idle.
//  2. decide: a worker of a collector moves to the OC when that raises J
//     (the move also shortens its collector's route, which the re-estimate
//     sees); the most promising moves by the worker's own estimate are tried
//     first, the best of them is kept, until none raises J.
// Each trial rebuilds one route and re-runs the estimate (a few ms).
void associate(const PlanContext& ctx, fmm::FastMarching& fm, ConfigurationPlan& cfg, const PlannerOptions& opt) {
  const Scenario& s = ctx.scenario;
  const double T = ctx.cycle_period, v = s.team.speed;
  const double G = std::max(1, s.mission.goals_per_request);
  const int cycles = std::max(1, s.mission.cycles);
  const RadioModel radio(s.grid, s.radio);
  // Moves segment k to the OC, rebuilds its collector's route, re-estimates
  // the workers that changes (that collector's and k's), returns J;
  // undo() restores the state before the move.
  CollectorRoute saved_route;
  Estimates saved_estimates;
  int saved_k = 0, saved_c = -1;
  auto try_move = [&](int k) {
    saved_k = k;
    saved_c = cfg.collector_of_segment[static_cast<std::size_t>(k - 1)];
    saved_route = cfg.routes[static_cast<std::size_t>(saved_c)];
    saved_estimates = cfg.estimates;
    cfg.collector_of_segment[static_cast<std::size_t>(k - 1)] = -1;
    cfg.routes[static_cast<std::size_t>(saved_c)] =
        build_route(ctx, fm, cfg.graph, cfg.partition.labels, segments_of(cfg, saved_c), saved_c, opt);
    for (WorkerEstimate& w : cfg.estimates.workers)
      if (w.segment == k || w.collector == saved_c)
        w = estimate_worker(ctx, cfg, cfg.graph.segment(w.segment), radio, opt);
    combine(cfg.estimates, ctx);
    return score(cfg.estimates, ctx);
  };
  auto undo = [&]() {
    cfg.collector_of_segment[static_cast<std::size_t>(saved_k - 1)] = saved_c;
    cfg.routes[static_cast<std::size_t>(saved_c)] = saved_route;
    cfg.estimates = saved_estimates;
  };
  // A segment's worker delivering to the OC: its estimate depends on no
  // route, so it is run once per segment, on first need.
  struct OcAlternative {
    bool known = false;
    double goals = 0.0, latency = 0.0, interval = 0.0;  // per cycle; [s]; [s]
  };
  std::vector<OcAlternative> alternatives(cfg.graph.segments.size());
  auto oc_alternative = [&](int segment) -> const OcAlternative& {
    OcAlternative& a = alternatives[static_cast<std::size_t>(segment - 1)];
    if (a.known) return a;
    const WorkerSegment& seg = cfg.graph.segment(segment);
    const std::vector<double> pmf = goal_count_pmf(s.mission.goals_per_request, seg.area / ctx.reachable_area);
    const TourModel model = tour_model(seg, true, opt.tsp_constant);
    const WorkerRun oc = run_oc_worker(model, first_trip(seg, model), pmf, v, T, cycles,
                                       cfg.area_parts[static_cast<std::size_t>(segment - 1)]);
    a.known = true;
    a.goals = oc.delivered / cycles;
    a.latency = oc.delivered > 0 ? oc.refresh_sum / oc.delivered : 0.0;
    a.interval = mean_interval(oc.areas, cycles * T);
    return a;
  };
  // The most promising moves first: by how much a worker's own share of J
  // would grow if it delivered to the OC. Only workers of collector `only`
  // (-1: of any collector).
  auto ranked = [&](int only) {
    const double goals = std::max(1e-9, cfg.estimates.goals);
    // Latency: the worker's goal-weighted part of the mean; interval: its
    // part of the mean over segments.
    const double n_workers = static_cast<double>(cfg.estimates.workers.size());
    auto share = [&](double delivered, double latency, double interval) {
      const double t = s.planner.refresh == RefreshMetric::kInterval ? interval / n_workers : delivered * latency / goals;
      return s.planner.beta * delivered / G - s.planner.alpha * t / T;
    };
    std::vector<std::pair<double, int>> gain;
    for (const WorkerEstimate& w : cfg.estimates.workers) {
      if (w.collector < 0 || (only >= 0 && w.collector != only)) continue;
      const OcAlternative& oc = oc_alternative(w.segment);
      gain.emplace_back(share(oc.goals, oc.latency, oc.interval) - share(w.delivered_goals, w.refresh_s, w.interval_s),
                        w.segment);
    }
    std::sort(gain.begin(), gain.end(), std::greater<>());
    return gain;
  };
  constexpr std::size_t kTrials = 4;  // moves fully re-estimated per step
  // 1. Balance: the best of the promising moves and of the one farthest
  // from the coverage (it usually shortens the route most).
  for (int c = 0; c < cfg.collectors; ++c) {
    while (cfg.routes[static_cast<std::size_t>(c)].period > T * (1.0 + 1e-9)) {
      const std::vector<std::pair<double, int>> gain = ranked(c);
      if (gain.empty()) break;
      std::vector<int> trials;
      for (std::size_t i = 0; i < gain.size() && i < kTrials; ++i) trials.push_back(gain[i].second);
      int farthest = gain.front().second;
      for (const auto& [g, k] : gain)
        if (cfg.graph.segment(k).coverage_distance > cfg.graph.segment(farthest).coverage_distance) farthest = k;
      if (std::find(trials.begin(), trials.end(), farthest) == trials.end()) trials.push_back(farthest);
      int best_k = trials.front();
      double best = -kInf;
      for (int k : trials) {
        const double j = try_move(k);
        undo();
        if (j > best) best = j, best_k = k;
      }
      try_move(best_k);
      ++cfg.moved_to_oc;
    }
  }
  // 2. Decide, worker by worker, while a move raises J.
  for (double current = score(cfg.estimates, ctx);;) {
    const std::vector<std::pair<double, int>> gain = ranked(-1);
    int best_k = -1;
    double best = current;
    for (std::size_t i = 0; i < gain.size() && i < kTrials; ++i) {
      const double j = try_move(gain[i].second);
      undo();
      if (j > best + 1e-12) best = j, best_k = gain[i].second;
    }
    if (best_k < 0) break;
    current = try_move(best_k);
    ++cfg.moved_to_oc;
  }
}

// Each segment's walking distances, marched at unit speed on the reachable
// space (as the workers walk), each march stopped once the segment's cells
// are reached:
//  - mean_home_distance and home_quantiles: from the home of its worker as
//    a worker of the OC;
//  - mean_oc_distance and oc_quantiles: from the OC's cell (ctx.oc_walk,
//    no march), where that worker starts the mission;
//  - mean_pair_distance: between two of its cells, the mean over the cells
//    of the distances from kPairSources cells spread over the segment (in
//    row-major order, so the estimate is deterministic), marched in the
//    segment's window as the worker marches between its goals.
// Returns each cell's rank in its segment by distance from that home, in
// [0, 1) (row-major; -1 off the segments).
// The bits of a distance as a float; for d >= 0 (and +inf) they sort like d.
uint32_t float_bits(double d) {
  const float f = static_cast<float>(d);
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}

std::vector<float> segment_distances(const PlanContext& ctx, const std::vector<int32_t>& labels, WorkerGraph& graph) {
  constexpr std::size_t kPairSources = 3, kQuantiles = 16;
  constexpr double kHomeBoxMargin = 3.0;  // [m] around the segment and its home, for the walk from the home
  const OccupancyGrid& grid = ctx.scenario.grid;
  std::vector<std::vector<Cell>> cells(graph.segments.size());
  for (std::size_t i = 0; i < labels.size() && i < grid.size(); ++i) {
    const int k = labels[i];
    if (k > 0 && static_cast<std::size_t>(k) <= cells.size() && ctx.reachable[i])
      cells[static_cast<std::size_t>(k - 1)].push_back(grid.cell(i));
  }
  std::vector<float> rank(labels.size(), -1.0f);
  std::vector<uint64_t> order;
  std::vector<double> sorted;  // distances of one segment's cells, ascending
  std::vector<double> pair;    // distances from one cell of a segment to its cells
  std::vector<double> walk_time;  // from the home to the segment's cells
  // The kQuantiles + 1 quantiles of ascending distances (the i-th: the
  // value at rank i / kQuantiles).
  auto quantiles = [](const std::vector<double>& ascending) {
    std::vector<double> q(kQuantiles + 1);
    for (std::size_t i = 0; i <= kQuantiles; ++i)
      q[i] = ascending[std::min(ascending.size() - 1, i * ascending.size() / kQuantiles)];
    return q;
  };
  fmm::FastMarching walk = ctx.coverage_field;  // unit speed on the reachable space
  fmm::SolveOptions so;
  so.labels = false;
  // The mean distance from `from` to the segment's cells (those reached).
  auto mean_from = [&](Cell from, const std::vector<Cell>& to, double& sum, std::size_t& n) {
    so.targets = to;
    walk.solve({fmm::Source::at_cell(from)}, so);
    for (Cell c : to) {
      const double t = walk.time(c);
      if (t < kInf) sum += t, ++n;
    }
  };
  for (std::size_t k = 0; k < cells.size(); ++k) {
    WorkerSegment& seg = graph.segments[k];
    seg.mean_home_distance = seg.mean_coverage_distance;
    seg.mean_pair_distance = kSquarePairDistance * std::sqrt(seg.area);  // an open square's, until measured
    if (cells[k].empty()) continue;
    walk_time.assign(cells[k].size(), kInf);
    double sum = 0.0;
    std::size_t n = 0;
    const Cell home = ctx.oc_worker_home(cells[k]);
    // From the home: in the segment's window when the home lies in it (a
    // segment that touches the coverage), else in a box around both, else
    // on the whole map.
    mission::SegmentWindow window(grid, cells[k]);
    pair.resize(cells[k].size());
    if (home.row >= 0) {
      if (window.march(home, cells[k], pair.data()) ||
          mission::SegmentWindow(grid, cells[k], home, kHomeBoxMargin).march(home, cells[k], pair.data())) {
        for (std::size_t i = 0; i < pair.size(); ++i) walk_time[i] = pair[i];
        for (double t : pair) sum += t;
        n = pair.size();
      } else {
        mean_from(home, cells[k], sum, n);
        for (std::size_t i = 0; i < cells[k].size(); ++i) walk_time[i] = walk.time(cells[k][i]);
      }
    }
    if (n > 0) seg.mean_home_distance = sum / static_cast<double>(n);
    // Ascending by distance, ties by row-major order: keys (the distance's
    // float bits, which sort like distances >= 0) << 32 | index in cells[k].
    // The marches' times are floats, so nothing is lost.
    order.clear();
    for (std::size_t i = 0; i < cells[k].size(); ++i)
      order.push_back(static_cast<uint64_t>(float_bits(home.row >= 0 ? walk_time[i] : 0.0)) << 32 | i);
    std::sort(order.begin(), order.end());
    for (std::size_t i = 0; i < order.size(); ++i)
      rank[grid.index(cells[k][order[i] & 0xffffffffu])] = static_cast<float>(static_cast<double>(i) / static_cast<double>(order.size()));
    if (home.row >= 0 && n == order.size()) {
      sorted.clear();
      for (uint64_t key : order) sorted.push_back(walk_time[key & 0xffffffffu]);
      seg.home_quantiles = quantiles(sorted);
    }
    // From the OC's cell (the first request's trip).
    std::vector<double>& from_oc = sorted;
    from_oc.clear();
    for (Cell c : cells[k]) {
      const double d = ctx.oc_walk[grid.index(c)];
      if (d < kInf) from_oc.push_back(d);
    }
    if (from_oc.size() == cells[k].size()) {
      std::sort(from_oc.begin(), from_oc.end());
      double total = 0.0;
      for (double d : from_oc) total += d;
      seg.mean_oc_distance = total / static_cast<double>(from_oc.size());
      seg.oc_quantiles = quantiles(from_oc);
    } else {
      seg.mean_oc_distance = seg.mean_home_distance, seg.oc_quantiles = seg.home_quantiles;
    }
    // Between its cells, in its window as the worker walks between goals
    // (on the whole map when the window does not connect them).
    sum = 0.0, n = 0;
    const std::size_t sources = std::min(kPairSources, cells[k].size());
    for (std::size_t j = 0; j < sources; ++j) {
      const Cell from = cells[k][(2 * j + 1) * cells[k].size() / (2 * sources)];
      if (!window.march(from, cells[k], pair.data())) {
        mean_from(from, cells[k], sum, n);
        continue;
      }
      for (double t : pair) sum += t;
      n += pair.size();
    }
    if (n > 0) seg.mean_pair_distance = sum / static_cast<double>(n);
  }
  return rank;
}

}  // namespace

PlanContext::PlanContext(const Scenario& s) : World(s), clearance(s.grid), oc_field(s.grid) {
  const OccupancyGrid& grid = s.grid;
  prepared.width = grid.width();
  prepared.height = grid.height();
  prepared.oc = oc_cell;
  prepared.reachable = reachable;
  prepared.reachable_cells = reachable_cells;
  prepared.clearance = clearance.values();
  coverage_field.copy_times(coverage_distance);
  // The simulator's own table of distances from the OC's cell.
  oc_walk = mission::SharedDistances(*this).from_oc;
  for (std::size_t i = 0; i < coverage_distance.size(); ++i) {
    if (coverage[i]) coverage_distance[i] = 0.0;
    if (!reachable[i]) coverage_distance[i] = kInf;
    else farthest = std::max(farthest, coverage_distance[i]);
  }
  route_speed.assign(grid.size(), 0.0);
  roomy.assign(grid.size(), 0);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!reachable[i]) continue;
    // The margin of a half cell diagonal makes every point of a roomy cell,
    // not only its centre, keep the radius (see ClearanceMap::free_distance).
    roomy[i] = clearance.disc_free(grid.cell_center(grid.cell(i)), s.team.radius + 0.5 * std::sqrt(2.0) * grid.resolution());
    route_speed[i] = roomy[i] ? 1.0 : kTightSpeed;
  }
  oc_field.set_speed(route_speed);
  fmm::SolveOptions from_oc;
  from_oc.labels = false;
  oc_field.solve({fmm::Source::at_point(s.oc)}, from_oc);
  cycle_period = s.mission.period > 0 ? s.mission.period : farthest / s.team.speed;
  if (cycle_period <= 0) cycle_period = 1.0;  // the whole space is covered: any period works
  area_tile = std::sqrt(std::max(reachable_area, grid.cell_area()) / std::max(1, s.team.agents));
  areas = mission::area_weights(*this, area_tile);
  for (const auto& [id, m2] : areas.area) tile_ids.push_back(id);
  tile_of_cell.assign(grid.size(), -1);
  for (std::size_t i = 0; i < grid.size(); ++i)
    if (reachable[i]) {
      const int64_t a = mission::area_of(grid.cell_center(grid.cell(i)), area_tile);
      tile_of_cell[i] = static_cast<int32_t>(std::lower_bound(tile_ids.begin(), tile_ids.end(), a) - tile_ids.begin());
    }
}

ConfigurationPlan plan_configuration(const PlanContext& ctx, partition::Method method, int collectors,
                                     const PlannerOptions& opt) {
  const Scenario& s = ctx.scenario;
  if (collectors < 0 || collectors >= s.team.agents)
    throw Error(s.path, "cannot plan " + std::to_string(collectors) + " collectors for a team of " +
                            std::to_string(s.team.agents) + " (at least one worker)");
  ConfigurationPlan cfg;
  cfg.method = method;
  cfg.collectors = collectors;
  cfg.workers = s.team.agents - collectors;

  auto t0 = Clock::now();
  cfg.partition = partition::partition_area(s.grid, ctx.prepared, method, cfg.workers, opt.seed);
  cfg.partition.clearance.clear();
  cfg.partition.clearance.shrink_to_fit();
  cfg.times.partition_ms = ms_since(t0);

  t0 = Clock::now();
  cfg.graph = build_worker_graph(s.grid, cfg.partition.labels, cfg.workers, ctx.coverage, ctx.coverage_distance, &ctx.roomy);
  const std::vector<float> home_rank = segment_distances(ctx, cfg.partition.labels, cfg.graph);
  cfg.times.graph_ms = ms_since(t0);
  // The tiles of each segment (the areas of the refresh interval).
  {
    const std::size_t tiles = ctx.tile_ids.size(), workers = static_cast<std::size_t>(cfg.workers);
    std::vector<int32_t> part(tiles * workers, -1);  // [segment][tile] -> index in area_parts[segment]
    cfg.area_parts.assign(workers, {});
    const double cell = s.grid.cell_area();
    for (std::size_t i = 0; i < cfg.partition.labels.size(); ++i) {
      const int k = cfg.partition.labels[i];
      const int32_t t = ctx.tile_of_cell[i];
      if (k <= 0 || k > cfg.workers || t < 0) continue;
      std::vector<AreaDeliveries>& parts = cfg.area_parts[static_cast<std::size_t>(k - 1)];
      int32_t& j = part[static_cast<std::size_t>(k - 1) * tiles + static_cast<std::size_t>(t)];
      if (j < 0) j = static_cast<int32_t>(parts.size()), parts.push_back(AreaDeliveries{ctx.tile_ids[static_cast<std::size_t>(t)]});
      AreaDeliveries& a = parts[static_cast<std::size_t>(j)];
      a.area_m2 += cell;
      const int b = std::clamp(static_cast<int>(std::max(0.0f, home_rank[i]) * AreaDeliveries::kRankBins), 0,
                               AreaDeliveries::kRankBins - 1);
      if (ctx.coverage[i]) a.covered_m2 += cell, a.rank_in[static_cast<std::size_t>(b)] += 1.0f;
      else a.rank_out[static_cast<std::size_t>(b)] += 1.0f;
    }
    for (std::vector<AreaDeliveries>& parts : cfg.area_parts)
      std::sort(parts.begin(), parts.end(), [](const AreaDeliveries& x, const AreaDeliveries& y) { return x.area < y.area; });
  }

  t0 = Clock::now();
  std::vector<double> work;
  for (const WorkerSegment& seg : cfg.graph.segments) {
    const double g = s.mission.goals_per_request * seg.area / ctx.reachable_area;
    work.push_back(tour_model(seg, false, opt.tsp_constant).length(g) / s.team.speed);
  }
  cfg.collector_of_segment = group_segments(cfg.graph, collectors, work);
  cfg.times.groups_ms = ms_since(t0);

  t0 = Clock::now();
  fmm::FastMarching fm = ctx.oc_field;  // a copy already on the route speed map
  for (int c = 0; c < collectors; ++c)
    cfg.routes.push_back(build_route(ctx, fm, cfg.graph, cfg.partition.labels, segments_of(cfg, c), c, opt));
  cfg.times.routes_ms = ms_since(t0);

  t0 = Clock::now();
  cfg.estimates = estimate(ctx, cfg, opt);
  cfg.times.estimate_ms = ms_since(t0);

  if (collectors > 0 && opt.associate) {
    t0 = Clock::now();
    associate(ctx, fm, cfg, opt);
    cfg.times.associate_ms = ms_since(t0);
  }
  return cfg;
}

double association_score(const PlanContext& ctx, const Estimates& estimates) { return score(estimates, ctx); }

void compute_utilities(std::vector<ConfigurationPlan>& configs, double alpha, double beta, RefreshMetric m) {
  if (configs.empty()) return;
  double tmin = kInf, tmax = -kInf, nmin = kInf, nmax = -kInf;
  for (const auto& c : configs) {
    tmin = std::min(tmin, c.estimates.refresh(m)), tmax = std::max(tmax, c.estimates.refresh(m));
    nmin = std::min(nmin, c.estimates.goals), nmax = std::max(nmax, c.estimates.goals);
  }
  const double sum = alpha + beta;
  // Spreads below a millionth of the values are rounding, not differences.
  const bool t_varies = tmax - tmin > 1e-6 * std::max(1.0, std::abs(tmax));
  const bool n_varies = nmax - nmin > 1e-6 * std::max(1.0, std::abs(nmax));
  for (auto& c : configs) {
    const double tn = t_varies ? (c.estimates.refresh(m) - tmin) / (tmax - tmin) : 0.0;
    const double nn = n_varies ? (c.estimates.goals - nmin) / (nmax - nmin) : 0.0;
    c.utility = (alpha * (1.0 - tn) + beta * nn) / (sum > 0 ? sum : 1.0);
  }
}

SweepResult sweep(const PlanContext& ctx, const PlannerOptions& opt) {
  const auto t0 = Clock::now();
  const PlannerParams& pp = ctx.scenario.planner;
  struct Job {
    partition::Method method;
    int collectors;
  };
  std::vector<Job> jobs;
  for (const std::string& m : pp.methods)
    for (int nc = pp.collectors_min; nc <= pp.collectors_max; ++nc) jobs.push_back(Job{partition::parse_method(m), nc});
  SweepResult result;
  result.configs.resize(jobs.size());
  std::vector<std::string> errors(jobs.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&]() {
    for (std::size_t j; (j = next.fetch_add(1)) < jobs.size();) {
      try {
        result.configs[j] = plan_configuration(ctx, jobs[j].method, jobs[j].collectors, opt);
      } catch (const std::exception& e) {
        errors[j] = e.what();
      }
    }
  };
  const int threads = std::max(1, std::min<int>(opt.threads, static_cast<int>(jobs.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  for (const std::string& e : errors)
    if (!e.empty()) throw Error("", e);
  compute_utilities(result.configs, pp.alpha, pp.beta, pp.refresh);
  for (std::size_t i = 0; i < result.configs.size(); ++i)
    if (result.best < 0 || result.configs[i].utility > result.configs[static_cast<std::size_t>(result.best)].utility)
      result.best = static_cast<int>(i);
  result.wall_ms = ms_since(t0);
  return result;
}

}  // namespace plan
}  // namespace gather
