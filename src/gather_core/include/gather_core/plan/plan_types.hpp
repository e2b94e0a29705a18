#pragma once
// The parts of a plan that executing it needs (plan.yaml holds them): where
// a worker meets its collector, a collector's closed route, the planner's
// per-worker estimate. Plain data, no planning code.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/ids.hpp"
#include "gather_core/segment_id.hpp"

namespace gather {
namespace plan {

// Where a worker meets its collector: the route point nearest to the
// segment's entry (where the request is handed over), and every stretch of the
// route that passes next to the segment (where data can be handed over).
struct MeetingArea {
  SegmentId segment;           // the worker segment it serves
  Point2 point;                // [m] on the route, next to the segment
  double arc_m = 0.0;          // [m] arc length of `point` from the route start
  std::vector<double> passes;  // [m] arc lengths of the middles of the stretches passing next to the segment
};

// A collector's closed route: from the OC through its meeting areas and back
// into the OC's coverage.
struct CollectorRoute {
  CollectorId collector;            // 0..N_c-1
  std::vector<SegmentId> segments;  // worker segments it serves, in visiting order
  std::vector<Point2> waypoints;    // [m] polished, first and last at the OC
  std::vector<MeetingArea> meetings;
  double length = 0.0;                   // [m]
  double period = 0.0;                   // [s] length / speed
  double min_clearance = 0.0;            // [m] of the polished route
  std::vector<double> coverage_entries;  // [m] arc lengths where the route enters the OC's coverage (uploads)
  std::vector<double> arcs;              // [m] arc length at each waypoint (build_route; empty: not known)
};

// One area of the refresh interval (a tile of mission::area_of), or the part
// of it in one worker's segment, and the deliveries of its data the
// estimate expects (over the goal count; first and last of them [s]).
struct AreaDeliveries {
  int64_t area = 0;         // mission::area_of
  double area_m2 = 0.0;     // reachable area of the tile in the segment
  double covered_m2 = 0.0;  // of it inside the OC's coverage
  // Where the part's cells rank among its segment's cells by walking
  // distance from the home of the segment's worker as a worker of the OC
  // (a worker that cannot measure all its goals in time measures the
  // nearest): cells of the part outside (rank_out) and inside (rank_in) the
  // OC's coverage whose rank lies in [b, b + 1) / kRankBins.
  static constexpr int kRankBins = 16;
  std::array<float, kRankBins> rank_out{}, rank_in{};
  // The share of those cells (rank_out or rank_in) among the nearest
  // fraction x of the segment (1 at x = 1; linear inside a bin).
  static double nearest_share(const std::array<float, kRankBins>& ranks, double x) {
    double total = 0.0, in = 0.0;
    for (float n : ranks) total += n;
    if (total <= 0.0) return 0.0;
    const double b = std::clamp(x, 0.0, 1.0) * kRankBins;
    for (int i = 0; i < kRankBins; ++i) in += ranks[static_cast<std::size_t>(i)] * std::clamp(b - i, 0.0, 1.0);
    return in / total;
  }
  double deliveries = 0.0;  // expected number of deliveries
  double events = 0.0;      // deliveries that may happen (each with its probability)
  double first = std::numeric_limits<double>::infinity(), last = -std::numeric_limits<double>::infinity();
  // A delivery at t [s] carrying some of the area's goals with probability
  // `expected`; `slots`: how many chances to deliver it stands for (below 1
  // when it is one of several exclusive cases, weighted by the case's
  // probability).
  void delivery(double t, double expected, double slots = 1.0) {
    if (expected <= 1e-9) return;
    deliveries += expected;
    events += slots;
    if (t < first) first = t;
    if (t > last) last = t;
  }
  // Adds another part's deliveries (a tile split between segments sums its
  // parts; the areas are not added).
  void merge(const AreaDeliveries& o) {
    deliveries += o.deliveries, events += o.events;
    first = std::min(first, o.first), last = std::max(last, o.last);
  }
  // The expected time [s] between the area's consecutive deliveries, as
  // mission::interval_stats measures it on one run: (last - first) / (D - 1)
  // for D >= 2 deliveries, the whole mission (`horizon`) when fewer. Here D
  // is random: `events` deliveries may happen between `first` and `last`,
  // `deliveries` of them expected. D is taken binomial (m = events,
  // p = deliveries / events), the D that happen lying anywhere among the
  // events: then E[last - first | D = d] = S (d - 1) / (d + 1) with
  // S = (m + 1) (last - first) / (m - 1) for m events evenly spread, so the
  // interval is S / (d + 1), and
  //   E = horizon P(D <= 1) + S E[1 / (D + 1); D >= 2],
  //   E[1 / (D + 1)] = (1 - (1 - p)^(m + 1)) / ((m + 1) p).
  // When every event happens (p = 1) it is (last - first) / (m - 1). (The
  // interval of the expected count, (last - first) / (E[D] - 1), is the
  // interval of no run, and too long when deliveries are uncertain.)
  double interval(double horizon) const {
    const double m = events;
    if (m < 2.0 - 1e-9 || !(last > first) || deliveries <= 1e-9) return horizon;
    const double p = std::clamp(deliveries / events, 0.0, 1.0), q = 1.0 - p;
    const double p0 = std::pow(q, m), p1 = m * p * std::pow(q, m - 1.0);
    const double inv = (1.0 - std::pow(q, m + 1.0)) / ((m + 1.0) * p);  // E[1 / (D + 1)]
    const double span = (m + 1.0) * (last - first) / (m - 1.0);
    return horizon * (p0 + p1) + span * std::max(0.0, inv - p0 - 0.5 * p1);
  }
};

struct WorkerEstimate {
  SegmentId segment;
  CollectorId collector;              // none: delivers to the OC directly
  double expected_goals = 0.0;        // goals of one request falling in its segment
  double delivered_goals = 0.0;       // of those, measured within the cycle
  double tour_s = 0.0;                // [s] time to measure all its goals (tour + approach)
  double refresh_s = 0.0;             // [s] mean request-to-delivery time of its goals (latency)
  double interval_s = 0.0;            // [s] mean over its areas of the time between their deliveries (interval)
  std::vector<AreaDeliveries> areas;  // the tiles of its segment (not in plan.yaml)
};

}  // namespace plan
}  // namespace gather
