#pragma once
// The in-process mission simulator (seed sec. 3.2, Fig. 3 R, Fig. 4): executes
// a plan cycle after cycle and measures what the planner estimated (refresh
// time, goals delivered per cycle). Deterministic for a seed. The model is
// documented in docs/simulator.md.
//
// Why per-agent analytic timelines and not a fixed time step: agents do not
// interact except at rendezvous, and a collector's position is a closed-form
// function of time (RouteTimetable). So each worker's timeline is computed
// exactly, decision point after decision point (travel times are FMM geodesic
// lengths / speed, meetings are the collector's exact pass times), and the
// resulting per-goal events are then replayed in time order for the
// accounting and its conservation check. No time-step error, and the cost is
// a few FMM marches per decision instead of one update per agent per tick.
#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/mission/route_timetable.hpp"
#include "gather_core/mission/worker_policy.hpp"
#include "gather_core/mission/world.hpp"
#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace mission {

// kLostWithAgent: the agent runtime's OC declared dead an agent that had
// the goal (its worker, or its worker's collector) and no survivor resolved
// it since (docs/faults.md). kUnreachable: its worker's robot could not
// reach it (its navigation gave up; docs/robots.md).
enum class GoalState : uint8_t { kPending, kCarried, kDelivered, kExpired, kDropped, kLostWithAgent, kUnreachable };
const char* goal_state_name(GoalState s);

struct GoalRecord {
  GoalId id;
  int cycle = 0;              // the request it belongs to
  Point2 point;               // [m] (a cell centre)
  SegmentId segment;          // of the goal's cell; none: in no segment (never measured, expires)
  AgentId worker;             // the segment's worker
  double requested_at = 0.0;  // [s]
  double deadline = 0.0;      // [s] the next request: unmeasured by then = expired
  double measured_at = -1.0;  // [s], -1 = never
  AgentId measured_by;
  double picked_up_at = -1.0;             // [s] handed to a collector, -1 = never (OC workers deliver themselves)
  AgentId picked_up_by;                   // the collector's agent
  double delivered_at = -1.0;             // [s] inside the OC's coverage, -1 = never
  AgentId delivered_by;                   // agent that brought it into coverage
  double expired_at = -1.0;               // [s] = deadline when never measured
  double dropped_at = -1.0;               // [s] measured, but no buffer had room for its data (agent runtime only)
  double lost_at = -1.0;                  // [s] declared lost with a dead agent (agent runtime only)
  double unreachable_at = -1.0;           // [s] its worker's robot gave it up (agent runtime only)
  GoalState state = GoalState::kPending;  // at the end of the run
};

struct CycleStats {
  int cycle = 0;
  double requested_at = 0.0;  // [s]
  int requested = 0;          // goals of this request
  // Goals of this request delivered (at any time of the run) and their
  // refresh times delivered_at - requested_at [s] (0 when none).
  int delivered = 0;
  double refresh_mean_s = 0.0, refresh_max_s = 0.0;
  int expired = 0;      // goals of this request never measured
  int dropped = 0;      // goals of this request measured and dropped (no room in a buffer)
  int lost = 0;         // goals of this request lost with a dead agent
  int unreachable = 0;  // goals of this request its worker's robot could not reach
  // Snapshot of all goals requested so far at the end of the cycle
  // (t = requested_at + period), as checked for conservation.
  int total_requested = 0, total_delivered = 0, total_carried = 0, total_pending = 0, total_expired = 0,
      total_dropped = 0, total_lost = 0, total_unreachable = 0;
};

// One straight-in-time leg of an agent: it moves from `from` to `to` along
// the FMM geodesic during [t0, t1] (t1 = t0 + length / speed) and then stays
// at `to` until the next leg starts. Collectors have none (see RouteTimetable).
struct Leg {
  AgentId agent;
  double t0 = 0.0, t1 = 0.0;  // [s]
  Point2 from, to;            // [m]
  bool to_goal = false;       // it ends where the agent measures a goal (else: commuting)
};

// Where an agent's time went over [0, horizon] (the requests' span,
// cycles x period): workers measure (walking to their goals, from wherever
// they are), commute (to a pass, a meeting point, the coverage) or wait;
// collectors drive their route (commuting) or wait at the OC.
struct TimeBudget {
  AgentId agent;
  const char* role = "";  // "collector", "collector_worker" or "oc_worker"
  double measuring_s = 0.0, commuting_s = 0.0, waiting_s = 0.0;
};

struct MissionOptions {
  int cycles = 10;
  unsigned seed = 1;
  int goals_per_request = -1;  // -1: the scenario's mission.goals_per_request
  // Tests: fixed goals (cycle, point [m]) instead of random ones.
  std::vector<std::pair<int, Point2>> fixed_goals;
  // [s] between two radio link checks of a walking or waiting worker (the
  // simulator's stand-in for an agent's check every tick), range [0.01, 10].
  double link_probe_s = 1.0;
};

struct MissionResult {
  std::vector<GoalRecord> goals;
  std::vector<CycleStats> cycles;
  std::vector<Leg> legs;
  double period_s = 0.0;        // request period
  double mission_s = 0.0;       // cycles * period [s]
  double end_s = 0.0;           // last event (data still carried at the last request is delivered)
  double refresh_mean_s = 0.0;  // latency: delivered_at - requested_at, mean over all delivered goals
  double refresh_max_s = 0.0;
  // interval: per area (a square tile of the map) the time between
  // consecutive deliveries of its data to the OC (interval_stats); the mean
  // over areas of each area's mean, and the largest area mean.
  double interval_mean_s = 0.0;
  double interval_max_s = 0.0;
  double goals_per_cycle = 0.0;  // delivered / cycles
  // How every goal ended (they add up to the goals requested).
  int delivered = 0, expired = 0, dropped = 0, lost_with_agent = 0, unreachable = 0;
  double wall_ms = 0.0;
  double speedup() const { return wall_ms > 0 ? mission_s * 1000.0 / wall_ms : 0.0; }
};

// The areas whose refresh interval is measured: square tiles of side
// `tile` [m] in the map frame (floor(x / tile), floor(y / tile)), the same
// for every configuration of a scenario (plan.yaml's area_tile_m, chosen by
// the planner: sqrt(reachable area / team size)). -1 when tile <= 0.
int64_t area_of(Point2 p, double tile);

// The areas of a world: reachable area [m^2] of every tile of side `tile`
// that holds reachable space.
struct AreaWeights {
  double tile = 0.0;               // [m]
  std::map<int64_t, double> area;  // area_of -> [m^2]
};
AreaWeights area_weights(const World& world, double tile);

class MissionSimulator {
 public:
  // Keeps references to ctx (and its scenario). Throws gather::Error when the
  // plan does not fit the scenario (label image size, roles, routes) or
  // `protocol` is out of its ranges. The agents compared with this simulator
  // must run with the same `protocol`.
  MissionSimulator(const World& ctx, MissionPlan plan, const ProtocolParams& protocol = {});
  ~MissionSimulator();

  // Runs `options.cycles` requests and drains the data measured meanwhile.
  // Throws gather::Error if the accounting breaks its invariants (a bug).
  MissionResult run(const MissionOptions& options);

  const MissionPlan& plan() const { return plan_; }
  // Each agent's time budget in `result` (a run of this simulator).
  std::vector<TimeBudget> time_budgets(const MissionResult& result) const;
  const RouteTimetable& route(CollectorId collector) const { return routes_[collector]; }
  // The decisions of worker `agent` (nullptr for a collector or no such agent).
  const WorkerPolicy* worker(AgentId agent) const {
    for (const WorkerPolicy& w : workers_)
      if (w.agent() == agent) return &w;
    return nullptr;
  }

 private:
  struct Run;
  void simulate_collector_worker(std::size_t w, Run& run);
  void simulate_oc_worker(std::size_t w, Run& run);

  const World& ctx_;
  MissionPlan plan_;
  double speed_ = 1.0;
  double period_ = 1.0;
  RadioModel radio_;
  PerCollector<RouteTimetable> routes_;
  PerCollector<AgentId> collector_agents_;  // who drives each collector (mission::collector_agents)
  std::unique_ptr<SharedDistances> shared_;
  std::vector<WorkerPolicy> workers_;  // the decisions of each worker, shared with the agents' worker role
  AreaWeights areas_;                  // of the refresh interval
};

// The refresh interval of a run (docs/simulator.md, "Metrics"): the areas
// are the tiles of `areas`; an area's deliveries are the distinct times at
// which goals of it reached the OC (times closer than 1 ms are one
// delivery); its interval is the mean gap between consecutive deliveries,
// or the whole mission (cycles x period) when it had fewer than two.
// `period` [s] between requests. Returns [s] {the mean over the areas
// weighted by their reachable area (the
// interval at a random point of the reachable space: a sliver of a tile at
// a wall weighs little), the largest area interval}.
std::pair<double, double> interval_stats(const std::vector<GoalRecord>& goals, int cycles, double period,
                                         const AreaWeights& areas);

// Replays the goals' timestamps in time order, checks that every transition
// is legal (pending -> carried -> delivered, pending -> expired, carried ->
// dropped, pending or carried -> lost with an agent, pending -> unreachable;
// never twice) and that requested = delivered + carried + pending + expired
// + dropped + lost + unreachable at the end of every cycle and at the end of
// the run, and
// returns the per-cycle stats (requests every `period` [s]).
// Throws gather::Error on any violation.
std::vector<CycleStats> account(const std::vector<GoalRecord>& goals, int cycles, double period);

// The goal records a command keeps at once (docs/input_limits.md, "Memory
// and time"): a run holds every goal's record and its goals.csv row, about
// 300 bytes a goal (gather sim on maps/office, 100 and 1000 cycles), beside
// the workers' tables of goals x goals (at most 200 MB at 5000 goals a request).
constexpr long long kMaxGoalRecords = 1000000;
// Throws gather::Error(where, ...) naming the fields to lower when
// goals_per_request x cycles x runs is over kMaxGoalRecords (before anything
// is simulated).
void check_goal_budget(long long goals_per_request, long long cycles, long long runs, const std::string& where);

}  // namespace mission
}  // namespace gather
