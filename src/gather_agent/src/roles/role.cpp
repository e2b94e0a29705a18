#include "gather_agent/roles/role.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::kRequest: return "request";
    case Kind::kData: return "data";
    case Kind::kAck: return "ack";
    case Kind::kState: return "state";
  }
  return "?";
}

const char* item_kind_name(ItemKind k) {
  switch (k) {
    case ItemKind::kMeasured: return "measured";
    case ItemKind::kExpired: return "expired";
    case ItemKind::kDropped: return "dropped";
    case ItemKind::kSkipped: return "skipped";
    case ItemKind::kUnreachable: return "unreachable";
  }
  return "?";
}

const char* nav_state_name(NavState s) {
  switch (s) {
    case NavState::kIdle: return "idle";
    case NavState::kActive: return "active";
    case NavState::kReached: return "reached";
    case NavState::kFailed: return "failed";
    case NavState::kBlocked: return "blocked";
  }
  return "?";
}

const char* base_fault_name(BaseFault f) {
  switch (f) {
    case BaseFault::kNone: return "none";
    case BaseFault::kSilent: return "silent";
    case BaseFault::kOffMap: return "off_map";
    case BaseFault::kLost: return "lost";
  }
  return "?";
}

const char* role_kind_name(RoleKind r) {
  switch (r) {
    case RoleKind::kWorker: return "worker";
    case RoleKind::kCollector: return "collector";
    case RoleKind::kOcRole: return "oc";
  }
  return "?";
}

TeamSetup::TeamSetup(const mission::World& w, const mission::MissionPlan& p, const MissionParams& prm)
    : world(w),
      plan(p),
      params(prm),
      radio(w.scenario.grid, w.scenario.radio),
      areas(mission::area_weights(w, p.file.area_tile_m)) {
  const plan::PlanFile& pf = p.file;
  const std::string where = p.source.empty() ? "plan" : p.source;
  const int n = static_cast<int>(pf.agents.size());
  if (n < 1 || n > kMaxTeam)
    throw Error(where, "a team of " + std::to_string(n) + " agents (1.." + std::to_string(kMaxTeam) + ")");
  mission::check_plan(p, w.scenario.team.agents, w.scenario.grid);  // agents listed by id, among the rest
  period = pf.cycle_period_s;
  speed = w.scenario.team.speed;
  if (!(period > 0) || !std::isfinite(period)) throw Error(where, "cycle_period_s must be > 0");
  if (params.cycles < 1 || params.cycles > kMaxRequests) throw Error(where, "cycles must be in 1..100000");
  if (params.goals_per_request < 0) throw Error(where, "goals per request must be >= 0");
  if (!(params.silent_intervals >= 1.5 && params.silent_intervals <= 100.0))
    throw Error("--silent-intervals", "must be in [1.5, 100], got " + std::to_string(params.silent_intervals));
  require_in_range(params.ask_after, 0, 60, "mission params", "ask_after", " s");
  mission::check_params(params.protocol);
  if (params.data_capacity == 0)
    params.data_capacity = std::max<std::size_t>(64, 4 * static_cast<std::size_t>(params.goals_per_request));
  if (params.notice_capacity == 0) params.notice_capacity = params.data_capacity;

  collector_agent_ = mission::collector_agents(pf);
  worker_of_segment_ = PerSegment<AgentId>(pf.workers);
  for (const plan::AgentAssignment& a : pf.agents)
    if (!a.collector) worker_of_segment_[a.segment] = a.id;
  for (const plan::CollectorRoute& r : pf.routes) {
    try {
      routes.emplace_back(r, speed, period, w.coverage);
    } catch (const Error& e) {
      throw Error(where, e.what());
    }
  }
  links = plan_links(pf);
  meeting_arc_.assign(n, 0.0);
  for (const plan::AgentAssignment& a : pf.agents) {
    if (a.collector || !a.delivers_to.valid()) continue;
    const plan::CollectorRoute& r = pf.routes[a.delivers_to];
    const auto m = std::find_if(r.meetings.begin(), r.meetings.end(),
                                [&](const plan::MeetingArea& x) { return x.segment == a.segment; });
    meeting_arc_[a.id] = m->arc_m;  // check_plan: there is one
  }
  distances = std::make_unique<mission::SharedDistances>(w, /*from_oc=*/false);  // agents start at their start poses
  if (params.protocol.home_clearance_m > 0) oc_homes = mission::oc_worker_homes(w, p, params.protocol.home_clearance_m);
  start_ = PerAgent<Point2>(mission::team_start_poses(w, p, oc_homes));
  range_ = radio.free_space_range();
}

FleetLinks plan_links(const plan::PlanFile& plan) {
  const PerCollector<AgentId> drivers = mission::collector_agents(plan);
  std::vector<int16_t> upstream;
  for (const plan::AgentAssignment& a : plan.agents)
    upstream.push_back(a.collector || !a.delivers_to.valid() ? int16_t{-1}
                                                             : static_cast<int16_t>(drivers[a.delivers_to].value()));
  return FleetLinks(std::move(upstream));
}

GridAStar& TeamSetup::paths() {
  if (!paths_) paths_ = std::make_unique<GridAStar>(world.scenario.grid, world.reachable, &world.coverage_field);
  return *paths_;
}

std::vector<uint8_t> TeamSetup::collector_flags() const {
  std::vector<uint8_t> flags;
  for (AgentId a : ids<AgentId>(agents())) flags.push_back(assignment(a).collector ? 1 : 0);
  return flags;
}

bool TeamSetup::linked(Point2 a, Point2 b) const {
  return std::hypot(a.x - b.x, a.y - b.y) <= range_ && radio.linked(a, b);
}

double TeamSetup::deadline(AgentId agent, int cycle) const {
  const plan::AgentAssignment& a = assignment(agent);
  if (a.collector || !a.delivers_to.valid()) return std::numeric_limits<double>::infinity();
  const mission::RouteTimetable& r = routes[a.delivers_to];
  const double arc = meeting_arc_[agent];
  return mission::request_deadline(mission::request_reaches_worker(r, arc, cycle, period),
                                   mission::request_reaches_worker(r, arc, cycle + 1, period), period);
}

const mission::RepairedPlan& TeamSetup::repaired(const int16_t* dead, std::size_t n) {
  std::vector<AgentId> key;
  key.reserve(n);
  for (std::size_t i = 0; i < n; ++i) key.emplace_back(dead[i]);
  std::sort(key.begin(), key.end());
  key.erase(std::unique(key.begin(), key.end()), key.end());
  for (const auto& [set, repaired] : repaired_)
    if (set == key) return *repaired;
  const std::size_t cells = plan.labels.frame().size();
  if (plan.labels.size() == cells) {
    repaired_.emplace_back(key,
                           std::make_unique<mission::RepairedPlan>(mission::repair_plan(plan, key, params.repair)));
  } else {
    mission::MissionPlan full;
    full.source = plan.source, full.file = plan.file;
    if (reload_labels) full.labels = reload_labels();
    if (full.labels.size() != cells)
      throw RuntimeError("plan repair (internal error)", "the plan's label image was dropped");
    repaired_.emplace_back(key,
                           std::make_unique<mission::RepairedPlan>(mission::repair_plan(full, key, params.repair)));
  }
  return *repaired_.back().second;
}

double TeamSetup::silent_timeout(const mission::MissionPlan& p, AgentId agent) const {
  const plan::AgentAssignment& a = p.file.agents[agent];
  if (!a.delivers_to.valid())
    return mission::silent_timeout(mission::Liveness::kOcWorker, period, 0.0, params.silent_intervals);
  // An idle collector's route has no period (it stays at the OC): at least
  // a request period.
  const double loop = std::max(routes[a.delivers_to].period(), period);
  return mission::silent_timeout(a.collector ? mission::Liveness::kCollector : mission::Liveness::kCollectorWorker,
                                 period, loop, params.silent_intervals);
}

Message* Outbox::add(Kind kind, int16_t dest) {
  if (n_ >= messages_.size()) {
    ++refused_;
    return nullptr;
  }
  Message& m = messages_[n_++];
  m.h = Header{};
  m.h.kind = kind;
  m.h.dest = dest;
  return &m;
}

Message* Role::send(Outbox& out, Kind kind, int16_t dest, double now) {
  Message* m = out.add(kind, dest);
  if (!m) return nullptr;
  m->h.sender = id_;
  m->h.t = now;
  m->h.pos = motion_.pose();
  m->h.request = newest_request();
  m->h.delay = delay();
  m->h.dead = static_cast<uint8_t>(known_declarations());
  return m;
}

void Role::restore(const DataItem*, std::size_t, const Progress&, double) {
  throw RuntimeError("restart", std::string(role_kind_name(kind())) + " " + std::to_string(id_) + " cannot restart");
}

bool Role::learn_dead(const RequestPart& part) {
  const std::size_t n = std::min<std::size_t>(part.dead_count, kMaxDead);
  if (n < dead_.size()) return false;
  // Revocations of declarations this role knows (or learns now): the OC
  // only sets bits, never clears one.
  const uint32_t mask = n >= 32 ? ~0u : (1u << n) - 1u;
  revoked_ |= part.dead_revoked & mask;
  if (n == dead_.size()) return false;
  dead_.assign(part.dead, part.dead + n);
  return true;
}

uint64_t Role::revoked_bits() const { return static_cast<uint64_t>(__builtin_popcount(revoked_)); }

int Role::revoked_index(int16_t agent) const {
  if (revoked_ != 0)
    for (std::size_t i = 0; i < dead_.size(); ++i)
      if (dead_[i] == agent) return (revoked_ >> i) & 1u ? static_cast<int>(i) : -1;
  return -1;
}

int64_t Role::refused_revoked() const {
  int64_t n = 0;
  for (int64_t r : refused_) n += r;
  return n;
}

void Role::control(double now, const Message* const* inbox, std::size_t n, Outbox& out) {
  before_control(now, out);
  if (revoked_ == 0) return step(now, inbox, n, out);
  admitted_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const int d = revoked_index(inbox[i]->h.sender);
    if (d >= 0)
      ++refused_[static_cast<std::size_t>(d)];
    else
      admitted_.push_back(inbox[i]);
  }
  step(now, admitted_.data(), admitted_.size(), out);
}

void Role::hand_in(const TeamSetup& team, double now, const Message* const* inbox, std::size_t n, Outbox& out,
                   Custody& custody) {
  for (std::size_t i = 0; i < n; ++i) {
    const Message& m = *inbox[i];
    if (m.h.kind == Kind::kAck && m.h.sender == kOc && m.h.dest == id_)
      custody.acked(m.ack.keys, std::min<std::size_t>(m.ack.count, kMaxBatch));
  }
  if (custody.size() == 0) {  // all in: it stays where it is
    if (handing_in_) motion_.stop(now), handing_in_ = false;
    return;
  }
  const Point2 oc = team.world.scenario.oc;
  const Point2 p = motion_.pose();
  const bool contact = team.linked(p, oc);
  if (!contact && (!handing_in_ || motion_.state() == NavState::kIdle || motion_.state() == NavState::kFailed ||
                   motion_.state() == NavState::kReached)) {
    const Waypoint to{oc, now + std::hypot(oc.x - p.x, oc.y - p.y) / team.speed,
                      team.params.protocol.place_tolerance_m};
    motion_.go(&to, 1, now);
    handing_in_ = true;
  }
  if (contact) {
    DataBatch batch;
    if (custody.due(now, team.params.resend_after, !hand_in_contact_, batch) > 0)
      if (Message* m = send(out, Kind::kData, kOc, now)) m->data = batch;
  }
  hand_in_contact_ = contact;
}

void Role::stamp_dead(RequestPart& part) const {
  part.dead_count = static_cast<uint8_t>(std::min<std::size_t>(dead_.size(), kMaxDead));
  std::copy(dead_.begin(), dead_.begin() + part.dead_count, part.dead);
  part.dead_revoked = revoked_;
}

}  // namespace agent
}  // namespace gather
