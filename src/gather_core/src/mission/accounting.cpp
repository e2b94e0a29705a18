// Per-goal accounting of a mission: replays the goals' timestamps in time
// order and checks conservation at the end of every cycle.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/mission/simulator.hpp"

namespace gather {
namespace mission {
namespace {

// At equal times: expiries first (a goal expires at the next request's time),
// then a goal's own request, measurement, pick-up and delivery.
enum Kind : int {
  kExpire = 0,
  kUnreach = 1,
  kRequest = 2,
  kMeasure = 3,
  kPickup = 4,
  kDeliver = 5,
  kDrop = 6,
  kLose = 7
};
enum Where : uint8_t {
  kNone,
  kPendingAt,
  kWorker,
  kCollector,
  kDeliveredAt,
  kExpiredAt,
  kDroppedAt,
  kLostAt,
  kUnreachableAt
};

struct Event {
  double t;
  int kind;
  int goal;
};

// A broken invariant of the accounting is a bug (exit status 1), not bad input.
[[noreturn]] void broken(const std::string& what) { throw RuntimeError("mission accounting (internal error)", what); }

}  // namespace

const char* goal_state_name(GoalState s) {
  switch (s) {
    case GoalState::kPending: return "pending";
    case GoalState::kCarried: return "carried";
    case GoalState::kDelivered: return "delivered";
    case GoalState::kExpired: return "expired";
    case GoalState::kDropped: return "dropped_overflow";
    case GoalState::kLostWithAgent: return "lost_with_agent";
    case GoalState::kUnreachable: return "unreachable";
  }
  return "?";
}

std::vector<CycleStats> account(const std::vector<GoalRecord>& goals, int cycles, double period) {
  std::vector<Event> events;
  events.reserve(goals.size() * 4);
  for (std::size_t i = 0; i < goals.size(); ++i) {
    const GoalRecord& g = goals[i];
    const int id = static_cast<int>(i);
    if (g.id != GoalId(id)) broken("goal ids are not their index");
    if (g.cycle < 0 || g.cycle >= cycles) broken("goal " + std::to_string(id) + " of cycle " + std::to_string(g.cycle));
    events.push_back({g.requested_at, kRequest, id});
    if (g.measured_at >= 0) events.push_back({g.measured_at, kMeasure, id});
    if (g.picked_up_at >= 0) events.push_back({g.picked_up_at, kPickup, id});
    if (g.delivered_at >= 0) events.push_back({g.delivered_at, kDeliver, id});
    if (g.expired_at >= 0) events.push_back({g.expired_at, kExpire, id});
    if (g.dropped_at >= 0) events.push_back({g.dropped_at, kDrop, id});
    if (g.lost_at >= 0) events.push_back({g.lost_at, kLose, id});
    if (g.unreachable_at >= 0) events.push_back({g.unreachable_at, kUnreach, id});
    if (g.measured_at >= 0 && g.expired_at >= 0) broken("goal " + std::to_string(id) + " both measured and expired");
    if (g.measured_at >= 0 && g.measured_at > g.deadline + 1e-9)
      broken("goal " + std::to_string(id) + " measured at " + std::to_string(g.measured_at) + " s by " +
             to_string(g.measured_by) + ", after its deadline " + std::to_string(g.deadline) + " s");
  }
  std::sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
    if (a.t != b.t) return a.t < b.t;
    if (a.kind != b.kind) return a.kind < b.kind;
    return a.goal < b.goal;
  });
  std::vector<uint8_t> where(goals.size(), kNone);
  int requested = 0, pending = 0, on_workers = 0, on_collectors = 0, delivered = 0, expired = 0, dropped = 0, lost = 0,
      unreachable = 0;
  auto move = [&](const Event& e) {
    uint8_t& w = where[static_cast<std::size_t>(e.goal)];
    const std::string id = "goal " + std::to_string(e.goal);
    switch (e.kind) {
      case kRequest:
        if (w != kNone) broken(id + " requested twice");
        w = kPendingAt, ++requested, ++pending;
        break;
      case kMeasure:
        if (w != kPendingAt) broken(id + " measured while not pending");
        w = kWorker, --pending, ++on_workers;
        break;
      case kPickup:
        if (w != kWorker) broken(id + " picked up while not on a worker");
        w = kCollector, --on_workers, ++on_collectors;
        break;
      case kDeliver:
        if (w == kDeliveredAt) broken(id + " delivered twice");
        if (w != kWorker && w != kCollector) broken(id + " delivered while not carried");
        (w == kWorker ? on_workers : on_collectors)--, ++delivered, w = kDeliveredAt;
        break;
      case kExpire:
        if (w != kPendingAt) broken(id + " expired while not pending");
        w = kExpiredAt, --pending, ++expired;
        break;
      case kUnreach:
        if (w != kPendingAt) broken(id + " given up as unreachable while not pending");
        w = kUnreachableAt, --pending, ++unreachable;
        break;
      case kDrop:
        if (w != kWorker && w != kCollector) broken(id + " dropped while not carried");
        (w == kWorker ? on_workers : on_collectors)--, ++dropped, w = kDroppedAt;
        break;
      case kLose:
        if (w != kPendingAt && w != kWorker && w != kCollector) broken(id + " lost while not pending or carried");
        (w == kPendingAt ? pending : w == kWorker ? on_workers : on_collectors)--, ++lost, w = kLostAt;
        break;
    }
  };
  // Conservation, and the counters against a recount of the goals' states.
  auto check = [&](const std::string& when) {
    const int carried = on_workers + on_collectors;
    if (requested != delivered + carried + pending + expired + dropped + lost + unreachable)
      broken(when + ": requested " + std::to_string(requested) + " != delivered " + std::to_string(delivered) +
             " + carried " + std::to_string(carried) + " + pending " + std::to_string(pending) + " + expired " +
             std::to_string(expired) + " + dropped " + std::to_string(dropped) + " + lost " + std::to_string(lost) +
             " + unreachable " + std::to_string(unreachable));
    int n[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (uint8_t w : where) ++n[w];
    if (n[kPendingAt] != pending || n[kWorker] != on_workers || n[kCollector] != on_collectors ||
        n[kDeliveredAt] != delivered || n[kExpiredAt] != expired || n[kDroppedAt] != dropped || n[kLostAt] != lost ||
        n[kUnreachableAt] != unreachable)
      broken(when + ": counters disagree with the goals' states");
  };

  std::vector<CycleStats> out(static_cast<std::size_t>(cycles));
  std::size_t next = 0;
  for (int c = 0; c < cycles; ++c) {
    const double end = (c + 1) * period;
    while (next < events.size() && (events[next].t < end || (events[next].t == end && events[next].kind == kExpire)))
      move(events[next++]);
    check("cycle " + std::to_string(c));
    CycleStats& s = out[static_cast<std::size_t>(c)];
    s.cycle = c;
    s.requested_at = c * period;
    s.total_requested = requested, s.total_delivered = delivered, s.total_carried = on_workers + on_collectors;
    s.total_pending = pending, s.total_expired = expired, s.total_dropped = dropped, s.total_lost = lost;
    s.total_unreachable = unreachable;
  }
  while (next < events.size()) move(events[next++]);
  check("end of run");
  for (const GoalRecord& g : goals) {
    if ((g.lost_at >= 0) != (g.state == GoalState::kLostWithAgent))
      broken(to_string(g.id) + " has a lost_at but is " + goal_state_name(g.state));
    if ((g.unreachable_at >= 0) != (g.state == GoalState::kUnreachable))
      broken(to_string(g.id) + " has an unreachable_at but is " + goal_state_name(g.state));
  }
  if (pending != 0 || on_workers + on_collectors != 0)
    broken("end of run: " + std::to_string(pending) + " goals pending and " +
           std::to_string(on_workers + on_collectors) + " still carried (data must never be dropped)");
  for (const GoalRecord& g : goals) {
    CycleStats& s = out[static_cast<std::size_t>(g.cycle)];
    ++s.requested;
    if (g.delivered_at >= 0) {
      const double r = g.delivered_at - g.requested_at;
      ++s.delivered, s.refresh_mean_s += r, s.refresh_max_s = std::max(s.refresh_max_s, r);
    } else if (g.dropped_at >= 0) {
      ++s.dropped;
    } else if (g.lost_at >= 0) {
      ++s.lost;
    } else if (g.unreachable_at >= 0) {
      ++s.unreachable;
    } else {
      ++s.expired;
    }
  }
  for (CycleStats& s : out)
    if (s.delivered > 0) s.refresh_mean_s /= s.delivered;
  return out;
}

int64_t area_of(Point2 p, double tile) {
  if (!(tile > 0)) return -1;
  const int64_t col = static_cast<int64_t>(std::floor(p.x / tile)), row = static_cast<int64_t>(std::floor(p.y / tile));
  return row * (int64_t{1} << 31) + col;
}

AreaWeights area_weights(const World& world, double tile) {
  AreaWeights w;
  w.tile = tile;
  if (!(tile > 0)) return w;
  const OccupancyGrid& grid = world.scenario.grid;
  // Neighbouring cells of a row mostly share a tile: look it up only when it changes.
  int64_t last = -1;
  double* area = nullptr;
  for (std::size_t i = 0; i < world.reachable.size(); ++i) {
    if (!world.reachable[i]) continue;
    const int64_t a = area_of(grid.cell_center(grid.cell(i)), tile);
    if (!area || a != last) last = a, area = &w.area[a];
    *area += grid.cell_area();
  }
  return w;
}

std::pair<double, double> interval_stats(const std::vector<GoalRecord>& goals, int cycles, double period,
                                         const AreaWeights& areas) {
  const double horizon = std::max(1, cycles) * period;
  std::map<int64_t, std::vector<double>> deliveries;  // area -> delivery times
  for (const auto& [area, m2] : areas.area) deliveries[area];
  for (const GoalRecord& g : goals) {
    if (g.delivered_at < 0) continue;
    const auto it = deliveries.find(area_of(g.point, areas.tile));
    if (it != deliveries.end()) it->second.push_back(g.delivered_at);
  }
  if (deliveries.empty()) return {0.0, 0.0};
  double sum = 0.0, weights = 0.0, max = 0.0;
  for (auto& [area, d] : deliveries) {
    const double weight = areas.area.at(area);
    std::sort(d.begin(), d.end());
    int n = 0;  // distinct deliveries
    for (std::size_t i = 0; i < d.size(); ++i) n += i == 0 || d[i] - d[i - 1] > 1e-3;
    const double interval = n >= 2 ? (d.back() - d.front()) / (n - 1) : horizon;
    sum += weight * interval, weights += weight, max = std::max(max, interval);
  }
  return {sum / weights, max};
}

}  // namespace mission
}  // namespace gather
