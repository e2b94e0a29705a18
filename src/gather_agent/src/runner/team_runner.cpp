#include "gather_agent/runner/team_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <stdexcept>

#include "gather_agent/roles/worker_role.hpp"

#include "gather_core/error.hpp"
#include "gather_core/input_file.hpp"
#include "gather_core/mission/mission_csv.hpp"

namespace gather {
namespace agent {

Kill parse_kill(const std::string& text, int agents, const std::string& flag) {
  const std::size_t at = text.find('@');
  Kill k;
  try {
    if (at == std::string::npos || at == 0 || at + 1 >= text.size()) throw std::invalid_argument("form");
    std::size_t used = 0;
    k.agent = std::stoi(text.substr(0, at), &used);
    if (used != at) throw std::invalid_argument("id");
    const std::string t = text.substr(at + 1);
    k.at = std::stod(t, &used);
    if (used != t.size()) throw std::invalid_argument("time");
  } catch (const std::exception&) {
    throw Error(flag, "must be ID@T (agent id, mission time in s), got '" + quote_input(text) + "'");
  }
  if (k.agent < 0 || k.agent >= agents)
    throw Error(flag, "agent " + std::to_string(k.agent) + " is not in the team of " + std::to_string(agents));
  if (!std::isfinite(k.at) || k.at < 0.0 || k.at > 1e7)
    throw Error(flag, "time must be in [0, 1e7] s, got '" + quote_input(text) + "'");
  return k;
}

std::vector<Kill> parse_kills(const std::string& list, int agents, const std::string& flag) {
  std::vector<Kill> kills;
  if (list.empty() || list == "none") return kills;
  std::size_t from = 0;
  for (;;) {
    const std::size_t comma = list.find(',', from);
    const Kill k =
        parse_kill(list.substr(from, comma == std::string::npos ? std::string::npos : comma - from), agents, flag);
    for (const Kill& other : kills)
      if (other.agent == k.agent) throw Error(flag, "agent " + std::to_string(k.agent) + " is named twice");
    kills.push_back(k);
    if (kills.size() > static_cast<std::size_t>(kMaxDead))
      throw Error(flag, "at most " + std::to_string(kMaxDead) + " agents");
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  return kills;
}

void check_lost_goals(const OcRole& oc, const std::vector<const Role*>& roles, const std::vector<uint8_t>& gone) {
  std::vector<uint8_t> held_by_gone(oc.goals().size(), 0);
  std::set<std::pair<int, int>> skips_held;  // (request, worker) of skip notices a dead agent held
  for (std::size_t a = 0; a < roles.size(); ++a) {
    if (!gone[a]) continue;
    if (const Custody* c = roles[a]->custody())
      for (std::size_t i = 0; i < c->size(); ++i) {
        const int32_t key = c->item(i).key;
        if (key >= 0 && static_cast<std::size_t>(key) < held_by_gone.size())
          held_by_gone[static_cast<std::size_t>(key)] = 1;
        if (key < 0) skips_held.emplace(skipped_request(key), skipped_worker(key));
      }
  }
  for (const mission::GoalRecord& g : oc.goals()) {
    if (g.state != mission::GoalState::kLostWithAgent || oc.closed_at_end(g.id)) continue;
    const bool own = g.worker.valid() && gone[g.worker.index()];
    if (!held_by_gone[g.id.index()] && !own && !skips_held.count({g.cycle, g.worker.value()}))
      throw RuntimeError("faults", to_string(g.id) +
                                       " was declared lost with an agent, but no dead agent "
                                       "had it (worker " +
                                       std::to_string(g.worker.value()) + ")");
  }
}

bool still_owes(const RoleReport& r, const OcRole& oc) {
  return !oc.dead().empty() && r.role == RoleKind::kWorker && (r.pending > 0 || r.requests < oc.issued() - 1);
}

double time_limit(const TeamSetup& team) {
  double longest = 0.0;
  for (const mission::RouteTimetable& r : team.routes) longest = std::max(longest, r.period());
  // And the longest way a worker may be out of the coverage: to the farthest
  // reachable cell and back (a period shorter than the plan's own leaves
  // workers out for longer than a few periods).
  const mission::World& w = team.world;
  double farthest = 0.0;
  for (std::size_t i = 0; i < w.reachable.size(); ++i)
    if (w.reachable[i] && !w.coverage[i]) {
      const double d = w.coverage_field.time(w.scenario.grid.cell(i));
      if (d < fmm::kUnreached) farthest = std::max(farthest, d);
    }
  return (team.params.cycles + 5) * team.period + 3.0 * longest + 2.0 * farthest / team.speed;
}

void check_team_conservation(const OcRole& oc, const std::vector<AgentUnit>& agents,
                             const std::vector<uint8_t>& measured, double now, std::vector<int32_t>& scratch) {
  scratch.clear();
  for (const AgentUnit& u : agents) {
    if (!u.role) continue;
    if (const Custody* c = u.role->custody())
      for (std::size_t i = 0; i < c->size(); ++i)
        if (c->item(i).kind == ItemKind::kMeasured) scratch.push_back(c->item(i).key);
  }
  check_conservation(oc, measured, scratch, now);
}

std::vector<AgentSummary> summarize(const OcRole& oc, const std::vector<const Role*>& roles,
                                    const std::vector<LinkCounters>& links) {
  std::vector<AgentSummary> out;
  for (std::size_t i = 0; i < roles.size(); ++i) {
    AgentSummary s;
    s.id = roles[i]->id();
    s.role = roles[i]->kind();
    s.report = roles[i]->report();
    s.link = links[i];
    if (const Custody* c = roles[i]->custody()) s.carried = static_cast<int64_t>(c->data());
    s.delivered = oc.delivered_by(AgentId(s.id));
    out.push_back(s);
  }
  return out;
}

TeamRunner::TeamRunner(TeamSetup& team, const RunOptions& options)
    : team_(team), options_(options), gate_(team, options.loss, options.loss_seed) {
  if (!(options_.tick > 0.0) || options_.tick > 0.1 + 1e-12)
    throw Error("--tick", "must be in (0, 0.1] s (the control rate), got " + std::to_string(options_.tick));
  if (!(options_.loss >= 0.0) || !(options_.loss < 1.0))
    throw Error("--loss", "must be in [0, 1), got " + std::to_string(options_.loss));
  units_.push_back(make_oc(team));
  for (AgentId a : ids<AgentId>(team.agents()))
    units_.push_back(make_agent(team, a, nullptr, options_.robots ? &commands_ : nullptr, options_.robot_params));
  robot_bases_.assign(static_cast<std::size_t>(team.agents()), nullptr);
  if (options_.robots)
    for (std::size_t i = 1; i < units_.size(); ++i)
      robot_bases_[i - 1] = static_cast<RobotBase*>(units_[i].motion.get());
  for (std::size_t i = 0; i < units_.size(); ++i) outboxes_.emplace_back(options_.outbox);
  links_.assign(units_.size(), LinkCounters{});
  seq_.assign(units_.size(), 0);
  killed_.assign(units_.size(), 0);
  restarted_.assign(units_.size(), 0);
  fresh_.assign(units_.size(), 0);
  for (const Kill& k : options_.restarts)
    if (k.agent < 0 || k.agent >= team.agents())
      throw Error("--restart",
                  "agent " + std::to_string(k.agent) + " is not in the team of " + std::to_string(team.agents()));
  if (!options_.restarts.empty() && options_.journal_dir.empty())
    throw Error("--restart", "needs the agents' journals (a journal directory)");
  journals_.resize(units_.size());
  if (!options_.journal_dir.empty())
    for (std::size_t i = 1; i < units_.size(); ++i) {
      const int a = static_cast<int>(i) - 1;
      journals_[i] =
          std::make_unique<JournalKeeper>(journal_path(options_.journal_dir, a), a, journal_run_id(team.params));
      journals_[i]->open(false);
      journals_[i]->bind(*units_[i].role);
    }
  for (const Kill& k : options_.kills)
    if (k.agent < 0 || k.agent >= team.agents())
      throw Error("--kill",
                  "agent " + std::to_string(k.agent) + " is not in the team of " + std::to_string(team.agents()));
  sent_.reserve(units_.size() * 8);
  next_.reserve(units_.size() * 8);
  inbox_.reserve(options_.inbox);
  limit_ = options_.time_limit > 0 ? options_.time_limit : time_limit(team);
  measured_.assign(oc().goals().size(), 0);
}

TeamRunner::~TeamRunner() = default;

Role& TeamRunner::role(AgentId agent) { return *units_[agent.index() + 1].role; }  // unit 0: the OC
OcRole& TeamRunner::oc() { return static_cast<OcRole&>(*units_[0].role); }

// The robots move first: to this tick's time, with the commands the agents
// sent in the tick before; each agent's base takes what its robot reported.
void TeamRunner::robots_step(double t) {
  sent_commands_.swap(commands_.commands);
  commands_.commands.clear();
  options_.robots->step(ticks_, t, sent_commands_, poses_, statuses_);
  for (const RobotPose& p : poses_)
    if (p.agent >= 0 && p.agent < team_.agents() && !killed_[static_cast<std::size_t>(p.agent) + 1])
      robot_bases_[static_cast<std::size_t>(p.agent)]->on_pose(p, t);
  for (const NavStatus& s : statuses_)
    if (s.agent >= 0 && s.agent < team_.agents() && !killed_[static_cast<std::size_t>(s.agent) + 1])
      robot_bases_[static_cast<std::size_t>(s.agent)]->on_status(s, t);
  for (RobotBase* b : robot_bases_) b->set_tick(ticks_);
}

bool TeamRunner::tick() {
  const double t = now();
  next_.clear();
  for (const Kill& k : options_.kills)
    if (t >= k.at - 1e-9) killed_[static_cast<std::size_t>(k.agent) + 1] = 1;
  for (const Kill& k : options_.restarts) {
    const std::size_t i = static_cast<std::size_t>(k.agent) + 1;
    if (t >= k.at - 1e-9 && !restarted_[i] && !killed_[i]) restart(i, t);
  }
  if (options_.robots) robots_step(t);
  for (std::size_t i = 0; i < units_.size(); ++i) {
    AgentUnit& u = units_[i];
    Outbox& out = outboxes_[i];
    if (killed_[i]) continue;  // dead: no motion, no radio; its memory stays as it was
    if (before_) before_();
    u.motion->update(t);
    if (fresh_[i]) {
      inbox_.clear(), fresh_[i] = 0;
    } else {
      gather_inbox(sent_, u.role->id(), u.motion->pose(), gate_, links_[i], inbox_);
    }
    out.clear();
    u.role->control(t, inbox_.data(), inbox_.size(), out);
    if (const std::vector<GoalId>* m = u.role->measured_in_step())
      for (GoalId g : *m) count_measured(measured_, g.value());
    if (journals_[i]) journals_[i]->after_step(*u.motion, t);  // durable before its messages go out
    if (after_) after_();
    for (std::size_t k = 0; k < out.size(); ++k) {
      Message m = out[k];
      m.h.seq = seq_[i]++;
      m.h.tick = ticks_;
      next_.push_back(m);
    }
    links_[i].sent += static_cast<int64_t>(out.size());
  }
  std::swap(sent_, next_);
  ++ticks_;
  // Conservation at every cycle's end.
  while (next_check_ < team_.params.cycles && t >= (next_check_ + 1) * team_.period) {
    check_team_conservation(oc(), units_, measured_, t, custody_scratch_);
    ++next_check_;
  }
  // Done when every goal is resolved and every ack has landed (no agent
  // still holds a copy of something the OC already has).
  bool held = false;
  for (std::size_t i = 1; i < units_.size(); ++i) {
    const Role& r = *units_[i].role;
    if (killed_[i] || r.retired() || oc().declared_dead_at(AgentId::at_index(i - 1)) >= 0) continue;
    held = held || (r.custody() && r.custody()->size() > 0) || still_owes(r.report(), oc());
  }
  return !(oc().done() && !held) && t < limit_;
}

// The agent's process crashed and was started again: a new role and motion
// from the journal (where it was, what it held, how far it got), a new
// process's counters and message sequence, and nothing heard yet.
void TeamRunner::restart(std::size_t i, double t) {
  const int a = static_cast<int>(i) - 1;
  journals_[i].reset();  // the old life's file handle
  auto keeper = std::make_unique<JournalKeeper>(journal_path(options_.journal_dir, a), a, journal_run_id(team_.params));
  const JournalState s = keeper->open(true);
  units_[i] = make_agent(team_, AgentId(a), s.have_pose ? &s.pose : nullptr, options_.robots ? &commands_ : nullptr,
                         options_.robot_params);
  if (options_.robots) robot_bases_[static_cast<std::size_t>(a)] = static_cast<RobotBase*>(units_[i].motion.get());
  keeper->bind(*units_[i].role);  // first: what restore() adds (expiry notices) is journaled too
  units_[i].role->restore(s.custody.data(), s.custody.size(), s.progress, t);
  int measured = 0;
  for (const DataItem& it : s.custody) measured += it.kind == ItemKind::kMeasured;
  restored_.emplace_back(a, measured);
  journals_[i] = std::move(keeper);
  seq_[i] = 0;
  sent_before_restart_ += links_[i].sent;  // its earlier life's messages still count in the run's total
  links_[i] = LinkCounters{};
  restarted_[i] = 1, fresh_[i] = 1;
}

RunOutcome TeamRunner::run() {
  const auto t0 = std::chrono::steady_clock::now();
  while (tick()) {
  }
  RunOutcome out;
  out.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  out.ticks = ticks_;
  out.end_s = (ticks_ - 1) * options_.tick;
  // A team on robots ends at its time limit whatever its robots still owe
  // (one stuck far away, one that never came back): lost with them.
  if (!oc().done() && options_.robots) out.closed_at_end = static_cast<int64_t>(oc().close(out.end_s));
  out.completed = oc().done();
  std::vector<const Role*> roles;
  std::vector<LinkCounters> links;
  for (std::size_t i = 1; i < units_.size(); ++i) roles.push_back(units_[i].role.get()), links.push_back(links_[i]);
  out.agents = summarize(oc(), roles, links);
  for (std::size_t a = 0; a < robot_bases_.size(); ++a)
    if (const RobotBase* b = robot_bases_[a]) {
      out.agents[a].contacts = b->contacts();
      out.agents[a].robot = b->counters();
      out.agents[a].robot_fault = b->first_fault();
    }
  out.oc_link = links_[0];
  out.messages = sent_before_restart_;
  for (const LinkCounters& l : links_) out.messages += l.sent;
  out.invalid_items = oc().invalid_items();
  out.duplicate_items = oc().duplicate_items();
  out.recovered = oc().recovered();
  out.overridden = oc().overridden();
  out.kills = options_.kills;
  out.restarts = options_.restarts;
  out.restored = restored_;
  for (int16_t a : oc().dead()) out.declared_dead.emplace_back(a, oc().declared_dead_at(AgentId(a)));
  out.revoked = revocations(oc());
  if (!out.completed && std::getenv("GATHER_DEBUG")) {
    for (const mission::GoalRecord& g : oc().goals()) {
      if (g.id.index() >= oc().requested() || oc().resolved(g.id)) continue;
      std::string where;
      for (std::size_t i = 1; i < units_.size(); ++i)
        if (const Custody* c = units_[i].role->custody())
          for (std::size_t k = 0; k < c->size(); ++k)
            if (c->item(k).key == g.id.value())
              where += " held by " + std::to_string(i - 1) + "(" + item_kind_name(c->item(k).kind) + ")";
      const Role* w = g.worker.valid() ? &role(g.worker) : nullptr;
      std::fprintf(
          stderr, "unresolved goal %d cycle %d worker %d seg %d deadline %.1f:%s worker knows %d phase %d\n",
          g.id.value(), g.cycle, g.worker.value(), g.segment.label(), g.deadline, where.c_str(),
          w ? w->newest_request() : -1,
          w && w->kind() == RoleKind::kWorker ? static_cast<int>(static_cast<const WorkerRole*>(w)->phase()) : -1);
    }
  }
  if (!out.completed) {
    out.failure = "mission not finished at t = " + std::to_string(out.end_s) + " s (limit " + std::to_string(limit_) +
                  " s): " + std::to_string(oc().requested() - oc().resolved_count()) + " of " +
                  std::to_string(oc().requested()) + " goals unresolved";
    return out;
  }
  std::vector<uint8_t> gone(static_cast<std::size_t>(team_.agents()), 0);
  for (std::size_t i = 1; i < units_.size(); ++i)
    gone[i - 1] = killed_[i] || units_[i].role->retired() || oc().declared_dead_at(AgentId::at_index(i - 1)) >= 0;
  check_lost_goals(oc(), roles, gone);
  out.result = mission::mission_result(oc().goals(), team_.params.cycles, team_.period, out.wall_ms, team_.areas);
  return out;
}

}  // namespace agent
}  // namespace gather
