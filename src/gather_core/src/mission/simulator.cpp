// The analytic mission simulator (MissionSimulator): each worker's timeline
// computed event by event (a worker of a collector, a worker of the OC),
// with the decisions of mission::WorkerPolicy and the collectors'
// RouteTimetable, and the time budgets. Goal generation is mission/requests,
// the distances mission/world and mission/segment_window. Just over 400
// lines: the two timelines are one concept and read best side by side.
#include "gather_core/mission/simulator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <tuple>

#include "gather_core/error.hpp"
#include "gather_core/mission/mission_csv.hpp"
#include "gather_core/mission/requests.hpp"
#include "mission_internal.hpp"

namespace gather {
namespace mission {
namespace {

constexpr int kMaxDecisions = 1000000;  // per worker: a loop that long is a bug

}  // namespace

// State of one run shared by the workers' timelines.
struct MissionSimulator::Run {
  int cycles = 0;
  double link_probe_s = 1.0;  // MissionOptions::link_probe_s
  std::vector<GoalRecord> goals;
  std::vector<std::vector<std::vector<GoalId>>> goals_of;  // [worker index][cycle] its goals
  std::vector<Leg> legs;
  std::vector<KnownGoal> scratch;  // a request as a worker learns it
};

namespace {

// Drops from `known` (local goal indices of the policy's request) the goals
// whose deadline has passed at t [s].
void drop_expired(std::vector<int>& known, const WorkerPolicy& p, double t) {
  known.erase(std::remove_if(known.begin(), known.end(),
                             [&](int i) { return p.goal(static_cast<std::size_t>(i)).deadline <= t + kEps; }),
              known.end());
}

// The worker learns request `ids` (goal ids of its segment) from the run's records.
void learn(WorkerPolicy& p, const std::vector<GoalRecord>& goals, const std::vector<GoalId>& ids,
           const OccupancyGrid& grid, std::vector<KnownGoal>& scratch, std::vector<int>& known) {
  scratch.clear();
  for (GoalId id : ids) {
    const GoalRecord& g = goals[id.index()];
    scratch.push_back(KnownGoal{g.id, grid.world_to_cell(g.point), g.deadline});
  }
  p.learn(scratch.data(), scratch.size());
  known.clear();
  for (std::size_t i = 0; i < scratch.size(); ++i) known.push_back(static_cast<int>(i));
}

}  // namespace

MissionSimulator::~MissionSimulator() = default;

MissionSimulator::MissionSimulator(const World& ctx, MissionPlan plan, const ProtocolParams& protocol)
    : ctx_(ctx), plan_(std::move(plan)), radio_(ctx.scenario.grid, ctx.scenario.radio) {
  const Scenario& s = ctx.scenario;
  const OccupancyGrid& grid = s.grid;
  const plan::PlanFile& pf = plan_.file;
  const std::string where = plan_.source.empty() ? "plan" : plan_.source;
  check_plan(plan_, static_cast<int>(pf.agents.size()), grid);
  plan_.labels.reframe(grid.frame());
  speed_ = s.team.speed;
  period_ = pf.cycle_period_s;
  areas_ = area_weights(ctx, pf.area_tile_m);
  for (const plan::CollectorRoute& r : pf.routes) {
    try {
      routes_.emplace_back(r, speed_, period_, ctx.coverage);
    } catch (const Error& e) {
      throw Error(where, e.what());
    }
  }
  collector_agents_ = collector_agents(pf);
  shared_ = std::make_unique<SharedDistances>(ctx);
  // Each worker's goal tables are sized in run() by the most goals a request
  // gives it (a table of goals x goals: sized by goals_per_request, all the
  // workers' together took gigabytes at a few thousand goals).
  for (const plan::AgentAssignment& a : pf.agents) {
    if (a.collector) continue;
    const RouteTimetable* route = a.delivers_to.valid() ? &routes_[a.delivers_to] : nullptr;
    workers_.emplace_back(ctx, plan_, a, route, *shared_, 0, protocol);
  }
}

MissionResult MissionSimulator::run(const MissionOptions& opt) {
  const auto t_start = std::chrono::steady_clock::now();
  if (opt.cycles < 1) throw Error("mission", "cycles must be >= 1");
  require_in_range(opt.link_probe_s, 0.01, 10, "mission options", "link_probe_s", " s");
  const OccupancyGrid& grid = ctx_.scenario.grid;
  Run run;
  run.cycles = opt.cycles;
  run.link_probe_s = opt.link_probe_s;
  run.goals_of.assign(workers_.size(), std::vector<std::vector<GoalId>>(static_cast<std::size_t>(opt.cycles)));
  PerSegment<int> worker_of_segment(plan_.file.workers, -1);
  for (std::size_t i = 0; i < workers_.size(); ++i) worker_of_segment[workers_[i].segment()] = static_cast<int>(i);
  auto add_goal = [&](int cycle, Cell cell) {
    GoalRecord g;
    g.id = GoalId::at_index(run.goals.size());
    g.cycle = cycle;
    g.point = grid.cell_center(cell);
    g.segment = SegmentId(plan_.labels[grid.index(cell)]);
    g.requested_at = cycle * period_;
    g.deadline = (cycle + 1) * period_;
    const int wi = g.segment.valid() ? worker_of_segment[g.segment] : -1;
    if (wi >= 0) {
      g.worker = workers_[static_cast<std::size_t>(wi)].agent();
      run.goals_of[static_cast<std::size_t>(wi)][static_cast<std::size_t>(cycle)].push_back(g.id);
    }
    run.goals.push_back(g);
  };
  if (!opt.fixed_goals.empty()) {
    for (int c = 0; c < opt.cycles; ++c)
      for (const auto& fg : opt.fixed_goals) {
        if (fg.first != c) continue;
        const Cell cell = grid.world_to_cell(fg.second);
        if (!grid.contains(cell) || !ctx_.reachable[grid.index(cell)])
          throw Error("mission", "fixed goal off the reachable space");
        add_goal(c, cell);
      }
  } else {
    const int per_request =
        opt.goals_per_request >= 0 ? opt.goals_per_request : ctx_.scenario.mission.goals_per_request;
    for (const DrawnGoal& g : draw_goals(ctx_, opt.seed, opt.cycles, per_request)) add_goal(g.cycle, g.cell);
  }

  for (std::size_t w = 0; w < workers_.size(); ++w) {
    std::size_t most = 0;
    for (const auto& ids : run.goals_of[w]) most = std::max(most, ids.size());
    workers_[w].reserve(most);
    if (workers_[w].delivers_to_oc())
      simulate_oc_worker(w, run);
    else
      simulate_collector_worker(w, run);
  }
  for (GoalRecord& g : run.goals) {
    if (g.measured_at < 0 && !std::isfinite(g.deadline)) bug(to_string(g.id) + " neither measured nor expired");
    if (g.measured_at < 0)
      g.expired_at = g.deadline, g.state = GoalState::kExpired;
    else
      g.state = g.delivered_at >= 0 ? GoalState::kDelivered : GoalState::kCarried;
  }

  std::vector<Leg> legs = std::move(run.legs);
  MissionResult res = mission_result(std::move(run.goals), opt.cycles, period_, 0.0, areas_);
  res.legs = std::move(legs);
  res.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
  return res;
}

void MissionSimulator::simulate_collector_worker(std::size_t wi, Run& run) {
  WorkerPolicy& w = workers_[wi];
  const OccupancyGrid& grid = ctx_.scenario.grid;
  const RouteTimetable& route = *w.route();
  const auto& mine = run.goals_of[wi];
  // A request's goals expire one period after it reached the worker, or when
  // the next request reaches it (it supersedes them): request_deadline;
  // requests that arrive together leave only the newest.
  for (int c = 0; c < run.cycles; ++c) {
    const double until = w.deadline(c, period_);
    for (GoalId id : mine[static_cast<std::size_t>(c)]) run.goals[id.index()].deadline = until;
  }

  Cell pos = ctx_.oc_cell;
  double t = 0.0;
  int next_req = 0;
  std::vector<int> known;       // local indices of unmeasured goals of the current request
  std::vector<GoalId> carried;  // measured and not yet handed over
  const AgentId collector = collector_agents_[w.collector()];
  int at_rv = -1;                  // the rendezvous the worker stands at, -1 elsewhere
  bool at_meeting = false;         // it stands at its meeting point
  double no_meeting_before = 0.0;  // [s] after a failed hand-over: the next try is a later pass
  // Everything carried goes to the collector at t; it drops it at its next
  // time inside the OC's coverage.
  auto hand_over = [&](double at) {
    const double drop = route.next_coverage_time(at);
    for (GoalId id : carried) {
      GoalRecord& g = run.goals[id.index()];
      if (g.picked_up_at >= 0 || g.delivered_at >= 0) bug(to_string(id) + " handed over twice");
      g.picked_up_at = at, g.picked_up_by = collector;
      g.delivered_at = drop, g.delivered_by = collector;
    }
    carried.clear();
  };
  // The collector also takes the data whenever the radio link holds on the
  // way (not only at the planned pass): probed every MissionOptions::link_probe_s while
  // the worker walks from `from` to `to` during [t0, t1] or waits (from ==
  // to); its position along a walk is interpolated on the straight line. A
  // hand-over of n goals needs the link to hold for transfer_s(n) from when
  // it came up with data on board (goals measured meanwhile join it): the
  // link's start is carried from one walk to the next while it holds.
  const double link_range = radio_.free_space_range();
  double link_since = -1.0;    // [s] the current contact with data began (-1: none)
  double probed_until = -1.0;  // [s] the last probe (link_since is valid only from there on)
  // Returns the time of the pick-up, or -1 if it did not happen during [t0, t1].
  auto pick_up_on_the_way = [&](Point2 from, Point2 to, double t0, double t1) -> double {
    if (std::abs(t0 - probed_until) > kEps) link_since = -1.0;
    probed_until = t1;
    if (carried.empty() || !(t1 >= t0)) {
      link_since = -1.0;
      return -1.0;
    }
    auto linked_at = [&](double when) {
      const double f = t1 > t0 ? (when - t0) / (t1 - t0) : 0.0;
      const Point2 p{from.x + f * (to.x - from.x), from.y + f * (to.y - from.y)};
      const Point2 c = route.position(when);
      return std::hypot(p.x - c.x, p.y - c.y) <= link_range && radio_.linked(p, c);
    };
    const double need = transfer_s(ctx_.scenario, carried.size());
    const int steps = std::max(1, static_cast<int>(std::ceil((t1 - t0) / run.link_probe_s)));
    for (int i = 0; i <= steps; ++i) {
      const double at = t0 + (t1 - t0) * i / steps;
      if (!linked_at(at)) {
        link_since = -1.0;
        continue;
      }
      if (link_since < 0) {
        link_since = at;
        if (i > 0) {  // the link came up between two probes: find when, to 1e-4 s
          double lo = t0 + (t1 - t0) * (i - 1) / steps;
          while (link_since - lo > 1e-4) {
            const double mid = 0.5 * (lo + link_since);
            (linked_at(mid) ? link_since : lo) = mid;
          }
        }
      }
      const double done = std::max(link_since + need, t0);
      if (done <= at + kEps) {
        hand_over(done);
        link_since = -1.0;
        return done;
      }
    }
    return -1.0;
  };
  for (int step = 0;; ++step) {
    if (step > kMaxDecisions) bug("worker " + std::to_string(w.agent().value()) + " does not terminate");
    drop_expired(known, w, t);
    while (next_req < run.cycles && w.learn_time(next_req, period_) <= t + kEps) {
      // Older goals are past their deadline by now (learn time >= request time).
      learn(w, run.goals, mine[static_cast<std::size_t>(next_req)], grid, run.scratch, known);
      ++next_req;
    }
    const WorkerPolicy::Decision dec = w.decide(Spot{pos, at_rv, false, at_meeting}, t, known.data(), known.size(),
                                                carried.size(), next_req < run.cycles, no_meeting_before);
    if (dec.action == WorkerPolicy::Action::kDone) break;
    if (dec.action == WorkerPolicy::Action::kGoToRendezvous) {
      const Cell to = w.rendezvous()[static_cast<std::size_t>(dec.rendezvous)];
      run.legs.push_back(Leg{w.agent(), t, dec.arrive, grid.cell_center(pos), grid.cell_center(to)});
      t = dec.arrive, pos = to, at_rv = dec.rendezvous, at_meeting = false;
      continue;
    }
    if (dec.action == WorkerPolicy::Action::kGoToMeeting) {
      run.legs.push_back(Leg{w.agent(), t, dec.arrive, grid.cell_center(pos), grid.cell_center(dec.landing)});
      t = dec.arrive, pos = dec.landing, at_rv = -1, at_meeting = true;
      continue;
    }
    if (dec.action == WorkerPolicy::Action::kWait) {
      t = std::max(t, w.learn_time(next_req, period_));
      continue;
    }
    // Execute: measure k goals, go to the pass, wait for the collector.
    Point2 here = grid.cell_center(pos);
    double clock = t;
    for (std::size_t i = 0; i < dec.k; ++i) {
      const int o = dec.tour[i];
      GoalRecord& g = run.goals[w.goal(static_cast<std::size_t>(o)).id.index()];
      if (g.measured_at >= 0) bug(to_string(g.id) + " measured twice");
      g.measured_at = dec.at[i], g.measured_by = w.agent();
      run.legs.push_back(Leg{w.agent(), clock, dec.at[i], here, g.point, true});
      pick_up_on_the_way(here, g.point, clock, dec.at[i]);
      here = g.point, clock = dec.at[i];
      carried.push_back(g.id);
      known.erase(std::find(known.begin(), known.end(), o));
    }
    const Point2 meet_point = grid.cell_center(w.rendezvous()[static_cast<std::size_t>(dec.rendezvous)]);
    const double arrive = dec.arrive;
    run.legs.push_back(Leg{w.agent(), clock, arrive, here, meet_point});
    pick_up_on_the_way(here, meet_point, clock, arrive);
    // Wait there for the hand-over, at most until the pass's link window ends.
    const double taken = pick_up_on_the_way(meet_point, meet_point, arrive, std::max(arrive, dec.link_until));
    pos = w.rendezvous()[static_cast<std::size_t>(dec.rendezvous)];
    at_rv = dec.rendezvous;
    at_meeting = false;
    if (carried.empty()) {
      // Taken (on the way or there): decide again as soon as the data is gone.
      t = std::max(arrive, taken);
    } else {
      t = std::max(arrive, dec.link_until);
      no_meeting_before = t + 1.0;  // the worker keeps its data for a later pass
    }
  }
}

void MissionSimulator::simulate_oc_worker(std::size_t wi, Run& run) {
  WorkerPolicy& w = workers_[wi];
  const OccupancyGrid& grid = ctx_.scenario.grid;
  const auto& mine = run.goals_of[wi];
  // Its goals stay valid for one period after the worker learned the request
  // (in the coverage), or until it learns a newer one: request_deadline; it
  // measures what it can in time, then comes back.
  for (const auto& ids : mine)
    for (GoalId id : ids) run.goals[id.index()].deadline = kInf;

  Cell pos = ctx_.oc_cell;
  double t = 0.0;
  int next_req = 0;
  std::vector<int> known;  // local indices of unmeasured goals of the current request
  std::vector<GoalId> carried;
  bool at_landing = false;  // pos is where the worker came back into the coverage
  auto deliver = [&]() {
    for (GoalId id : carried) {
      GoalRecord& g = run.goals[id.index()];
      if (g.delivered_at >= 0) bug(to_string(id) + " delivered twice");
      g.delivered_at = t, g.delivered_by = w.agent();
    }
    carried.clear();
  };
  auto back_to_coverage = [&]() {
    const auto [to, dist] = w.way_back(pos);
    run.legs.push_back(Leg{w.agent(), t, t + dist / speed_, grid.cell_center(pos), grid.cell_center(to)});
    t += dist / speed_, pos = to;
    at_landing = true;
  };
  for (int step = 0;; ++step) {
    if (step > kMaxDecisions) bug("worker " + std::to_string(w.agent().value()) + " does not terminate");
    drop_expired(known, w, t);
    if (ctx_.covered(pos)) {
      deliver();
      while (next_req < run.cycles && next_req * period_ <= t + kEps) {
        // The newer request supersedes what is left of the older one.
        for (int i : known) run.goals[w.goal(static_cast<std::size_t>(i)).id.index()].deadline = t;
        for (GoalId id : mine[static_cast<std::size_t>(next_req)])
          run.goals[id.index()].deadline = request_deadline(t, kInf, period_);
        learn(w, run.goals, mine[static_cast<std::size_t>(next_req)], grid, run.scratch, known);
        ++next_req;
      }
    }
    const WorkerPolicy::Decision dec =
        w.decide(Spot{pos, -1, at_landing}, t, known.data(), known.size(), carried.size(), next_req < run.cycles);
    if (dec.action == WorkerPolicy::Action::kDone) break;
    if (dec.action == WorkerPolicy::Action::kBackToCoverage) {
      back_to_coverage();
      continue;
    }
    if (dec.action == WorkerPolicy::Action::kGoToMeeting) {  // home, in the coverage
      run.legs.push_back(Leg{w.agent(), t, dec.arrive, grid.cell_center(pos), grid.cell_center(dec.landing)});
      t = dec.arrive, pos = dec.landing, at_landing = true;
      continue;
    }
    if (dec.action == WorkerPolicy::Action::kWait) {
      t = std::max(t, next_req * period_);
      continue;
    }
    // Measure every goal that can still be measured in time, then go back.
    Point2 here = grid.cell_center(pos);
    for (std::size_t i = 0; i < dec.k; ++i) {
      const int o = dec.tour[i];
      GoalRecord& g = run.goals[w.goal(static_cast<std::size_t>(o)).id.index()];
      if (g.measured_at >= 0) bug(to_string(g.id) + " measured twice");
      g.measured_at = dec.at[i], g.measured_by = w.agent();
      run.legs.push_back(Leg{w.agent(), t, dec.at[i], here, g.point, true});
      here = g.point, t = dec.at[i], pos = w.goal(static_cast<std::size_t>(o)).cell, at_landing = false;
      carried.push_back(g.id);
      known.erase(std::find(known.begin(), known.end(), o));
      if (ctx_.covered(pos)) deliver();  // measured inside the coverage: the OC hears it at once
    }
    if (!ctx_.covered(pos)) back_to_coverage();
  }
}

std::vector<TimeBudget> MissionSimulator::time_budgets(const MissionResult& result) const {
  const double horizon = result.mission_s;
  // The workers' legs, summed in one pass: [agent] = {measuring, commuting}.
  PerAgent<std::pair<double, double>> walked(plan_.file.agents.count(), {0.0, 0.0});
  for (const Leg& l : result.legs) {
    if (!l.agent.within(walked.count()) || l.t0 >= horizon) continue;
    const double d = std::max(0.0, std::min(l.t1, horizon) - l.t0);
    (l.to_goal ? walked[l.agent].first : walked[l.agent].second) += d;
  }
  std::vector<TimeBudget> out;
  for (const auto& a : plan_.file.agents) {
    TimeBudget b;
    b.agent = a.id;
    if (a.collector) {
      b.role = "collector";
      // Driving: the loops of the timetable that fall in [0, horizon].
      // (Stepping half a loop past a departure always reaches the next one.)
      const plan::LoopSchedule& s = routes_[a.delivers_to].schedule();
      if (!s.idle())
        for (double t = s.next_departure(0.0); t < horizon; t = s.next_departure(t + 0.5 * s.travel()))
          b.commuting_s += std::min(s.travel(), horizon - t);
    } else {
      b.role = a.delivers_to.valid() ? "collector_worker" : "oc_worker";
      if (a.id.within(walked.count())) std::tie(b.measuring_s, b.commuting_s) = walked[a.id];
    }
    b.waiting_s = std::max(0.0, horizon - b.measuring_s - b.commuting_s);
    out.push_back(b);
  }
  return out;
}

void check_goal_budget(long long goals_per_request, long long cycles, long long runs, const std::string& where) {
  const long long records =
      goals_per_request * cycles * runs;  // at most 5000 x 100000 x 1000 (their ranges): no overflow
  if (records <= kMaxGoalRecords) return;
  throw Error(where, "mission.goals_per_request x cycles x runs = " + std::to_string(goals_per_request) + " x " +
                         std::to_string(cycles) + " x " + std::to_string(runs) + " = " + std::to_string(records) +
                         " goal records, over the budget of " + std::to_string(kMaxGoalRecords) +
                         " (about 300 bytes each in memory; docs/input_limits.md): lower the cycles, the seeds or "
                         "mission.goals_per_request");
}

}  // namespace mission
}  // namespace gather
