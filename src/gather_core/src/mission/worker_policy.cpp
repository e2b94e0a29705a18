// The worker's decisions, shared by the planner's estimate, the analytic
// simulator and the agents' worker role: which goals a request leaves it,
// its tour, where and when it meets its collector, when it gives up a goal.
// Over 400 lines because decide() and the distances it needs (marches in the
// segment's window, landing tables, rendezvous windows) change together; the
// tour itself is mission/tour, the window mission/segment_window.
#include "gather_core/mission/worker_policy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/mission/tour.hpp"
#include "gather_core/radio/radio_model.hpp"
#include "gather_core/scenario/start_poses.hpp"
#include "mission_internal.hpp"

namespace gather {
namespace mission {
namespace {

constexpr std::size_t kMaxLandings = 8;  // per OC worker: landing tables kept; beyond, march each time

}  // namespace

SharedDistances::SharedDistances(const World& world, bool with_from_oc) : fm(world.scenario.grid) {
  if (!with_from_oc) return;
  fmm::SolveOptions so;
  so.labels = false;
  fm.solve({fmm::Source::at_cell(world.oc_cell)}, so);
  const Raster<double> t = fm.times();
  from_oc = Field(t.frame(), std::vector<float>(t.begin(), t.end()));
}

void check_params(const ProtocolParams& p) {
  require_in_range(p.link_step_m, 0.01, 1, "protocol params", "link_step_m", " m");
  require_in_range(p.window_margin_m, 0, 100, "protocol params", "window_margin_m", " m");
  require_in_range(p.two_opt_rounds, 0, 10000, "protocol params", "two_opt_rounds");
  require_in_range(p.replan_guard_s, 0.1, 600, "protocol params", "replan_guard_s", " s");
  require_in_range(p.wait_loops, 0, 10, "protocol params", "wait_loops");
  require_in_range(p.place_tolerance_m, 0.05, 10, "protocol params", "place_tolerance_m", " m");
  require_in_range(p.home_clearance_m, 0, 5, "protocol params", "home_clearance_m", " m");
}

std::vector<Cell> oc_worker_homes(const World& world, const MissionPlan& mp, double clearance) {
  const OccupancyGrid& grid = world.scenario.grid;
  const plan::PlanFile& pf = mp.file;
  std::vector<std::vector<Cell>> segments;
  std::vector<int> slot(static_cast<std::size_t>(std::max(pf.workers, 0)) + 1, -1);  // by segment label
  std::vector<int> of_agent(pf.agents.size(), -1);                                   // agent id -> segments[k]
  for (const plan::AgentAssignment& o : pf.agents) {
    if (o.collector || o.delivers_to.valid() || !o.segment.within(pf.workers)) continue;
    of_agent[static_cast<std::size_t>(o.id.value())] = static_cast<int>(segments.size());
    slot[static_cast<std::size_t>(o.segment.label())] = static_cast<int>(segments.size());
    segments.emplace_back();
  }
  for (std::size_t i = 0; i < mp.labels.size() && i < grid.size(); ++i) {
    const int l = mp.labels[i];
    if (l > 0 && l <= pf.workers && slot[static_cast<std::size_t>(l)] >= 0 && world.reachable[i])
      segments[static_cast<std::size_t>(slot[static_cast<std::size_t>(l)])].push_back(grid.cell(i));
  }
  const std::vector<Cell> homes = world.oc_worker_homes(segments, clearance);
  std::vector<Cell> out(pf.agents.size(), Cell{-1, -1});
  for (std::size_t id = 0; id < out.size(); ++id)
    if (of_agent[id] >= 0) out[id] = homes[static_cast<std::size_t>(of_agent[id])];
  return out;
}

std::vector<Point2> team_start_poses(const World& world, const MissionPlan& mp, const std::vector<Cell>& oc_homes) {
  const OccupancyGrid& grid = world.scenario.grid;
  const int n = static_cast<int>(mp.file.agents.size());
  if (oc_homes.empty()) return start_poses(grid, world.scenario.oc, n, kStartSpacing);
  std::vector<Point2> at_home;
  std::vector<int> home_of(static_cast<std::size_t>(n), -1);
  for (int id = 0; id < n; ++id) {
    const Cell h = oc_homes[static_cast<std::size_t>(id)];
    if (h.row < 0) continue;
    const Point2 p = grid.cell_center(h);
    const bool apart = std::all_of(at_home.begin(), at_home.end(),
                                   [&](Point2 q) { return std::hypot(p.x - q.x, p.y - q.y) >= kStartSpacing - 1e-9; });
    if (!apart) continue;  // homes squeezed closer than robots stand: it starts by the OC
    home_of[static_cast<std::size_t>(id)] = static_cast<int>(at_home.size());
    at_home.push_back(p);
  }
  const std::vector<Point2> by_oc =
      start_poses(grid, world.scenario.oc, n - static_cast<int>(at_home.size()), kStartSpacing, at_home);
  std::vector<Point2> out;
  out.reserve(static_cast<std::size_t>(n));
  std::size_t next = 0;
  for (int id = 0; id < n; ++id) {
    const int k = home_of[static_cast<std::size_t>(id)];
    out.push_back(k >= 0 ? at_home[static_cast<std::size_t>(k)] : by_oc[next++]);
  }
  return out;
}

ProtocolParams robot_protocol(ProtocolParams p) {
  p.home_clearance_m = 1.5;  // out of doorways and corridors: room to pass a robot waiting there
  return p;
}

int32_t WorkerPolicy::segment_index(Cell c) const {
  const int r = c.row - box_origin_.row, q = c.col - box_origin_.col;
  if (r < 0 || q < 0 || r >= box_height_ || q >= box_width_) return -1;
  return box_index_[static_cast<std::size_t>(r) * static_cast<std::size_t>(box_width_) + static_cast<std::size_t>(q)];
}

WorkerPolicy::~WorkerPolicy() = default;
WorkerPolicy::WorkerPolicy(WorkerPolicy&&) noexcept = default;

WorkerPolicy::WorkerPolicy(const World& world, const MissionPlan& mp, const plan::AgentAssignment& a,
                           const RouteTimetable* route, SharedDistances& shared, std::size_t max_goals,
                           const ProtocolParams& protocol, const std::vector<Cell>* oc_homes)
    : world_(world), shared_(shared), route_(route), agent_(a.id), segment_(a.segment), collector_(a.delivers_to) {
  const OccupancyGrid& grid = world.scenario.grid;
  const plan::PlanFile& pf = mp.file;
  const std::string where = mp.source.empty() ? "plan" : mp.source;
  check_params(protocol);
  two_opt_rounds_ = protocol.two_opt_rounds;
  speed_ = world.scenario.team.speed;
  if (a.collector) throw Error(where, to_string(a.id) + " is a collector, not a worker");
  if (!segment_.within(pf.workers)) throw Error(where, to_string(a.id) + ": bad segment");
  if (collector_.value() >= pf.collectors) throw Error(where, to_string(a.id) + ": bad collector");
  if (collector_.valid()) {
    if (!route_) throw Error(where, to_string(a.id) + ": no timetable of its collector");
    const plan::CollectorRoute& r = pf.routes[collector_];
    const auto m = std::find_if(r.meetings.begin(), r.meetings.end(),
                                [&](const plan::MeetingArea& x) { return x.segment == segment_; });
    if (m == r.meetings.end() || route_->idle())
      throw Error(where, to_string(collector_) + " has no meeting area for " + to_string(segment_));
    meeting_arc_ = m->arc_m;
    for (double pass : m->passes) {
      const Cell c = grid.world_to_cell(route_->position_at_arc(pass));
      if (!grid.contains(c) || !world.reachable[grid.index(c)]) continue;
      rendezvous_.push_back(c);
      rendezvous_arc_.push_back(pass);
    }
    if (rendezvous_.empty()) throw Error(where, to_string(segment_) + " has no reachable pass of its collector");
    // Each pass's link window: from the pass along the route both ways while
    // the rendezvous point (where the worker waits) stays linked to the
    // collector, within one loop (the route starts and ends at the OC).
    const RadioModel radio(grid, world.scenario.radio);
    const double range = radio.free_space_range();
    double longest = 0.0;
    for (std::size_t k = 0; k < rendezvous_.size(); ++k) {
      const Point2 w = grid.cell_center(rendezvous_[k]);
      auto linked = [&](double s) {
        const Point2 c = route_->position_at_arc(s);
        return std::hypot(c.x - w.x, c.y - w.y) <= range && radio.linked(w, c);
      };
      const double s0 = rendezvous_arc_[k];
      double lo = s0, hi = s0;
      if (linked(s0)) {
        const double step = protocol.link_step_m;
        while (lo > 0.0 && linked(std::max(0.0, lo - step))) lo = std::max(0.0, lo - step);
        while (hi < route_->length() && linked(std::min(route_->length(), hi + step)))
          hi = std::min(route_->length(), hi + step);
      }
      link_window_.emplace_back(lo, hi);
      longest = std::max(longest, (hi - lo) / route_->speed());
    }
    const double one = transfer_s(world.scenario, 1);
    // n goals fit a window when n * one + guard <= window (+ kEps [s], as
    // meeting_at); clamped before the cast (a goal of a few bytes at a fast
    // rate would overflow it).
    const double fits = one > 0.0 ? std::floor((longest - handover_guard(longest) + kEps) / one) : 1e12;
    capacity_ = fits >= 1e9 ? std::numeric_limits<std::size_t>::max() : static_cast<std::size_t>(std::max(0.0, fits));
  } else {
    capacity_ = std::numeric_limits<std::size_t>::max();
  }
  for (std::size_t i = 0; i < mp.labels.size() && i < grid.size(); ++i)
    if (mp.labels[i] == segment_.label() && world.reachable[i]) segment_cells_.push_back(grid.cell(i));
  if (!segment_cells_.empty()) {
    int r0 = grid.height(), r1 = -1, c0 = grid.width(), c1 = -1;
    for (Cell c : segment_cells_)
      r0 = std::min(r0, c.row), r1 = std::max(r1, c.row), c0 = std::min(c0, c.col), c1 = std::max(c1, c.col);
    box_origin_ = Cell{r0, c0};
    box_width_ = c1 - c0 + 1, box_height_ = r1 - r0 + 1;
    box_index_.assign(static_cast<std::size_t>(box_width_) * static_cast<std::size_t>(box_height_), -1);
    for (std::size_t k = 0; k < segment_cells_.size(); ++k) {
      const Cell c = segment_cells_[k];
      box_index_[static_cast<std::size_t>(c.row - r0) * static_cast<std::size_t>(box_width_) +
                 static_cast<std::size_t>(c.col - c0)] = static_cast<int32_t>(k);
    }
  }

  // Marches between its goals stay in its window (see SegmentWindow).
  if (!segment_cells_.empty())
    window_ = std::make_unique<SegmentWindow>(grid, segment_cells_, protocol.window_margin_m);

  solve_options_.labels = false;
  source_.resize(1);
  if (collector_.valid()) {
    std::vector<Cell> targets = segment_cells_;
    const std::size_t m = targets.size();
    targets.insert(targets.end(), rendezvous_.begin(), rendezvous_.end());
    for (Cell r : rendezvous_) {
      fmm::SolveOptions so;
      so.labels = false;
      so.targets = targets;
      shared_.fm.solve({fmm::Source::at_cell(r)}, so);
      std::vector<float> to_cell(m);
      for (std::size_t i = 0; i < m; ++i) to_cell[i] = static_cast<float>(shared_.fm.time(targets[i]));
      std::vector<double> to_rv;
      for (Cell q : rendezvous_) to_rv.push_back(shared_.fm.time(q));
      rendezvous_to_cell_.push_back(std::move(to_cell));
      rendezvous_to_rendezvous_.push_back(std::move(to_rv));
    }
    const Cell mc = grid.world_to_cell(route_->position_at_arc(meeting_arc_));
    if (grid.contains(mc) && world.reachable[grid.index(mc)]) {
      meeting_cell_ = mc;
      fmm::SolveOptions so;
      so.labels = false;
      so.targets = targets;
      shared_.fm.solve({fmm::Source::at_cell(mc)}, so);
      meeting_to_cell_.resize(m);
      for (std::size_t i = 0; i < m; ++i) meeting_to_cell_[i] = static_cast<float>(shared_.fm.time(targets[i]));
      for (Cell q : rendezvous_) meeting_to_rv_.push_back(shared_.fm.time(q));
    }
  }

  if (!route_) {
    // A worker of the OC waits for requests at home: the coverage cell
    // nearest its segment (where it comes back to from the segment's nearest
    // cell), so that a request learned there can be served within its
    // period (mission::request_deadline), wherever the OC itself stands.
    // On robots (home_clearance_m > 0) the workers of the OC take homes
    // with room around them and apart from each other, in the order of
    // their ids: every worker finds the same homes (World::oc_worker_homes).
    if (protocol.home_clearance_m > 0) {
      const auto id = static_cast<std::size_t>(a.id.value());
      home_ = oc_homes ? (*oc_homes)[id] : oc_worker_homes(world, mp, protocol.home_clearance_m)[id];
      if (home_.row >= 0) {
        home_to_border_.resize(world.coverage_border.size());
        march(home_, world.coverage_border, home_to_border_.data());
        place_tolerance_m_ = protocol.place_tolerance_m;
      }
    } else {
      home_ = world.oc_worker_home(segment_cells_);
    }
  }

  tmp_.reserve(segment_cells_.size());
  solve_options_.targets.reserve(segment_cells_.size());
  landing_to_cell_.reserve(kMaxLandings);
  reserve(max_goals);
}

void WorkerPolicy::reserve(std::size_t max_goals) {
  if (max_goals <= max_goals_ && !goals_.empty()) return;
  const bool grown = max_goals > max_goals_ && !goals_.empty();
  max_goals_ = std::max(max_goals_, max_goals);
  const std::size_t nr = rendezvous_.size(), m = max_goals_ + nr;
  goals_.resize(max_goals_);
  cells_.reserve(m);
  from_.resize(max_goals_ * m, 0.0);
  from_position_.resize(m, 0.0);
  position_to_rv_.resize(nr, 0.0);
  tour_.resize(max_goals_, 0);
  at_.resize(max_goals_, 0.0);
  used_.resize(max_goals_, 0);
  targets_.reserve(m);
  tmp_.reserve(m);
  if (solve_options_.targets.capacity() < m) solve_options_.targets.reserve(m);
  if (grown && window_) window_->reserve(m);
}

void WorkerPolicy::reserve_all() {
  const OccupancyGrid& grid = world_.scenario.grid;
  shared_.fm.reserve_work(std::max(segment_cells_.size(), max_goals_ + rendezvous_.size()),
                          8 * (static_cast<std::size_t>(grid.width()) + static_cast<std::size_t>(grid.height())));
  if (window_) window_->reserve(max_goals_ + rendezvous_.size());
  if (delivers_to_oc())
    while (landing_to_cell_.size() < kMaxLandings)
      landing_to_cell_.emplace_back(static_cast<std::size_t>(-1), std::vector<float>(segment_cells_.size()));
}

Point2 WorkerPolicy::rendezvous_point(int r) const {
  return world_.scenario.grid.cell_center(rendezvous_[static_cast<std::size_t>(r)]);
}

double request_reaches_worker(const RouteTimetable& route, double meeting_arc, int cycle, double period) {
  if (cycle == 0) return 0.0;
  return route.next_time_at(meeting_arc, route.next_coverage_time(cycle * period));
}

double WorkerPolicy::learn_time(int cycle, double period) const {
  if (!route_) return cycle == 0 ? 0.0 : cycle * period;
  return request_reaches_worker(*route_, meeting_arc_, cycle, period);
}

double WorkerPolicy::deadline(int cycle, double period) const {
  return route_ ? request_deadline(learn_time(cycle, period), learn_time(cycle + 1, period), period) : kInf;
}

void WorkerPolicy::march(Cell from, const std::vector<Cell>& targets, double* out) {
  source_[0] = fmm::Source::at_cell(from);
  solve_options_.targets.assign(targets.begin(), targets.end());
  shared_.fm.solve(source_, solve_options_);
  for (std::size_t i = 0; i < targets.size(); ++i) out[i] = shared_.fm.time(targets[i]);
}

void WorkerPolicy::march_one(Cell from, Cell to, double& out) {
  targets_.assign(1, to);
  march(from, targets_, &out);
}

// Distances [m] from `from` to `targets`, all in the worker's window, marched
// in the window; on the whole map if some target cannot be reached there.
void WorkerPolicy::march_in_window(Cell from, const std::vector<Cell>& targets, double* out) {
  if (window_ && window_->march(from, targets, out)) return;
  march(from, targets, out);
}

void WorkerPolicy::learn(const KnownGoal* goals, std::size_t n) {
  if (n > max_goals_)
    throw Error("mission", "worker " + std::to_string(agent_.value()) + ": " + std::to_string(n) +
                               " goals in a request, at most " + std::to_string(max_goals_));
  const OccupancyGrid& grid = world_.scenario.grid;
  for (std::size_t i = 0; i < n; ++i) {
    const Cell c = goals[i].cell;
    if (!grid.contains(c) || segment_index(c) < 0)
      throw Error("mission", "worker " + std::to_string(agent_.value()) + ": " + to_string(goals[i].id) +
                                 " is not in its segment");
  }
  const std::size_t nr = rendezvous_.size();
  n_ = n;
  stride_ = n + nr;
  std::copy(goals, goals + n, goals_.begin());
  cells_.clear();
  for (std::size_t i = 0; i < n; ++i) cells_.push_back(goals[i].cell);
  cells_.insert(cells_.end(), rendezvous_.begin(), rendezvous_.end());
  std::fill(from_.begin(), from_.begin() + static_cast<long>(n * stride_), 0.0);
  // Geodesic distances are symmetric (up to the march's discretisation): goal
  // i marches to the later goals only, which halves the work.
  for (std::size_t i = 0; i < n; ++i) {
    if (i + 1 < n) {
      targets_.assign(cells_.begin() + static_cast<long>(i) + 1, cells_.begin() + static_cast<long>(n));
      tmp_.resize(targets_.size());
      march_in_window(cells_[i], targets_, tmp_.data());
      for (std::size_t j = i + 1; j < n; ++j) from_[i * stride_ + j] = from_[j * stride_ + i] = tmp_[j - i - 1];
    }
    const std::size_t local = static_cast<std::size_t>(segment_index(cells_[i]));
    for (std::size_t r = 0; r < nr; ++r) from_[i * stride_ + n + r] = rendezvous_to_cell_[r][local];
  }
}

void WorkerPolicy::from_landing(Cell landing, const Cell* targets, std::size_t n, double* out) {
  const OccupancyGrid& grid = world_.scenario.grid;
  const std::size_t key = grid.index(landing);
  auto it =
      std::find_if(landing_to_cell_.begin(), landing_to_cell_.end(), [&](const auto& e) { return e.first == key; });
  if (it == landing_to_cell_.end()) {
    // A free table (made up front by reserve_all), or a new one while there is room.
    it = std::find_if(landing_to_cell_.begin(), landing_to_cell_.end(),
                      [](const auto& e) { return e.first == static_cast<std::size_t>(-1); });
    if (it == landing_to_cell_.end() && landing_to_cell_.size() < kMaxLandings) {
      landing_to_cell_.emplace_back(static_cast<std::size_t>(-1), std::vector<float>(segment_cells_.size()));
      it = landing_to_cell_.end() - 1;
    }
    if (it == landing_to_cell_.end()) {
      targets_.assign(targets, targets + n);
      march(landing, targets_, out);
      return;
    }
    tmp_.resize(segment_cells_.size());
    march(landing, segment_cells_, tmp_.data());
    it->first = key;
    std::copy(tmp_.begin(), tmp_.end(), it->second.begin());
  }
  for (std::size_t i = 0; i < n; ++i) out[i] = it->second[static_cast<std::size_t>(segment_index(targets[i]))];
}

void WorkerPolicy::distances_from(const Spot& at) {
  const OccupancyGrid& grid = world_.scenario.grid;
  const std::size_t nr = rendezvous_.size();
  if (at.rendezvous >= 0) {
    const std::size_t rv = static_cast<std::size_t>(at.rendezvous);
    for (std::size_t i = 0; i < n_; ++i) from_position_[i] = from_[i * stride_ + n_ + rv];
    for (std::size_t r = 0; r < nr; ++r) from_position_[n_ + r] = rendezvous_to_rendezvous_[rv][r];
  } else if (at.meeting && meeting_cell_.row >= 0) {
    for (std::size_t i = 0; i < n_; ++i)
      from_position_[i] = meeting_to_cell_[static_cast<std::size_t>(segment_index(cells_[i]))];
    for (std::size_t r = 0; r < nr; ++r) from_position_[n_ + r] = meeting_to_rv_[r];
  } else if (at.cell == world_.oc_cell && !shared_.from_oc.empty()) {
    for (std::size_t i = 0; i < cells_.size(); ++i) from_position_[i] = shared_.from_oc[grid.index(cells_[i])];
  } else if (at.landing) {
    from_landing(at.cell, cells_.data(), cells_.size(), from_position_.data());
  } else {
    march(at.cell, cells_, from_position_.data());
  }
}

// Arrival times [s] at the goals of the tour, leaving at t; the list stops
// before the first goal reached after its deadline. Returns how many.
std::size_t WorkerPolicy::arrival_times(double t) {
  double clock = t;
  std::size_t k = 0;
  for (std::size_t i = 0; i < tour_n_; ++i) {
    const std::size_t o = static_cast<std::size_t>(tour_[i]);
    clock += (i == 0 ? from_position_[o] : from_[static_cast<std::size_t>(tour_[i - 1]) * stride_ + o]) / v_;
    if (clock > goals_[o].deadline + kEps) break;
    at_[k++] = clock;
  }
  return k;
}

void WorkerPolicy::order_tour(const int* known, std::size_t n_known) {
  mission::order_tour(TourDistances{from_position_.data(), from_.data(), stride_}, known, n_known, tour_.data(),
                      used_.data(), two_opt_rounds_);
  tour_n_ = n_known;
}

// The hand-over of `load` goals at rendezvous r by a worker standing there
// from `arrive` [s]: at the collector's first pass whose link window still
// holds for the transfer (and the guard) after the worker is there; the
// transfer starts when both are there and linked. done = +inf when no
// window of r is long enough for the load.
WorkerPolicy::Meeting WorkerPolicy::meeting_at(std::size_t r, double arrive, std::size_t load, double delay) const {
  Meeting m;
  m.done = kInf;
  const double v = route_->speed(), s = rendezvous_arc_[r];
  const double before = (s - link_window_[r].first) / v, after = (link_window_[r].second - s) / v;
  const double need = transfer_s(world_.scenario, load), guard = handover_guard(before + after);
  if (before + after < need + guard - kEps) return m;
  // The pass on the timetable shifted by the collector's delay.
  const double h = route_->next_time_at(s, std::max(0.0, arrive + need + guard - after) - delay) + delay;
  m.rv = static_cast<int>(r);
  m.start = std::max(arrive, h - before);
  m.done = m.start + need;
  m.until = h + after;
  m.pass = h;
  return m;
}

// The earliest hand-over of `load` goals after measuring the first k goals
// of the tour, over every rendezvous (and not before no_meeting_before).
WorkerPolicy::Meeting WorkerPolicy::earliest_meeting(std::size_t k, double t, double no_meeting_before,
                                                     std::size_t load, double delay) const {
  Meeting best;
  best.done = kInf;
  for (std::size_t r = 0; r < rendezvous_.size(); ++r) {
    const double dist = k == 0 ? position_to_rv_[r] : from_[static_cast<std::size_t>(tour_[k - 1]) * stride_ + n_ + r];
    if (!(dist < kInf)) continue;
    const double arrive = std::max((k == 0 ? t : at_[k - 1]) + dist / v_, no_meeting_before);
    const Meeting m = meeting_at(r, arrive, load, delay);
    if (m.done < best.done) best = m;
  }
  return best;
}

WorkerPolicy::Decision WorkerPolicy::decide(const Spot& at, double t, const int* known, std::size_t n_known,
                                            std::size_t carried, bool more_requests, double no_meeting_before,
                                            const Facts& facts) {
  const double collector_delay = facts.collector_delay;
  const double pace = tours_at_team_speed() ? 1.0 : facts.pace;
  v_ = speed_ * pace;
  const bool carrying = carried > 0;
  Decision d;
  d.pace = pace;
  d.tour = tour_.data();
  d.at = at_.data();
  std::size_t kmax = 0;
  tour_n_ = 0;
  if (n_known > 0) {
    distances_from(at);
    order_tour(known, n_known);
    kmax = arrival_times(t);
    // A hand-over carries at most capacity_ goals: measure no more than it
    // can still hand over (the rest expire, reported).
    if (!delivers_to_oc()) kmax = std::min(kmax, capacity_ > carried ? capacity_ - carried : 0);
  }
  if (delivers_to_oc()) {
    // Measure every goal that can still be measured in time, then come back.
    if (kmax > 0) {
      d.action = Action::kWork;
      d.k = kmax;
      return d;
    }
    if (!world_.covered(at.cell)) {
      d.action = Action::kBackToCoverage;
      const auto back = way_back(at.cell);
      d.landing = back.first;
      d.arrive = t + back.second / v_;
      return d;
    }
    // At home: on its cell, or on robots back within the place tolerance.
    const Point2 h = world_.scenario.grid.cell_center(home_), p = world_.scenario.grid.cell_center(at.cell);
    const bool at_home =
        at.cell == home_ || (back_to_home() && at.landing && std::hypot(h.x - p.x, h.y - p.y) <= place_tolerance_m_);
    if ((more_requests || back_to_home()) && home_.row >= 0 && !at_home) {
      // Nothing to do in the coverage: wait for the next request at home.
      // On robots also when none is to come: a robot that stopped where it
      // came back in stands in the way of the others (at the end of a
      // mission, five of them across an office corridor held two robots
      // carrying data outside the coverage until the OC declared them dead).
      double dist = kInf;
      march_one(at.cell, home_, dist);
      if (dist < kInf) {
        d.action = Action::kGoToMeeting;
        d.landing = home_;
        d.arrive = t + dist / v_;
        return d;
      }
    }
    d.action = more_requests ? Action::kWait : Action::kDone;
    return d;
  }

  const OccupancyGrid& grid = world_.scenario.grid;
  if (kmax == 0 && !carrying && !more_requests && (at.meeting || meeting_cell_.row < 0)) return d;  // kDone
  const std::size_t nr = rendezvous_.size();
  if (n_known == 0 && at.rendezvous >= 0) {
    std::copy(rendezvous_to_rendezvous_[static_cast<std::size_t>(at.rendezvous)].begin(),
              rendezvous_to_rendezvous_[static_cast<std::size_t>(at.rendezvous)].end(), position_to_rv_.begin());
  } else if (n_known == 0 && at.meeting && meeting_cell_.row >= 0) {
    std::copy(meeting_to_rv_.begin(), meeting_to_rv_.end(), position_to_rv_.begin());
  } else if (n_known == 0 && at.cell == world_.oc_cell && !shared_.from_oc.empty()) {
    for (std::size_t r = 0; r < nr; ++r) position_to_rv_[r] = shared_.from_oc[grid.index(rendezvous_[r])];
  } else if (n_known == 0) {
    march(at.cell, rendezvous_, position_to_rv_.data());
  } else {
    for (std::size_t r = 0; r < nr; ++r) position_to_rv_[r] = from_position_[n_ + r];
  }
  if (kmax == 0 && !carrying) {
    // Nothing to do: wait for the next request at the meeting point, where
    // the collector hands it over (going there first: this is how workers
    // reach their segments at the start); with no request to come, end
    // there too (the collector passes it every loop: whatever the worker
    // still has to report reaches it).
    if (meeting_cell_.row >= 0) {
      if (at.meeting) {
        d.action = more_requests ? Action::kWait : Action::kDone;
        return d;
      }
      double dist = kInf;
      if (at.rendezvous >= 0)
        dist = meeting_to_rv_[static_cast<std::size_t>(at.rendezvous)];
      else if (at.cell == world_.oc_cell && !shared_.from_oc.empty())
        dist = shared_.from_oc[grid.index(meeting_cell_)];
      else
        march_one(at.cell, meeting_cell_, dist);
      if (dist < kInf) {
        d.action = Action::kGoToMeeting;
        d.landing = meeting_cell_;
        d.arrive = t + dist / v_;
        return d;
      }
    }
    // No way to the meeting point: the nearest pass.
    if (!more_requests) return d;  // kDone
    if (at.rendezvous < 0) {
      const std::size_t r = static_cast<std::size_t>(std::min_element(position_to_rv_.begin(), position_to_rv_.end()) -
                                                     position_to_rv_.begin());
      if (!(position_to_rv_[r] < kInf))
        bug("worker " + std::to_string(agent_.value()) + " cannot reach any pass of its collector");
      d.action = Action::kGoToRendezvous;
      d.rendezvous = static_cast<int>(r);
      d.arrive = t + position_to_rv_[r] / v_;
      return d;
    }
    d.action = Action::kWait;
    return d;
  }
  // The earliest hand-over reachable after measuring at least one goal; then
  // as many goals of the tour as can still be handed over in that same pass's
  // link window: the worker measures until the latest moment from which it
  // reaches the rendezvous in time for the transfer of all it carries to end
  // within the window (less the guard), walking to meet the collector in
  // movement instead of waiting for its pass.
  std::size_t k = 0;
  Meeting meet;
  if (kmax == 0) {
    meet = earliest_meeting(0, t, no_meeting_before, carried, collector_delay);
  } else {
    meet = earliest_meeting(1, t, no_meeting_before, carried + 1, collector_delay);
    k = 1;
    const double until = meet.until;
    for (std::size_t j = 2; j <= kmax && meet.rv >= 0; ++j) {
      const Meeting m = earliest_meeting(j, t, no_meeting_before, carried + j, collector_delay);
      if (m.done <= until + kEps) k = j, meet = m;
    }
  }
  // (The load never exceeds capacity_, which the longest window holds.)
  if (!(meet.done < kInf)) bug("worker " + std::to_string(agent_.value()) + " cannot reach any pass of its collector");
  const std::size_t rv = static_cast<std::size_t>(meet.rv);
  const double dist = k == 0 ? position_to_rv_[rv] : from_[static_cast<std::size_t>(tour_[k - 1]) * stride_ + n_ + rv];
  d.action = Action::kWork;
  d.k = k;
  d.rendezvous = meet.rv;
  d.arrive = (k == 0 ? t : at_[k - 1]) + dist / v_;
  d.handover = meet.done;
  d.link_until = meet.until;
  d.pass = meet.pass;
  return d;
}

std::pair<Cell, double> WorkerPolicy::way_back(Cell from) const {
  const double dist = world_.coverage_field.time(from);
  const int label = world_.coverage_field.label(from);
  if (!(dist < kInf) || label < 0) bug("worker " + std::to_string(agent_.value()) + " cannot reach the OC's coverage");
  if (back_to_home()) {
    const double on = home_to_border_[static_cast<std::size_t>(label)];
    if (on < kInf) return {home_, dist + on};
  }
  return {world_.coverage_border[static_cast<std::size_t>(label)], dist};
}

}  // namespace mission
}  // namespace gather
