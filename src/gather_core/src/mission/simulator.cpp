#include "gather_core/mission/simulator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/mission/tour.hpp"

namespace gather {
namespace mission {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = 1e-9;        // [s] time tolerance
constexpr int kMaxDecisions = 1000000;  // per worker: a loop that long is a bug
constexpr double kWindowMargin = 1.0;   // [m] around a segment's bounding box for marches between its goals
constexpr double kLinkProbe = 1.0;      // [s] between two radio link checks of a walking or waiting worker

[[noreturn]] void bug(const std::string& what) { throw Error("mission", what); }

void march(fmm::FastMarching& fm, Cell from, const std::vector<Cell>& targets, std::vector<double>& out);

}  // namespace

struct MissionSimulator::Worker {
  int agent = 0;
  int segment = 0;
  int collector = -1;               // -1: delivers to the OC
  double meeting_arc = 0.0;         // [m] where its collector hands it each request
  std::vector<Cell> rendezvous;     // cells of the passes of its collector next to its segment
  std::vector<double> rendezvous_arc;  // [m] their arc positions on the route
  // Geodesic distances [m] from each rendezvous to every cell of the segment
  // (by the cell's index in its segment) and to the other rendezvous: one
  // march per rendezvous at setup instead of one per goal and decision.
  std::vector<std::vector<float>> rendezvous_to_cell;
  std::vector<std::vector<double>> rendezvous_to_rendezvous;
  std::vector<Cell> segment_cells;  // by index in the segment
  // A workspace on the segment's bounding box plus a margin, traversable only
  // in the segment and within the margin of it: marches between goals of the
  // segment stay small (a way that leaves the window is re-marched on the
  // whole map when the window cannot reach a goal at all).
  std::shared_ptr<fmm::FastMarching> window;
  Cell window_origin;  // its cell (0, 0) on the map
  // OC workers: distances [m] from the coverage cells they came back to, to
  // every cell of the segment (filled on first use, kept across runs: the
  // ways back funnel through a few cells, so most decisions are lookups).
  mutable std::vector<std::pair<std::size_t, std::vector<float>>> landing_to_cell;
};

// State of one run shared by the workers' timelines.
struct MissionSimulator::Run {
  int cycles = 0;
  std::vector<GoalRecord> goals;
  std::vector<std::vector<std::vector<int>>> goals_of;  // [worker index][cycle] goal ids
  std::vector<Leg> legs;
};

// The distances of one worker's request: between its goals and from each to
// the rendezvous cells (one multi-target FMM march per goal, done once when
// the request is learned), and from the worker's position (one march per
// decision).
struct RequestDistances {
  std::vector<int> ids;                   // goal ids, local index = position here
  std::vector<Cell> cells;                // goals then rendezvous cells
  std::vector<std::vector<double>> from;  // [local goal][target] [m]
  std::vector<double> from_position;      // [target] [m]
  std::size_t goals() const { return ids.size(); }
};

// Drops from `known` (local goal indices) the goals whose deadline has passed at t [s].
static void drop_expired(std::vector<int>& known, const RequestDistances& d, const std::vector<GoalRecord>& goals, double t) {
  known.erase(std::remove_if(known.begin(), known.end(),
                             [&](int i) { return goals[static_cast<std::size_t>(d.ids[static_cast<std::size_t>(i)])].deadline <= t + kEps; }),
              known.end());
}

// Arrival times [s] at the goals of `order`, leaving the worker's position at
// t [s] at speed v [m/s]; the list stops before the first goal reached after
// its deadline.
static std::vector<double> arrival_times(const std::vector<int>& order, const RequestDistances& d,
                                  const std::vector<GoalRecord>& goals, double t, double v) {
  std::vector<double> at;
  double clock = t;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t o = static_cast<std::size_t>(order[i]);
    clock += (i == 0 ? d.from_position[o] : d.from[static_cast<std::size_t>(order[i - 1])][o]) / v;
    if (clock > goals[static_cast<std::size_t>(d.ids[o])].deadline + kEps) break;
    at.push_back(clock);
  }
  return at;
}

MissionSimulator::~MissionSimulator() = default;

MissionSimulator::MissionSimulator(const World& ctx, MissionPlan plan)
    : ctx_(ctx), plan_(std::move(plan)), radio_(ctx.scenario.grid, ctx.scenario.radio), fm_(ctx.scenario.grid) {
  const Scenario& s = ctx.scenario;
  const OccupancyGrid& grid = s.grid;
  const plan::PlanFile& pf = plan_.file;
  const std::string where = "plan";
  if (plan_.width != grid.width() || plan_.height != grid.height())
    throw Error(where, "label image is " + std::to_string(plan_.width) + "x" + std::to_string(plan_.height) +
                           ", the scenario's map " + std::to_string(grid.width()) + "x" + std::to_string(grid.height()));
  speed_ = s.team.speed;
  period_ = pf.cycle_period_s;
  if (!(period_ > 0)) throw Error(where, "cycle_period_s must be > 0");
  if (static_cast<int>(pf.routes.size()) != pf.collectors) throw Error(where, "one route per collector expected");
  for (const plan::CollectorRoute& r : pf.routes) routes_.emplace_back(r, speed_, period_, grid, ctx.coverage);
  for (const plan::AgentAssignment& a : pf.agents) {
    if (a.collector) continue;
    Worker w;
    w.agent = a.id;
    w.segment = a.segment;
    w.collector = a.delivers_to;
    if (w.segment < 1 || w.segment > pf.workers) throw Error(where, "agent " + std::to_string(a.id) + ": bad segment");
    if (w.collector >= pf.collectors) throw Error(where, "agent " + std::to_string(a.id) + ": bad collector");
    if (w.collector >= 0) {
      const plan::CollectorRoute& r = pf.routes[static_cast<std::size_t>(w.collector)];
      const auto m = std::find_if(r.meetings.begin(), r.meetings.end(),
                                  [&](const plan::MeetingArea& x) { return x.segment == w.segment; });
      if (m == r.meetings.end() || routes_[static_cast<std::size_t>(w.collector)].idle())
        throw Error(where, "collector " + std::to_string(w.collector) + " has no meeting area for segment " +
                               std::to_string(w.segment));
      w.meeting_arc = m->route_s;
      const RouteTimetable& rt = routes_[static_cast<std::size_t>(w.collector)];
      for (double pass : m->passes) {
        const Cell c = grid.world_to_cell(rt.position_at_arc(pass));
        if (!grid.contains(c) || !ctx.reachable[grid.index(c)]) continue;
        w.rendezvous.push_back(c);
        w.rendezvous_arc.push_back(pass);
      }
      if (w.rendezvous.empty())
        throw Error(where, "segment " + std::to_string(w.segment) + " has no reachable pass of its collector");
    }
    workers_.push_back(w);
  }
  for (std::size_t i = 0; i < ctx.reachable.size(); ++i)
    if (ctx.reachable[i]) reachable_.push_back(static_cast<uint32_t>(i));
  // Segment cell tables and the rendezvous distance tables.
  index_in_segment_.assign(grid.size(), -1);
  std::vector<std::vector<Cell>> cells_of(static_cast<std::size_t>(pf.workers) + 1);
  for (std::size_t i = 0; i < plan_.labels.size(); ++i) {
    const int k = plan_.labels[i];
    if (k <= 0 || !ctx.reachable[i]) continue;
    index_in_segment_[i] = static_cast<int32_t>(cells_of[static_cast<std::size_t>(k)].size());
    cells_of[static_cast<std::size_t>(k)].push_back(grid.cell(i));
  }
  std::vector<double> tmp;
  const int margin = static_cast<int>(std::ceil(kWindowMargin / grid.resolution()));
  for (Worker& wk : workers_) {
    wk.segment_cells = cells_of[static_cast<std::size_t>(wk.segment)];
    if (!wk.segment_cells.empty()) {
      int r0 = grid.height(), r1 = -1, c0 = grid.width(), c1 = -1;
      for (Cell c : wk.segment_cells) r0 = std::min(r0, c.row), r1 = std::max(r1, c.row), c0 = std::min(c0, c.col), c1 = std::max(c1, c.col);
      r0 = std::max(0, r0 - margin), c0 = std::max(0, c0 - margin);
      r1 = std::min(grid.height() - 1, r1 + margin), c1 = std::min(grid.width() - 1, c1 + margin);
      const int ww = c1 - c0 + 1, wh = r1 - r0 + 1;
      std::vector<int8_t> vals(static_cast<std::size_t>(ww) * wh);
      std::vector<uint8_t> fr(vals.size());
      for (int r = 0; r < wh; ++r)
        for (int c = 0; c < ww; ++c) {
          const std::size_t src = grid.index(Cell{r0 + r, c0 + c}), dst = static_cast<std::size_t>(r) * ww + c;
          vals[dst] = grid.values()[src], fr[dst] = grid.free_mask()[src];
        }
      // Keep only the segment dilated by the margin (a square dilation, one
      // pass along rows and one along columns): between its goals a worker
      // stays in or next to its own area, as the planner assumes.
      std::vector<uint8_t> near(vals.size(), 0), rows(vals.size(), 0);
      for (Cell c : wk.segment_cells) near[static_cast<std::size_t>(c.row - r0) * ww + (c.col - c0)] = 1;
      for (int r = 0; r < wh; ++r)
        for (int c = 0, last = -1000000; c < ww; ++c) {
          if (near[static_cast<std::size_t>(r) * ww + c]) last = c;
          if (c - last <= margin) rows[static_cast<std::size_t>(r) * ww + c] = 1;
        }
      for (int r = 0; r < wh; ++r)
        for (int c = ww - 1, last = 1000000; c >= 0; --c) {
          if (near[static_cast<std::size_t>(r) * ww + c]) last = c;
          if (last - c <= margin) rows[static_cast<std::size_t>(r) * ww + c] = 1;
        }
      std::fill(near.begin(), near.end(), 0);
      for (int c = 0; c < ww; ++c) {
        for (int r = 0, last = -1000000; r < wh; ++r) {
          if (rows[static_cast<std::size_t>(r) * ww + c]) last = r;
          if (r - last <= margin) near[static_cast<std::size_t>(r) * ww + c] = 1;
        }
        for (int r = wh - 1, last = 1000000; r >= 0; --r) {
          if (rows[static_cast<std::size_t>(r) * ww + c]) last = r;
          if (last - r <= margin) near[static_cast<std::size_t>(r) * ww + c] = 1;
        }
      }
      for (std::size_t i = 0; i < fr.size(); ++i) fr[i] = fr[i] && near[i];
      const Point2 o{grid.origin().x + c0 * grid.resolution(), grid.origin().y + r0 * grid.resolution()};
      wk.window = std::make_shared<fmm::FastMarching>(OccupancyGrid(ww, wh, grid.resolution(), o, vals, fr));
      wk.window_origin = Cell{r0, c0};
    }
    if (wk.collector < 0) continue;
    std::vector<Cell> targets = cells_of[static_cast<std::size_t>(wk.segment)];
    const std::size_t m = targets.size();
    targets.insert(targets.end(), wk.rendezvous.begin(), wk.rendezvous.end());
    for (Cell r : wk.rendezvous) {
      fmm::SolveOptions so;
      so.labels = false;
      so.targets = targets;
      fm_.solve({fmm::Source::at_cell(r)}, so);
      std::vector<float> to_cell(m);
      for (std::size_t i = 0; i < m; ++i) to_cell[i] = static_cast<float>(fm_.time(targets[i]));
      std::vector<double> to_rv;
      for (Cell q : wk.rendezvous) to_rv.push_back(fm_.time(q));
      wk.rendezvous_to_cell.push_back(std::move(to_cell));
      wk.rendezvous_to_rendezvous.push_back(std::move(to_rv));
    }
  }
  // Every worker starts at the OC: distances from there, once.
  {
    fmm::SolveOptions so;
    so.labels = false;
    fm_.solve({fmm::Source::at_cell(ctx.oc_cell)}, so);
    std::vector<double> t;
    fm_.copy_times(t);
    from_oc_.assign(t.begin(), t.end());
  }
}

MissionResult MissionSimulator::run(const MissionOptions& opt) {
  const auto t_start = std::chrono::steady_clock::now();
  if (opt.cycles < 1) throw Error("mission", "cycles must be >= 1");
  const OccupancyGrid& grid = ctx_.scenario.grid;
  Run run;
  run.cycles = opt.cycles;
  run.goals_of.assign(workers_.size(), std::vector<std::vector<int>>(static_cast<std::size_t>(opt.cycles)));
  std::vector<int> worker_of_segment(static_cast<std::size_t>(plan_.file.workers) + 1, -1);
  for (std::size_t i = 0; i < workers_.size(); ++i) worker_of_segment[static_cast<std::size_t>(workers_[i].segment)] = static_cast<int>(i);
  auto add_goal = [&](int cycle, Cell cell) {
    GoalRecord g;
    g.id = static_cast<int>(run.goals.size());
    g.cycle = cycle;
    g.point = grid.cell_center(cell);
    g.segment = plan_.labels[grid.index(cell)];
    g.requested_at = cycle * period_;
    g.deadline = (cycle + 1) * period_;
    const int wi = g.segment > 0 ? worker_of_segment[static_cast<std::size_t>(g.segment)] : -1;
    if (wi >= 0) {
      g.worker = workers_[static_cast<std::size_t>(wi)].agent;
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
    const int per_request = opt.goals_per_request >= 0 ? opt.goals_per_request : ctx_.scenario.mission.goals_per_request;
    std::mt19937_64 rng(opt.seed);
    const uint64_t n = reachable_.size();  // modulo bias < n / 2^64: negligible
    for (int c = 0; c < opt.cycles; ++c)
      for (int i = 0; i < per_request; ++i)
        add_goal(c, grid.cell(reachable_[static_cast<std::size_t>(rng() % n)]));
  }

  for (const Worker& w : workers_) simulate_worker(w, run);
  for (GoalRecord& g : run.goals) {
    if (g.measured_at < 0 && !std::isfinite(g.deadline)) bug("goal " + std::to_string(g.id) + " neither measured nor expired");
    if (g.measured_at < 0) g.expired_at = g.deadline, g.state = GoalState::kExpired;
    else g.state = g.delivered_at >= 0 ? GoalState::kDelivered : GoalState::kCarried;
  }

  MissionResult res;
  res.cycles = account(run.goals, opt.cycles, period_);
  res.period_s = period_;
  res.mission_s = opt.cycles * period_;
  int delivered = 0;
  double sum = 0.0;
  for (const GoalRecord& g : run.goals) {
    res.end_s = std::max({res.end_s, g.delivered_at, g.expired_at});
    if (g.delivered_at < 0) continue;
    const double r = g.delivered_at - g.requested_at;
    ++delivered, sum += r, res.refresh_max_s = std::max(res.refresh_max_s, r);
  }
  res.refresh_mean_s = delivered > 0 ? sum / delivered : 0.0;
  res.goals_per_cycle = static_cast<double>(delivered) / opt.cycles;
  res.goals = std::move(run.goals);
  res.legs = std::move(run.legs);
  res.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
  return res;
}

void MissionSimulator::from_oc(const std::vector<Cell>& targets, std::vector<double>& out) const {
  const OccupancyGrid& grid = ctx_.scenario.grid;
  out.resize(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) out[i] = from_oc_[grid.index(targets[i])];
}

void MissionSimulator::from_landing(const Worker& w, Cell landing, const std::vector<Cell>& targets,
                                    std::vector<double>& out) {
  constexpr std::size_t kMaxLandings = 16;  // per worker; beyond, march each time
  const OccupancyGrid& grid = ctx_.scenario.grid;
  const std::size_t key = grid.index(landing);
  auto it = std::find_if(w.landing_to_cell.begin(), w.landing_to_cell.end(),
                         [&](const auto& e) { return e.first == key; });
  if (it == w.landing_to_cell.end()) {
    if (w.landing_to_cell.size() >= kMaxLandings) {
      march(fm_, landing, targets, out);
      return;
    }
    std::vector<double> all;
    march(fm_, landing, w.segment_cells, all);
    w.landing_to_cell.emplace_back(key, std::vector<float>(all.begin(), all.end()));
    it = w.landing_to_cell.end() - 1;
  }
  out.resize(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i)
    out[i] = it->second[static_cast<std::size_t>(index_in_segment_[grid.index(targets[i])])];
}

void MissionSimulator::simulate_worker(const Worker& w, Run& run) {
  if (w.collector >= 0) simulate_collector_worker(w, run);
  else simulate_oc_worker(w, run);
}

namespace {

// Distances [m] from `from` to each of `targets` (one march that stops once
// all are final); +inf for unreachable ones.
void march(fmm::FastMarching& fm, Cell from, const std::vector<Cell>& targets, std::vector<double>& out) {
  fmm::SolveOptions so;
  so.labels = false;
  so.targets = targets;
  fm.solve({fmm::Source::at_cell(from)}, so);
  out.resize(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) out[i] = fm.time(targets[i]);
}

// Learns a request: its goals' distances to each other (one march per goal,
// stopped at the farthest other goal) and to the rendezvous (from the tables).
// Distances [m] from `from` to `targets`, all in the worker's window, marched
// in the window; on the whole map if some target cannot be reached there.
void march_in_window(fmm::FastMarching& fm, fmm::FastMarching* window, Cell origin, Cell from,
                     const std::vector<Cell>& targets, std::vector<double>& out) {
  if (window) {
    auto local = [&](Cell c) { return Cell{c.row - origin.row, c.col - origin.col}; };
    bool inside = window->contains(local(from));
    std::vector<Cell> shifted;
    for (Cell c : targets) shifted.push_back(local(c)), inside = inside && window->contains(shifted.back());
    if (inside) {
      march(*window, local(from), shifted, out);
      if (std::all_of(out.begin(), out.end(), [](double x) { return x < kInf; })) return;
    }
  }
  march(fm, from, targets, out);
}

void learn(fmm::FastMarching& fm, fmm::FastMarching* window, Cell window_origin, const OccupancyGrid& grid,
           const std::vector<GoalRecord>& goals, const std::vector<int>& ids, const std::vector<Cell>& rendezvous,
           const std::vector<std::vector<float>>& rendezvous_to_cell, const std::vector<int32_t>& index_in_segment,
           RequestDistances& d) {
  d.ids = ids;
  d.cells.clear();
  for (int id : ids) d.cells.push_back(grid.world_to_cell(goals[static_cast<std::size_t>(id)].point));
  const std::vector<Cell> goal_cells = d.cells;
  d.cells.insert(d.cells.end(), rendezvous.begin(), rendezvous.end());
  d.from.assign(ids.size(), std::vector<double>(d.cells.size(), 0.0));
  // Geodesic distances are symmetric (up to the march's discretisation): goal
  // i marches to the later goals only, which halves the work.
  std::vector<double> tmp;
  std::vector<Cell> later;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (i + 1 < ids.size()) {
      later.assign(goal_cells.begin() + static_cast<long>(i) + 1, goal_cells.end());
      march_in_window(fm, window, window_origin, d.cells[i], later, tmp);
      for (std::size_t j = i + 1; j < ids.size(); ++j) d.from[i][j] = d.from[j][i] = tmp[j - i - 1];
    }
    const std::size_t local = static_cast<std::size_t>(index_in_segment[grid.index(d.cells[i])]);
    for (std::size_t r = 0; r < rendezvous.size(); ++r) d.from[i][ids.size() + r] = rendezvous_to_cell[r][local];
  }
}

}  // namespace

void MissionSimulator::simulate_collector_worker(const Worker& w, Run& run) {
  const OccupancyGrid& grid = ctx_.scenario.grid;
  const RouteTimetable& route = routes_[static_cast<std::size_t>(w.collector)];
  const auto& mine = run.goals_of[static_cast<std::size_t>(&w - workers_.data())];
  const double v = speed_;
  // The request reaches the collector when it is next inside the OC's
  // coverage, and the worker when the collector next passes its meeting area.
  auto learn_time = [&](int c) {
    return c == 0 ? 0.0 : route.next_time_at(w.meeting_arc, route.next_coverage_time(c * period_));
  };
  // A request's goals expire when the next request reaches the worker (it
  // supersedes them); requests that arrive together leave only the newest.
  for (int c = 0; c < run.cycles; ++c) {
    const double until = learn_time(c + 1);
    for (int id : mine[static_cast<std::size_t>(c)]) run.goals[static_cast<std::size_t>(id)].deadline = until;
  }

  Cell pos = ctx_.oc_cell;
  double t = 0.0;
  int next_req = 0;
  RequestDistances d;
  std::vector<int> known;    // local indices of unmeasured goals of the current request
  std::vector<int> carried;  // goal ids measured and not yet handed over
  const std::size_t n_rv = w.rendezvous.size();
  int at_rv = -1;  // the rendezvous the worker stands at, -1 elsewhere
  double no_meeting_before = 0.0;  // [s] after a failed hand-over: the next try is a later pass
  // Everything carried goes to the collector at t; it drops it at its next
  // time inside the OC's coverage.
  auto hand_over = [&](double t) {
    const double drop = route.next_coverage_time(t);
    for (int id : carried) {
      GoalRecord& g = run.goals[static_cast<std::size_t>(id)];
      if (g.picked_up_at >= 0 || g.delivered_at >= 0) bug("goal " + std::to_string(id) + " handed over twice");
      g.picked_up_at = t, g.picked_up_by = w.collector;
      g.delivered_at = drop, g.delivered_by = w.collector;
    }
    carried.clear();
  };
  // The collector also takes the data whenever the radio link holds on the
  // way (not only at the planned pass): probed every kLinkProbe seconds while
  // the worker walks from `from` to `to` during [t0, t1] or waits (from ==
  // to); its position along a walk is interpolated on the straight line.
  const double link_range = radio_.free_space_range();
  // Returns the time of the pick-up, or -1 if the link never came up.
  auto pick_up_on_the_way = [&](Point2 from, Point2 to, double t0, double t1) -> double {
    if (carried.empty() || !(t1 > t0)) return -1.0;
    auto linked_at = [&](double t) {
      const double f = (t - t0) / (t1 - t0);
      const Point2 p{from.x + f * (to.x - from.x), from.y + f * (to.y - from.y)};
      const Point2 c = route.position(t);
      return std::hypot(p.x - c.x, p.y - c.y) <= link_range && radio_.linked(p, c);
    };
    const int steps = std::max(1, static_cast<int>(std::ceil((t1 - t0) / kLinkProbe)));
    for (int i = 0; i <= steps; ++i) {
      double hi = t0 + (t1 - t0) * i / steps;
      if (!linked_at(hi)) continue;
      if (i > 0) {  // the link came up between two probes: find when, to 1e-4 s
        double lo = t0 + (t1 - t0) * (i - 1) / steps;
        while (hi - lo > 1e-4) {
          const double mid = 0.5 * (lo + hi);
          (linked_at(mid) ? hi : lo) = mid;
        }
      }
      hand_over(hi);
      return hi;
    }
    return -1.0;
  };
  for (int step = 0;; ++step) {
    if (step > kMaxDecisions) bug("worker " + std::to_string(w.agent) + " does not terminate");
    drop_expired(known, d, run.goals, t);
    while (next_req < run.cycles && learn_time(next_req) <= t + kEps) {
      // Older goals are past their deadline by now (learn time >= request time).
      learn(fm_, w.window.get(), w.window_origin, grid, run.goals, mine[static_cast<std::size_t>(next_req)], w.rendezvous, w.rendezvous_to_cell,
            index_in_segment_, d);
      known.clear();
      for (std::size_t i = 0; i < d.goals(); ++i) known.push_back(static_cast<int>(i));
      ++next_req;
    }
    const std::size_t n = d.goals();
    std::vector<int> order;
    std::vector<double> at;  // measurement time of order[i]
    if (!known.empty()) {
      if (at_rv >= 0) {
        d.from_position.resize(d.cells.size());
        for (std::size_t i = 0; i < n; ++i)
          d.from_position[i] = d.from[i][n + static_cast<std::size_t>(at_rv)];
        for (std::size_t r = 0; r < n_rv; ++r)
          d.from_position[n + r] = w.rendezvous_to_rendezvous[static_cast<std::size_t>(at_rv)][r];
      } else if (pos == ctx_.oc_cell) {
        from_oc(d.cells, d.from_position);
      } else {
        march(fm_, pos, d.cells, d.from_position);
      }
      order = order_tour(d.from_position, d.from, known);
      at = arrival_times(order, d, run.goals, t, v);
    }
    const std::size_t kmax = at.size();
    if (kmax == 0 && carried.empty() && next_req >= run.cycles) break;
    std::vector<double> pos_rv(n_rv);  // [m] from the position to each rendezvous
    if (known.empty() && at_rv >= 0) pos_rv = w.rendezvous_to_rendezvous[static_cast<std::size_t>(at_rv)];
    else if (known.empty() && pos == ctx_.oc_cell) from_oc(w.rendezvous, pos_rv);
    else if (known.empty()) march(fm_, pos, w.rendezvous, pos_rv);
    else for (std::size_t r = 0; r < n_rv; ++r) pos_rv[r] = d.from_position[n + r];
    if (kmax == 0 && carried.empty()) {
      // Nothing to do: wait for the next request at the nearest pass (going
      // there first: this is how workers reach their segments at the start).
      if (at_rv < 0) {
        const std::size_t r = static_cast<std::size_t>(std::min_element(pos_rv.begin(), pos_rv.end()) - pos_rv.begin());
        if (!(pos_rv[r] < kInf)) bug("worker " + std::to_string(w.agent) + " cannot reach any pass of its collector");
        run.legs.push_back(Leg{w.agent, t, t + pos_rv[r] / v, grid.cell_center(pos), grid.cell_center(w.rendezvous[r])});
        t += pos_rv[r] / v, pos = w.rendezvous[r], at_rv = static_cast<int>(r);
        continue;
      }
      t = std::max(t, learn_time(next_req));
      continue;
    }
    // Earliest meeting after measuring the first k goals of the tour.
    auto meet = [&](std::size_t k, std::size_t& best_rv) {
      double best = kInf;
      for (std::size_t r = 0; r < n_rv; ++r) {
        double dist;
        if (k == 0) dist = pos_rv[r];
        else dist = d.from[static_cast<std::size_t>(order[k - 1])][n + r];
        if (!(dist < kInf)) continue;
        const double arrive = std::max((k == 0 ? t : at[k - 1]) + dist / v, no_meeting_before);
        const double h = route.next_time_at(w.rendezvous_arc[r], arrive);
        if (h < best) best = h, best_rv = r;
      }
      return best;
    };
    std::size_t rv = 0, k = 0;
    double handover = kInf;
    if (kmax == 0) {
      handover = meet(0, rv);
    } else {
      std::size_t rv1 = 0;
      const double first = meet(1, rv1);
      k = 1, rv = rv1, handover = first;
      for (std::size_t j = 2; j <= kmax; ++j) {
        std::size_t rvj = 0;
        const double h = meet(j, rvj);
        if (h <= first + kEps) k = j, rv = rvj, handover = h;
      }
    }
    if (!(handover < kInf)) bug("worker " + std::to_string(w.agent) + " cannot reach any pass of its collector");
    // Execute: measure k goals, go to the pass, wait for the collector.
    Point2 here = grid.cell_center(pos);
    double clock = t;
    for (std::size_t i = 0; i < k; ++i) {
      const std::size_t o = static_cast<std::size_t>(order[i]);
      GoalRecord& g = run.goals[static_cast<std::size_t>(d.ids[o])];
      if (g.measured_at >= 0) bug("goal " + std::to_string(g.id) + " measured twice");
      g.measured_at = at[i], g.measured_by = w.agent;
      run.legs.push_back(Leg{w.agent, clock, at[i], here, g.point});
      pick_up_on_the_way(here, g.point, clock, at[i]);
      here = g.point, clock = at[i];
      carried.push_back(g.id);
      known.erase(std::find(known.begin(), known.end(), order[i]));
    }
    const Point2 meet_point = grid.cell_center(w.rendezvous[rv]);
    const double dist = k == 0 ? pos_rv[rv] : d.from[static_cast<std::size_t>(order[k - 1])][n + rv];
    const double arrive = clock + dist / v;
    run.legs.push_back(Leg{w.agent, clock, arrive, here, meet_point});
    pick_up_on_the_way(here, meet_point, clock, arrive);
    const double taken = pick_up_on_the_way(meet_point, meet_point, arrive, handover);
    pos = w.rendezvous[rv];
    at_rv = static_cast<int>(rv);
    if (carried.empty()) {
      // Taken on the way: no need to wait for the pass; decide again as soon
      // as the data is gone (at the pass, or when the collector came in range).
      t = std::max(arrive, taken);
    } else {
      t = handover;
      if (radio_.linked(meet_point, route.position(t))) hand_over(t);
      else no_meeting_before = t + 1.0;  // the worker keeps its data for a later pass
    }
  }
}

void MissionSimulator::simulate_oc_worker(const Worker& w, Run& run) {
  const OccupancyGrid& grid = ctx_.scenario.grid;
  const auto& mine = run.goals_of[static_cast<std::size_t>(&w - workers_.data())];
  const double v = speed_;
  auto covered = [&](Cell c) { return ctx_.coverage[grid.index(c)] != 0; };
  // Its goals stay valid until the worker learns a newer request (in the
  // coverage); it measures them all, then comes back.
  for (const auto& ids : mine)
    for (int id : ids) run.goals[static_cast<std::size_t>(id)].deadline = kInf;

  Cell pos = ctx_.oc_cell;
  double t = 0.0;
  int next_req = 0;
  RequestDistances d;
  std::vector<int> known, carried;
  bool at_landing = false;  // pos is where the worker came back into the coverage
  auto deliver = [&]() {
    for (int id : carried) {
      GoalRecord& g = run.goals[static_cast<std::size_t>(id)];
      if (g.delivered_at >= 0) bug("goal " + std::to_string(id) + " delivered twice");
      g.delivered_at = t, g.delivered_by = w.agent;
    }
    carried.clear();
  };
  auto back_to_coverage = [&]() {
    const double dist = ctx_.coverage_field.time(pos);
    const int label = ctx_.coverage_field.label(pos);
    if (!(dist < kInf) || label < 0) bug("worker " + std::to_string(w.agent) + " cannot reach the OC's coverage");
    const Cell to = ctx_.coverage_border[static_cast<std::size_t>(label)];
    run.legs.push_back(Leg{w.agent, t, t + dist / v, grid.cell_center(pos), grid.cell_center(to)});
    t += dist / v, pos = to;
    at_landing = true;
  };
  for (int step = 0;; ++step) {
    if (step > kMaxDecisions) bug("worker " + std::to_string(w.agent) + " does not terminate");
    drop_expired(known, d, run.goals, t);
    if (covered(pos)) {
      deliver();
      while (next_req < run.cycles && next_req * period_ <= t + kEps) {
        // The newer request supersedes what is left of the older one.
        for (int i : known) run.goals[static_cast<std::size_t>(d.ids[static_cast<std::size_t>(i)])].deadline = t;
        learn(fm_, w.window.get(), w.window_origin, grid, run.goals, mine[static_cast<std::size_t>(next_req)], {}, {},
              index_in_segment_, d);
        known.clear();
        for (std::size_t i = 0; i < d.goals(); ++i) known.push_back(static_cast<int>(i));
        ++next_req;
      }
    }
    std::vector<int> order;
    std::vector<double> at;
    if (!known.empty()) {
      if (pos == ctx_.oc_cell) from_oc(d.cells, d.from_position);
      else if (at_landing) from_landing(w, pos, d.cells, d.from_position);
      else march(fm_, pos, d.cells, d.from_position);
      order = order_tour(d.from_position, d.from, known);
      at = arrival_times(order, d, run.goals, t, v);
    }
    if (at.empty()) {
      if (!covered(pos)) {
        back_to_coverage();
        continue;
      }
      if (next_req >= run.cycles) break;
      t = std::max(t, next_req * period_);
      continue;
    }
    // Measure every goal that can still be measured in time, then go back.
    Point2 here = grid.cell_center(pos);
    for (std::size_t i = 0; i < at.size(); ++i) {
      const std::size_t o = static_cast<std::size_t>(order[i]);
      GoalRecord& g = run.goals[static_cast<std::size_t>(d.ids[o])];
      if (g.measured_at >= 0) bug("goal " + std::to_string(g.id) + " measured twice");
      g.measured_at = at[i], g.measured_by = w.agent;
      run.legs.push_back(Leg{w.agent, t, at[i], here, g.point});
      here = g.point, t = at[i], pos = d.cells[o], at_landing = false;
      carried.push_back(g.id);
      known.erase(std::find(known.begin(), known.end(), order[i]));
      if (covered(pos)) deliver();  // measured inside the coverage: the OC hears it at once
    }
    if (!covered(pos)) back_to_coverage();
  }
}

}  // namespace mission
}  // namespace gather
