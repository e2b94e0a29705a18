// The worker role: WorkerRole's state machine around mission::WorkerPolicy
// (requests in, measurements, custody of the data, hand-overs, expiry, repair
// after a death, restore from a journal). Over 400 lines because it is one
// state machine whose transitions read the same state; the decisions
// themselves live in the shared policy (mission/worker_policy).
#include "gather_agent/roles/worker_role.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

int trace_id() {
  static const int id = std::getenv("GATHER_TRACE") ? std::atoi(std::getenv("GATHER_TRACE")) : -100;
  return id;
}
#define TRACE(...) \
  if (id_ == trace_id()) std::fprintf(stderr, __VA_ARGS__)

constexpr double kEps = 1e-9;  // [s] as the simulator's time tolerance
constexpr double kInf = std::numeric_limits<double>::infinity();

// Room for this many goals of one request in a worker's segment before its
// buffers grow (and its control step allocates): every goal of a request,
// up to 256 (the distance matrix is 8 B x goals x (goals + passes)).
std::size_t initial_goals(const TeamSetup& team) {
  return std::min<std::size_t>(static_cast<std::size_t>(team.params.goals_per_request), 256);
}

}  // namespace

WorkerRole::WorkerRole(TeamSetup& team, AgentId agent, MotionBackend& motion)
    : Role(static_cast<int16_t>(agent.value()), motion),
      team_(team),
      policy_(std::make_unique<mission::WorkerPolicy>(
          team.world, team.plan, team.assignment(agent),
          team.assignment(agent).delivers_to.valid() ? &team.routes[team.assignment(agent).delivers_to] : nullptr,
          *team.distances, initial_goals(team), team.params.protocol,
          team.oc_homes.empty() ? nullptr : &team.oc_homes)),
      custody_(team.params.data_capacity, team.params.notice_capacity) {
  if (!policy_->delivers_to_oc()) upstream_ = static_cast<int16_t>(team.collector_agent(policy_->collector()).value());
  const std::size_t g = static_cast<std::size_t>(team.params.goals_per_request);
  request_.mine.reserve(initial_goals(team));
  scratch_.reserve(initial_goals(team));
  known_.reserve(g);
  measured_in_step_.reserve(g);
  legs_.resize(g + 2);
  leg_goal_.resize(g + 2);
  old_legs_.resize(g + 2);
  old_goal_.resize(g + 2);
  leg_nominal_.resize(g + 2);
  old_nominal_.resize(g + 2);
  policy_->reserve_all();  // no allocation in the control step after this
  if (motion.max_legs() < g + 2)
    throw Error(to_string(agent), "its motion backend takes " + std::to_string(motion.max_legs()) +
                                      " legs, a plan may need " + std::to_string(g + 2));
  // Beacons spread over the period, so they do not all go out in one tick.
  next_beacon_ = team.params.beacon_period * static_cast<double>(agent.value() % 10) / 10.0;
  counters_.role = RoleKind::kWorker;
  counters_.id = agent.value();
  const int segment = team.assignment(agent).segment.label();
  served_cells_ = std::count(team.plan.labels.begin(), team.plan.labels.end(), segment);
  if (!policy_->delivers_to_oc()) {
    // As long as the OC waits before it declares a worker of that collector
    // dead: a live worker hears its collector at least once a loop and a
    // request (it may tour through a pass), so silence for that long means
    // the collector is gone (the OC, which declares the collector sooner,
    // answers a worker that comes to it all the same).
    const double loop = std::max(team.routes[policy_->collector()].period(), team.period);
    suspect_after_ =
        mission::silent_timeout(mission::Liveness::kCollectorWorker, team.period, loop, team.params.silent_intervals);
  }
  dead_.reserve(kMaxDead);
}

double WorkerRole::deadline(int cycle, double delay) const {
  return policy_->delivers_to_oc() ? kInf : team_.deadline(policy_->agent(), cycle) + delay;
}

void WorkerRole::progress(Progress& out) const {
  out.resolved = resolved_;
  out.measured = counters_.measured, out.dropped = counters_.dropped;
  out.expired = counters_.expired, out.skipped = counters_.skipped;
  out.dead.assign(dead_.begin(), dead_.end());
  out.revoked = revoked_;
  out.learned.clear();
  for (std::size_t i = 0; i < policy_->goals(); ++i) out.learned.push_back(policy_->goal(i));
  out.known.clear();
  for (int local : known_) out.known.push_back(policy_->goal(static_cast<std::size_t>(local)).id);
}

void WorkerRole::restore(const DataItem* items, std::size_t n, const Progress& p, double now) {
  for (std::size_t i = 0; i < n; ++i)
    if (custody_.put(items[i]) == Custody::Put::kFull) ++counters_.refused_full;
  counters_.measured = p.measured, counters_.dropped = p.dropped;
  counters_.expired = p.expired, counters_.skipped = p.skipped;
  dead_.assign(p.dead.begin(), p.dead.end());
  revoked_ = p.revoked;
  if (!dead_.empty()) repair(now);
  if (retired_) return;
  resolved_ = p.resolved;
  upstream_heard_ = now;
  // The request it worked on: its goals again (distances recomputed), those
  // not measured yet still to do; one its segment no longer holds (a repair
  // it did not journal) is reported expired, never dropped silently.
  scratch_.clear();
  for (const mission::KnownGoal& g : p.learned)
    if (policy_->in_segment(g.cell)) scratch_.push_back(g);
  policy_->reserve(scratch_.size());
  policy_->learn(scratch_.data(), scratch_.size());
  known_.clear();
  for (GoalId id : p.known) {
    bool found = false;
    for (std::size_t i = 0; i < scratch_.size() && !found; ++i)
      if (scratch_[i].id == id) known_.push_back(static_cast<int>(i)), found = true;
    if (!found) notice(ItemKind::kExpired, id.value(), now);
  }
  phase_ = resolved_ >= 0 ? Phase::kReady : Phase::kStart;
  ++progress_version_;
}

void WorkerRole::repair(double now) {
  std::vector<int16_t> set(dead_);
  if (suspected_ >= 0) set.push_back(suspected_);
  const mission::RepairedPlan& r = team_.repaired(set.data(), set.size());
  if (r.dead[policy_->agent()]) {  // declared dead while alive: it stops for good
    retired_ = true;
    motion_.stop(now);
    phase_ = Phase::kDone;
    TRACE("%.1f retired: declared dead\n", now);
    return;
  }
  const plan::AgentAssignment& a = r.plan.file.agents[policy_->agent()];
  const int64_t cells = std::count(r.plan.labels.begin(), r.plan.labels.end(), a.segment.label());
  const bool new_upstream = a.delivers_to != policy_->collector();
  if (!new_upstream && cells == served_cells_) return;
  const mission::RouteTimetable* route = a.delivers_to.valid() ? &team_.routes[a.delivers_to] : nullptr;
  auto fresh = std::make_unique<mission::WorkerPolicy>(team_.world, r.plan, a, route, *team_.distances,
                                                       policy_->max_goals(), team_.params.protocol);
  fresh->reserve_all();
  // The current request's goals, in the same order: the plan under way
  // refers to them by their local index.
  // Those the new segment does not hold (it can shrink: a collector
  // suspected, then heard again) are expired now, never an error.
  scratch_.clear();
  std::vector<int> local(policy_->goals(), -1);
  for (std::size_t i = 0; i < policy_->goals(); ++i)
    if (fresh->in_segment(policy_->goal(i).cell))
      local[i] = static_cast<int>(scratch_.size()), scratch_.push_back(policy_->goal(i));
  fresh->learn(scratch_.data(), scratch_.size());
  std::size_t kept = 0;
  for (const int k : known_) {
    if (local[static_cast<std::size_t>(k)] >= 0)
      known_[kept++] = local[static_cast<std::size_t>(k)];
    else
      notice(ItemKind::kExpired, policy_->goal(static_cast<std::size_t>(k)).id.value(), now);
  }
  known_.resize(kept);
  for (std::size_t i = 0; i < n_legs_; ++i)
    if (leg_goal_[i] >= 0) leg_goal_[i] = local[static_cast<std::size_t>(leg_goal_[i])];
  policy_ = std::move(fresh);
  served_cells_ = cells;
  upstream_ = route ? static_cast<int16_t>(team_.collector_agent(a.delivers_to).value()) : kOc;
  TRACE("%.1f repaired: segment cells %lld, delivers to %d\n", now, static_cast<long long>(cells),
        a.delivers_to.value());
  if (new_upstream && phase_ != Phase::kMoving) phase_ = Phase::kReady;  // decide again, for the OC
  if (new_upstream) heard_oc_ = false, last_hello_ = -kInf, transfer_since_ = -1.0;
}

RoleReport WorkerRole::report() const {
  RoleReport r = counters_;
  r.pending = static_cast<int64_t>(known_.size());
  r.requests = newest_request();
  r.dead_known = static_cast<int64_t>(dead_.size());
  r.legs = legs_stats_.legs(), r.legs_late = legs_stats_.late();
  r.late_median_s = legs_stats_.median_late(), r.late_max_s = legs_stats_.max_late();
  r.refused_revoked = refused_revoked();
  return r;
}

bool WorkerRole::contact(double now) const {
  const Point2 here = motion_.pose();
  if (policy_->delivers_to_oc()) return team_.linked(here, team_.world.scenario.oc);
  // Where its collector is: its timetable, as late as it last said it was.
  return team_.linked(here, policy_->route()->position(now - collector_delay_));
}

double WorkerRole::due_time() const {
  if (resolved_ + 1 >= team_.params.cycles) return kInf;
  if (policy_->delivers_to_oc()) return (resolved_ + 1) * team_.period;
  // A worker of a collector: when the next request reaches it.
  return resolved_ < 0
             ? 0.0
             : mission::request_reaches_worker(*policy_->route(), policy_->meeting_arc(), resolved_ + 1, team_.period);
}

void WorkerRole::on_request(const RequestPart& part, int16_t, double delay) {
  const OccupancyGrid& grid = team_.world.scenario.grid;
  if (part.request <= resolved_ || part.request < request_.id) return;  // old news
  if (part.request >= team_.params.cycles || part.parts == 0 || part.parts > kMaxRequestParts ||
      part.part >= part.parts || part.count > kRequestPartGoals || part.total > team_.params.goals_per_request ||
      part.first_goal < 0 || part.first_goal > std::numeric_limits<int32_t>::max() - part.total)
    return;  // not a request of this mission
  TRACE("request %d part %d from %d\n", part.request, part.part, 0);
  if (part.request > request_.id) {
    request_.id = part.request;
    request_.parts = part.parts;
    request_.seen = 0;
    request_.delay = delay;
    request_.mine.clear();
  }
  if (part.parts != request_.parts || ((request_.seen >> part.part) & 1)) return;
  request_.seen |= 1ull << part.part;
  for (uint16_t k = 0; k < part.count; ++k) {
    const uint32_t cell = part.cells[k];
    if (cell >= grid.size() || !policy_->in_segment(grid.cell(cell))) continue;
    const int64_t index = static_cast<int64_t>(part.part) * kRequestPartGoals + k;
    if (index >= part.total) break;
    const GoalId goal(part.first_goal + static_cast<int32_t>(index));
    request_.mine.push_back(mission::KnownGoal{goal, grid.cell(cell), 0.0});
  }
}

const char* WorkerRole::phase_name(int phase) {
  static const char* const names[] = {"start", "ready", "moving", "at_pass", "settling", "waiting", "done"};
  return phase >= 0 && phase < 7 ? names[phase] : "?";
}

void WorkerRole::notice(ItemKind kind, int32_t key, double at) {
  ++progress_version_;
  DataItem item;
  item.key = key, item.kind = kind, item.by = id_, item.at = at;
  item.deadline = key >= 0 ? goal_deadline(GoalId(key)) : kInf;
  if (custody_.put(item) == Custody::Put::kFull) ++counters_.lost_notices;
  if (kind == ItemKind::kExpired) ++counters_.expired;
  if (kind == ItemKind::kSkipped) ++counters_.skipped;
  if (kind == ItemKind::kDropped) ++counters_.dropped;
  if (kind == ItemKind::kUnreachable) ++counters_.unreachable;
}

double WorkerRole::goal_deadline(GoalId goal) const {
  for (std::size_t i = 0; i < policy_->goals(); ++i)
    if (policy_->goal(i).id == goal) return policy_->goal(i).deadline;
  return kInf;
}

void WorkerRole::measure(int local, double at) {
  const mission::KnownGoal& g = policy_->goal(static_cast<std::size_t>(local));
  const GoalId goal = g.id;
  const auto it = std::find(known_.begin(), known_.end(), local);
  if (it == known_.end()) return;  // expired meanwhile (within the deadline's tolerance): its notice is out
  known_.erase(it);
  ++progress_version_;
  if (at > g.deadline + kEps) {  // its robot got there too late: the goal expired on the way
    notice(ItemKind::kExpired, goal.value(), g.deadline);
    return;
  }
  if (custody_.data_full()) {
    notice(ItemKind::kDropped, goal.value(), at);  // the measurement has no room: reported, never silently lost
    return;
  }
  DataItem item;
  item.key = goal.value(), item.kind = ItemKind::kMeasured, item.by = id_, item.at = at;
  item.deadline = g.deadline;
  custody_.put(item);
  ++counters_.measured;
  measured_in_step_.push_back(goal);
}

// Collector workers: a request whose deadline has passed before it reached
// the worker can no longer be measured (it was superseded on the way, or
// never heard): its goals here expire, reported as one notice.
void WorkerRole::skip_overdue(double now) {
  if (policy_->delivers_to_oc()) return;
  while (resolved_ + 1 < team_.params.cycles) {
    const int c = resolved_ + 1;
    const double d = deadline(c, collector_delay_);
    if (d > now + kEps) break;
    notice(ItemKind::kSkipped, skipped_key(c, id_), d);
    TRACE("%.1f skip request %d (deadline %.1f)\n", now, c, d);
    resolved_ = c;
  }
}

void WorkerRole::expire_overdue(double now) {
  for (std::size_t i = 0; i < known_.size();) {
    const mission::KnownGoal& g = policy_->goal(static_cast<std::size_t>(known_[i]));
    if (g.deadline <= now + kEps) {
      notice(ItemKind::kExpired, g.id.value(), g.deadline);
      known_.erase(known_.begin() + static_cast<long>(i));
    } else {
      ++i;
    }
  }
}

bool WorkerRole::settled(double now, bool in_contact) {
  switch (phase_) {
    case Phase::kStart:
      // Request 0, or (it missed request 0: its deadline passed) the way to
      // where the next one comes.
      return (request_.complete() && request_.id > resolved_) || resolved_ >= 0;
    case Phase::kReady: return true;
    case Phase::kMoving:
    case Phase::kDone: return false;
    case Phase::kAtPass: {
      // Decide again once the data is gone (taken on the way or at the pass),
      // or when its collector said it is later (or earlier) than the plan
      // assumed; a pass without a link keeps the data for a later one.
      if (custody_.data() == 0) return true;
      if (std::abs(collector_delay_ - delay_used_) > team_.params.protocol.replan_guard_s) return true;
      if (now >= link_until_ && !in_contact) {
        // Not a word from its collector since before the pass was due: it
        // is late, by now - its timetable's pass at least. It waits on for
        // it, up to a bound.
        const double on_time = pass_ - delay_used_;
        const double bound = team_.params.protocol.wait_loops * policy_->route()->period();
        if (upstream_heard_ < on_time - 1.0 && now - on_time <= bound) {
          collector_delay_ = std::max(collector_delay_, now - on_time);
          TRACE("%.1f collector not seen at the pass due %.1f: assumed %.1f s late\n", now, on_time, collector_delay_);
          return true;
        }
        no_meeting_before_ = link_until_ + 1.0;
        return true;
      }
      return false;
    }
    case Phase::kSettling:
      // Back in the coverage: everything delivered, and the OC said which
      // request is newest (and passed it on if this worker lacked it).
      return custody_.data() == 0 && heard_oc_ && oc_newest_ <= newest_request();
    case Phase::kWaiting:
      return (request_.complete() && request_.id > resolved_) || resolved_ + 1 >= team_.params.cycles;
  }
  return false;
}

void WorkerRole::decide(double now) {
  const OccupancyGrid& grid = team_.world.scenario.grid;
  const bool oc_worker = policy_->delivers_to_oc();
  const bool may_learn =
      !oc_worker || team_.world.covered(grid.world_to_cell(motion_.pose()));  // OC workers: in the coverage
  if (may_learn && request_.complete() && request_.id > resolved_) {
    // Requests in between never reached this worker; what is left of the
    // older one is superseded by the newer (its goals expire when a newer
    // request reaches the worker: now, if that is before the timetable's
    // deadline, as after a collector's restart that lost a request).
    for (int c = resolved_ + 1; c < request_.id; ++c)
      notice(ItemKind::kSkipped, skipped_key(c, id_), oc_worker ? now : std::min(now, deadline(c, request_.delay)));
    for (int local : known_) notice(ItemKind::kExpired, policy_->goal(static_cast<std::size_t>(local)).id.value(), now);
    known_.clear();
    const double due =
        oc_worker ? mission::request_deadline(now, kInf, team_.period) : deadline(request_.id, request_.delay);
    learned_delay_ = request_.delay;
    scratch_.assign(request_.mine.begin(), request_.mine.end());
    // A goal outside its segment (the OC's repaired plan and this worker's
    // differ for a while on who is dead): expired now, never an error.
    std::size_t kept = 0;
    for (std::size_t i = 0; i < scratch_.size(); ++i) {
      if (policy_->in_segment(scratch_[i].cell))
        scratch_[kept++] = scratch_[i];
      else
        notice(ItemKind::kExpired, scratch_[i].id.value(), now);
    }
    scratch_.resize(kept);
    for (mission::KnownGoal& g : scratch_) g.deadline = due;
    policy_->reserve(scratch_.size());
    policy_->learn(scratch_.data(), scratch_.size());
    for (std::size_t i = 0; i < scratch_.size(); ++i) known_.push_back(static_cast<int>(i));
    resolved_ = request_.id;
    ++progress_version_;
  }
  const bool more = resolved_ + 1 < team_.params.cycles;
  // Where its robot stands: a reachable cell (a real robot's pose may sit
  // on a wall's edge).
  const Cell here = team_.world.standing_cell(motion_.pose());
  if (!team_.world.reaches(here)) {  // far off the free space: it waits until its robot is back on it
    phase_ = Phase::kReady;
    return;
  }
  const mission::Spot spot{here, at_rv_, at_landing_, at_meeting_};
  mission::WorkerPolicy::Facts facts;
  facts.collector_delay = collector_delay_;
  facts.pace = pace_;
  const mission::WorkerPolicy::Decision d =
      policy_->decide(spot, now, known_.data(), known_.size(), custody_.data(), more, no_meeting_before_, facts);
  delay_used_ = collector_delay_;
  pace_used_ = d.pace;
  eta_base_ = kInf;
  TRACE("%.1f decide: resolved %d known %zu carrying %zu -> action %d k %zu rv %d arrive %.1f handover %.1f\n", now,
        resolved_, known_.size(), custody_.data(), static_cast<int>(d.action), d.k, d.rendezvous, d.arrive, d.handover);

  // Deciding again while its robot drives: the command under way, kept if
  // the new plan drives the same way (a new command would only disturb the
  // robot); its times are the new plan's.
  const bool driving = (phase_ == Phase::kMoving || replan_driving_) &&
                       (motion_.state() == NavState::kActive || motion_.state() == NavState::kBlocked);
  replan_driving_ = false;
  const std::size_t old_n = n_legs_, old_seen = legs_seen_;
  if (driving) {
    std::copy(legs_.begin(), legs_.begin() + static_cast<long>(old_n), old_legs_.begin());
    std::copy(leg_goal_.begin(), leg_goal_.begin() + static_cast<long>(old_n), old_goal_.begin());
    std::copy(leg_nominal_.begin(), leg_nominal_.begin() + static_cast<long>(old_n), old_nominal_.begin());
  }
  n_legs_ = 0, legs_seen_ = 0;
  plan_is_work_ = false, ends_at_landing_ = false, ends_at_meeting_ = false, target_rv_ = -1, back_in_ = false;
  // Goals and the landing back into the coverage (a border cell: near is
  // not in) take the robot's own tolerance; places it waits at, the place
  // tolerance.
  const double place = team_.params.protocol.place_tolerance_m;
  auto leg = [&](Point2 p, double arrive, int goal, bool exact = false) {
    if (n_legs_ >= legs_.size()) return;  // cannot happen: a request holds at most goals_per_request goals
    legs_[n_legs_] = Waypoint{p, arrive, goal >= 0 || exact ? 0.0 : place};
    leg_goal_[n_legs_++] = goal;
  };
  using Action = mission::WorkerPolicy::Action;
  switch (d.action) {
    case Action::kDone:
      motion_.stop(now);
      phase_ = Phase::kDone;
      return;
    case Action::kWait:
      motion_.stop(now);
      phase_ = Phase::kWaiting;
      return;
    case Action::kGoToRendezvous:
      leg(policy_->rendezvous_point(d.rendezvous), d.arrive, -1);
      target_rv_ = d.rendezvous;
      break;
    case Action::kBackToCoverage:
      leg(grid.cell_center(d.landing), d.arrive, -1, true);
      ends_at_landing_ = true;
      back_in_ = policy_->back_to_home();
      break;
    case Action::kGoToMeeting:  // a worker of the OC: its home in the coverage
      leg(grid.cell_center(d.landing), d.arrive, -1);
      (oc_worker ? ends_at_landing_ : ends_at_meeting_) = true;
      break;
    case Action::kWork:
      for (std::size_t i = 0; i < d.k; ++i)
        leg(grid.cell_center(policy_->goal(static_cast<std::size_t>(d.tour[i])).cell), d.at[i], d.tour[i]);
      if (!oc_worker) {
        leg(policy_->rendezvous_point(d.rendezvous), d.arrive, -1);
        target_rv_ = d.rendezvous;
        handover_ = d.handover;
        link_until_ = d.link_until;
        pass_ = d.pass;
        plan_is_work_ = true;
      } else {
        const Cell last = policy_->goal(static_cast<std::size_t>(d.tour[d.k - 1])).cell;
        if (!team_.world.covered(last)) {
          const auto back = policy_->way_back(last);
          leg(grid.cell_center(back.first), d.at[d.k - 1] + back.second / (team_.speed * d.pace), -1, true);
          ends_at_landing_ = true;
          back_in_ = policy_->back_to_home();
        }
      }
      break;
  }
  if (n_legs_ == 0) {  // cannot happen: every action above drives somewhere
    motion_.stop(now);
    phase_ = Phase::kReady;
    return;
  }
  bool same = driving && n_legs_ == old_n - old_seen;
  for (std::size_t i = 0; same && i < n_legs_; ++i)
    same = legs_[i].point.x == old_legs_[old_seen + i].point.x && legs_[i].point.y == old_legs_[old_seen + i].point.y &&
           leg_goal_[i] == old_goal_[old_seen + i];
  if (same) {
    for (std::size_t i = n_legs_; i-- > 0;) {  // after the legs already driven, as the robot counts them
      legs_[old_seen + i] = legs_[i];
      leg_goal_[old_seen + i] = leg_goal_[i];
    }
    std::copy(old_legs_.begin(), old_legs_.begin() + static_cast<long>(old_seen), legs_.begin());
    std::copy(old_goal_.begin(), old_goal_.begin() + static_cast<long>(old_seen), leg_goal_.begin());
    // The legs as first planned: their travel times, and when the one
    // under way began, stay.
    std::copy(old_nominal_.begin(), old_nominal_.begin() + static_cast<long>(old_n), leg_nominal_.begin());
    n_legs_ = old_n, legs_seen_ = old_seen;
  } else {
    // Each leg's travel time at the team speed: its planned time at the
    // pace this decision assumed. A leg to a pass is left out (its planned
    // time may hold a wait for the collector: no_meeting_before).
    for (std::size_t i = 0; i < n_legs_; ++i)
      leg_nominal_[i] =
          oc_worker || leg_goal_[i] >= 0 ? (legs_[i].arrive - (i == 0 ? now : legs_[i - 1].arrive)) * pace_used_ : -1.0;
    // A new command whose first leg drives on to where the robot was
    // driving: the same leg, begun when it began.
    const bool goes_on = driving && old_seen < old_n && legs_[0].point.x == old_legs_[old_seen].point.x &&
                         legs_[0].point.y == old_legs_[old_seen].point.y && leg_goal_[0] == old_goal_[old_seen];
    if (goes_on)
      leg_nominal_[0] = old_nominal_[old_seen];
    else
      leg_began_ = now;
    motion_.go(legs_.data(), n_legs_, now);
  }
  phase_ = Phase::kMoving;
  into_coverage_ = false;
  at_rv_ = -1, at_landing_ = false, at_meeting_ = false;
}

double WorkerRole::back_by(double now) const {
  const double end = legs_[n_legs_ - 1].arrive;
  return std::max(now, pace_used_ == pace_ ? end : now + (end - now) * pace_used_ / pace_);
}

bool WorkerRole::reaches_oc() const {
  const Point2 p = motion_.pose();
  return team_.world.covered(team_.world.scenario.grid.world_to_cell(p)) && team_.linked(p, team_.world.scenario.oc);
}

void WorkerRole::settle() {
  phase_ = Phase::kSettling;
  into_coverage_ = false;
  heard_oc_ = false;
  last_hello_ = -kInf;
}

void WorkerRole::follow_progress(double now) {
  const bool oc_worker = policy_->delivers_to_oc();
  // Goals reached are measured at the time the robot reached them.
  const std::size_t done = std::min(motion_.legs_done(), n_legs_);
  for (; legs_seen_ < done; ++legs_seen_) {
    const std::size_t i = legs_seen_;
    legs_stats_.add(motion_.arrived_at(i) - legs_[i].arrive);
    // Its robot's pace: how long the legs took from when they began against
    // their travel time at the team speed (recent driving weighs more).
    const double planned = leg_nominal_[i], took = motion_.arrived_at(i) - leg_began_;
    leg_began_ = motion_.arrived_at(i);
    if (took > 0.5 && planned > 0.0) {
      const double keep = std::exp(-took / kPaceHorizon_s);
      planned_s_ = keep * planned_s_ + planned, took_s_ = keep * took_s_ + took;
      pace_ = std::clamp(planned_s_ / took_s_, kMinPace, kMaxPace);
    }
    if (leg_goal_[i] >= 0) measure(leg_goal_[i], motion_.arrived_at(i));
  }
  if (done == n_legs_) {
    at_rv_ = target_rv_;
    at_landing_ = ends_at_landing_;
    at_meeting_ = ends_at_meeting_;
    if (!oc_worker) {
      phase_ = plan_is_work_ ? Phase::kAtPass : Phase::kReady;
    } else if (reaches_oc()) {
      settle();
    } else if (ends_at_landing_ || into_coverage_) {
      // Its robot stopped short of the coverage (within its tolerance of
      // the border): on towards the OC, until it is in.
      legs_[0] = Waypoint{team_.world.scenario.oc, now + 1.0, team_.params.protocol.place_tolerance_m};
      leg_goal_[0] = -1, leg_nominal_[0] = -1.0, n_legs_ = 1, legs_seen_ = 0, leg_began_ = now;
      ends_at_landing_ = false, into_coverage_ = true;
      motion_.go(legs_.data(), 1, now);
    } else {
      phase_ = Phase::kReady;
    }
    return;
  }
  // On its way into the coverage: in touch with the OC is enough.
  if (into_coverage_ && reaches_oc()) {
    motion_.stop(now);
    at_landing_ = true;
    settle();
    return;
  }
  // On robots, on the way back in to its home (the goals behind it): in
  // touch with the OC it settles while its robot drives on; what it decides
  // then keeps the command (home) or replaces it (new goals).
  if (back_in_ && legs_seen_ + 1 == n_legs_ && reaches_oc()) {
    TRACE("%.1f back in touch with the OC on the way home\n", now);
    back_in_ = false;
    settle();
    return;
  }
  const NavState state = motion_.state();
  if (state == NavState::kFailed || state == NavState::kIdle) {
    // Its robot gave up the next waypoint (or dropped the command): a goal
    // there is unreachable; from where it is, it decides again.
    if (state == NavState::kFailed) {
      ++counters_.nav_failures;
      const int goal = leg_goal_[done];
      if (goal >= 0 && std::find(known_.begin(), known_.end(), goal) != known_.end()) {
        known_.erase(std::find(known_.begin(), known_.end(), goal));
        notice(ItemKind::kUnreachable, policy_->goal(static_cast<std::size_t>(goal)).id.value(), now);
      } else if (goal < 0) {
        // A place it could not reach (a pass, its home, the way back): the
        // same decision would send it there again at once; it tries again
        // after a while, and a worker of the OC heads for the OC itself.
        decide_after_ = now + kRetryPlace;
        if (policy_->delivers_to_oc() && !reaches_oc() && !into_coverage_) {
          legs_[0] = Waypoint{team_.world.scenario.oc, now + 1.0, team_.params.protocol.place_tolerance_m};
          leg_goal_[0] = -1, leg_nominal_[0] = -1.0, n_legs_ = 1, legs_seen_ = 0, leg_began_ = now;
          ends_at_landing_ = false, into_coverage_ = true;
          motion_.go(legs_.data(), 1, now);
          return;
        }
      }
    }
    TRACE("%.1f robot %s at waypoint %zu of %zu: decide again\n", now, nav_state_name(state), done, n_legs_);
    phase_ = Phase::kReady;
    return;
  }
  // Its robot's arrival estimate moved by more than the guard since the
  // plan began, or says it will miss the pass it drives to, or its
  // collector's delay moved by more than the guard since it planned: it
  // decides again from where it is (at most once a guard's time).
  const double guard = team_.params.protocol.replan_guard_s;
  const double eta = motion_.arrival_estimate();
  if (eta < kInf && !(eta_base_ < kInf)) eta_base_ = eta;
  const bool drifted = eta < kInf && std::abs(eta - eta_base_) > guard;
  const bool misses = eta < kInf && plan_is_work_ && eta > link_until_;
  const bool collector_moved = !oc_worker && std::abs(collector_delay_ - delay_used_) > guard;
  if ((drifted || misses || collector_moved) && now >= next_replan_ && !into_coverage_) {
    TRACE(
        "%.1f replan: estimate %.1f (%.1f at the start, %.1f planned), collector delay %.1f (planned with %.1f), "
        "pace %.2f\n",
        now, eta, eta_base_, legs_[n_legs_ - 1].arrive, collector_delay_, delay_used_, pace_);
    next_replan_ = now + guard;
    phase_ = Phase::kReady;
    replan_driving_ = true;
  }
}

void WorkerRole::step(double now, const Message* const* inbox, std::size_t n, Outbox& out) {
  measured_in_step_.clear();
  if (retired_) return hand_in(team_, now, inbox, n, out, custody_);
  bool oc_worker = policy_->delivers_to_oc();
  for (std::size_t i = 0; i < n; ++i) {
    const Message& m = *inbox[i];
    if (m.h.sender == upstream_) upstream_heard_ = now, collector_delay_ = oc_worker ? 0.0 : m.h.delay;
    // The collector it suspected is heard again and the OC has not declared
    // it dead: it works for its collector again.
    if (suspected_ >= 0 && m.h.sender == suspected_ &&
        std::find(dead_.begin(), dead_.end(), suspected_) == dead_.end()) {
      TRACE("%.1f hears collector %d again\n", now, suspected_);
      suspected_ = -1;
      upstream_heard_ = now;
      ++progress_version_;
      repair(now);
      if (retired_) return;
      oc_worker = policy_->delivers_to_oc();
    }
    if (oc_worker && m.h.sender == kOc) heard_oc_ = true, oc_newest_ = std::max(oc_newest_, m.h.request);
    if (m.h.dest != id_ && m.h.dest != kBroadcast) continue;
    switch (m.h.kind) {
      case Kind::kRequest:
        // A worker of a collector hears requests from its collector only
        // (request 0 comes from the OC: the whole team starts next to it).
        // The OC's declarations of dead agents come with them.
        if (m.h.sender == upstream_ || (m.h.sender == kOc && (oc_worker || m.request.request == 0))) {
          if (learn_dead(m.request)) {
            ++progress_version_;
            repair(now);
            if (retired_) return;
            oc_worker = policy_->delivers_to_oc();
          }
          on_request(m.request, m.h.sender, m.h.sender == kOc ? 0.0 : m.h.delay);
        }
        break;
      case Kind::kAck:
        if (m.h.sender == upstream_ && m.h.dest == id_)
          custody_.acked(m.ack.keys, std::min<std::size_t>(m.ack.count, kMaxBatch));
        break;
      default: break;
    }
  }
  // The plan's progress, as its robot reports it.
  if (phase_ == Phase::kMoving) follow_progress(now);
  if (retired_) return;
  oc_worker = policy_->delivers_to_oc();
  // Its collector silent for too long: it works for the OC (docs/faults.md).
  if (!oc_worker && suspected_ < 0 && now - upstream_heard_ > suspect_after_) {
    suspected_ = upstream_;
    TRACE("%.1f suspects collector %d (silent since %.1f)\n", now, suspected_, upstream_heard_);
    repair(now);
    if (retired_) return;
    oc_worker = policy_->delivers_to_oc();
  }
  skip_overdue(now);
  expire_overdue(now);
  // A worker of the OC waiting out of touch with it: its robot came to rest
  // past the place (it coasted on, or stepped aside for another robot). It
  // decides again from where it is, which takes it back in.
  if (oc_worker && phase_ == Phase::kWaiting && !reaches_oc()) {
    TRACE("%.1f waiting out of touch with the OC: back in\n", now);
    at_landing_ = false;
    phase_ = Phase::kReady;
  }
  // The radio model is asked only when contact matters: data to hand on, a
  // pass to meet at, a request due from the collector.
  const bool need = custody_.size() > 0 || phase_ == Phase::kAtPass || (!oc_worker && now >= due_time());
  const bool in_contact = need && contact(now);
  const bool decided = now >= decide_after_ && settled(now, in_contact);
  if (decided) decide(now);

  // Custody: everything due goes upstream while in contact; to a collector,
  // measured data once the contact has lasted its transfer time (notices
  // alone at once; deliveries to the OC count as instant, as in the
  // simulator).
  if (!oc_worker && in_contact && custody_.data() > 0) {
    if (transfer_since_ < 0) transfer_since_ = now;
  } else {
    transfer_since_ = -1.0;
  }
  if (!in_contact) sent_in_contact_ = false;
  const bool transferred = oc_worker || custody_.data() == 0 ||
                           now + kEps >= transfer_since_ + transfer_s(team_.world.scenario, custody_.data());
  if (in_contact && custody_.size() > 0 && transferred) {
    DataBatch batch;
    if (custody_.due(now, team_.params.resend_after, !contact_prev_ || !sent_in_contact_, batch) > 0) {
      if (Message* m = send(out, Kind::kData, upstream_, now)) m->data = batch;
    }
    sent_in_contact_ = true;
  }
  // State: a hello when it needs to hear from upstream, and the beacon.
  auto state = [&](int16_t dest) {
    if (Message* m = send(out, Kind::kState, dest, now)) {
      m->state = StateReport{};
      m->state.role = RoleKind::kWorker;
      m->state.carried = static_cast<uint16_t>(std::min<std::size_t>(custody_.data(), 65535));
      m->state.notices = static_cast<uint16_t>(std::min<std::size_t>(custody_.notices(), 65535));
      m->state.pending = static_cast<uint16_t>(std::min<std::size_t>(known_.size(), 65535));
      m->state.measured = static_cast<int32_t>(counters_.measured);
      m->state.back_by = phase_ == Phase::kMoving && n_legs_ > 0 ? back_by(now) : now;
    }
  };
  const double resend = team_.params.resend_after;
  // A worker of the OC asks until it has heard the OC and holds the request
  // the OC says is newest; waiting for a request that is due (and whose
  // broadcast it may have missed), it asks too.
  const bool settling = phase_ == Phase::kSettling && !(heard_oc_ && oc_newest_ <= newest_request());
  const bool overdue = (phase_ == Phase::kWaiting || phase_ == Phase::kStart) &&
                       now >= due_time() + team_.params.ask_after && !(request_.complete() && request_.id > resolved_);
  // On robots, a worker of the OC that sets off tells the OC at once when
  // it will be back (its robot may leave the coverage before its next
  // beacon: the OC would wait on the back_by it had).
  const bool leaving = decided && oc_worker && policy_->back_to_home() && phase_ == Phase::kMoving && reaches_oc();
  if (oc_worker && (((settling || overdue) && now - last_hello_ >= resend) || leaving)) {
    state(kOc);
    last_hello_ = now;
  } else if (!oc_worker && in_contact && now >= due_time() && (!contact_prev_ || now - last_hello_ >= resend)) {
    state(upstream_);  // a request is due: the collector passes it on
    TRACE("%.1f hello to collector (due %.1f)\n", now, due_time());
    last_hello_ = now;
  }
  if (now >= next_beacon_) {
    state(kBroadcast);
    while (next_beacon_ <= now) next_beacon_ += team_.params.beacon_period;
  }
  contact_prev_ = in_contact;
}

}  // namespace agent
}  // namespace gather
