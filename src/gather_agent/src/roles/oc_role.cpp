#include "gather_agent/roles/oc_role.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/mission/requests.hpp"

namespace gather {
namespace agent {

OcRole::OcRole(TeamSetup& team, MotionBackend& station) : Role(kOc, station), team_(team) {
  const OccupancyGrid& grid = team.world.scenario.grid;
  std::vector<mission::DrawnGoal> drawn;
  if (team.params.fixed_goals.empty()) {
    drawn = mission::draw_goals(team.world, team.params.seed, team.params.cycles, team.params.goals_per_request);
  } else {
    for (int c = 0; c < team.params.cycles; ++c)
      for (const auto& [cycle, p] : team.params.fixed_goals) {
        const Cell cell = grid.world_to_cell(p);
        if (cycle != c) continue;
        if (!grid.contains(cell) || !team.world.reachable[grid.index(cell)])
          throw Error("mission", "fixed goal off the reachable space");
        drawn.push_back(mission::DrawnGoal{c, cell});
      }
  }
  first_.assign(static_cast<std::size_t>(team.params.cycles) + 1, 0);
  for (const mission::DrawnGoal& d : drawn) ++first_[static_cast<std::size_t>(d.cycle) + 1];
  for (std::size_t c = 1; c < first_.size(); ++c) first_[c] += first_[c - 1];
  goals_.reserve(drawn.size());
  for (const mission::DrawnGoal& d : drawn) {
    mission::GoalRecord g;
    g.id = GoalId::at_index(goals_.size());
    g.cycle = d.cycle;
    g.point = grid.cell_center(d.cell);
    g.segment = SegmentId(team.plan.labels[grid.index(d.cell)]);
    g.worker = g.segment.valid() ? team.worker_of_segment(g.segment) : AgentId();
    g.requested_at = -1.0;
    g.deadline = g.worker.valid() ? team.deadline(g.worker, g.cycle) : std::numeric_limits<double>::infinity();
    goals_.push_back(g);
    cell_of_.push_back(static_cast<uint32_t>(grid.index(d.cell)));
  }
  resolved_.assign(goals_.size(), 0);
  resolved_by_.assign(goals_.size(), -1);
  issued_at_.assign(static_cast<std::size_t>(team.params.cycles), 0.0);
  answered_at_.assign(team.agents(), -std::numeric_limits<double>::infinity());
  for (const mission::GoalRecord& g : goals_)
    if (!g.worker.valid()) unassigned_.push_back(g.id);
  delivered_by_.assign(team.agents(), 0);
  acks_.reserve(kMaxBatch);
  heard_.assign(team.agents(), 0.0);  // the team starts next to the OC
  back_by_.assign(team.agents(), 0.0);
  delay_.assign(team.agents(), 0.0);
  declared_at_.assign(team.agents(), -1.0);
  grace_until_.assign(team.agents(), 0.0);
  dead_.reserve(kMaxDead);
  revoked_at_.assign(team.agents(), -1.0);
  discarded_of_.assign(team.agents(), 0);
  discarded_.assign(goals_.size(), 0);
}

std::size_t OcRole::requested() const { return first_[static_cast<std::size_t>(issued_)]; }

RoleReport OcRole::report() const {
  RoleReport r;
  r.role = RoleKind::kOcRole;
  r.id = kOc;
  r.requests = newest_request();
  r.pending = static_cast<int64_t>(requested() - resolved_count_);
  r.dead_known = static_cast<int64_t>(dead_.size());
  r.refused_revoked = refused_revoked();
  return r;
}

void OcRole::issue(int cycle, int16_t dest, double now, Outbox& out) {
  const std::size_t first = first_[static_cast<std::size_t>(cycle)];
  const int count = static_cast<int>(first_[static_cast<std::size_t>(cycle) + 1] - first);
  const int parts = std::max(1, (count + kRequestPartGoals - 1) / kRequestPartGoals);
  for (int p = 0; p < parts; ++p) {
    Message* m = send(out, Kind::kRequest, dest, now);
    if (!m) return;
    RequestPart& r = m->request;
    r.request = cycle;
    r.issued_at = goals_.empty() ? now : goals_[std::min(first, goals_.size() - 1)].requested_at;
    r.first_goal = static_cast<int32_t>(first);
    r.total = count;
    r.part = static_cast<uint16_t>(p);
    r.parts = static_cast<uint16_t>(parts);
    const int begin = p * kRequestPartGoals, end = std::min(count, begin + kRequestPartGoals);
    r.count = static_cast<uint16_t>(std::max(0, end - begin));
    for (int k = begin; k < end; ++k) r.cells[k - begin] = cell_of_[first + static_cast<std::size_t>(k)];
    stamp_dead(r);
  }
}

bool OcRole::open(GoalId goal, const DataItem* item) {
  if (!resolved_[goal.index()]) return true;
  mission::GoalRecord& g = goals_[goal.index()];
  if (g.state == mission::GoalState::kLostWithAgent) {
    g.lost_at = -1.0;
    ++recovered_;
  } else if (item && item->kind == ItemKind::kMeasured && resolved_by_[goal.index()] != item->by &&
             (g.state == mission::GoalState::kExpired || g.state == mission::GoalState::kDropped ||
              g.state == mission::GoalState::kUnreachable)) {
    g.expired_at = g.dropped_at = g.unreachable_at = g.measured_at = -1.0;
    g.measured_by = AgentId();
    ++overridden_;
  } else {
    return false;
  }
  g.state = mission::GoalState::kPending;
  resolved_[goal.index()] = 0;
  --resolved_count_;
  return true;
}

void OcRole::before_control(double now, Outbox& out) {
  for (const auto& [id, at] : team_.params.revoke) {
    const AgentId a(id);
    if (!a.within(team_.agents()) || revoked_at_[a] >= 0 || now < at - 1e-9) continue;
    if (declared_at_[a] < 0) {
      // Past kMaxDead declarations none is made, a revocation neither
      // (docs/faults.md): it waits for room, which never comes.
      if (dead_.size() >= static_cast<std::size_t>(kMaxDead)) continue;
      revoked_at_[a] = now;
      declare_dead(a, now, out, true);
      continue;
    }
    revoked_at_[a] = now;
    // Declared dead before (it fell silent): its declaration is revoked now.
    const auto i = std::find(dead_.begin(), dead_.end(), a.value()) - dead_.begin();
    revoked_ |= 1u << i;
    if (issued_ > 0) issue(issued_ - 1, kBroadcast, now, out);
  }
}

bool OcRole::could_serve(AgentId w, GoalId goal) {
  const uint32_t cell = cell_of_[goal.index()];
  auto serves = [&](const mission::MissionPlan& p) {
    const int32_t label = p.labels[cell];
    return label > 0 && team_.worker_of_segment(SegmentId(label)) == w;
  };
  if (team_.assignment(w).collector) return false;
  if (serves(team_.plan)) return true;
  // (A worker that suspects its collector adds it to the set: a dead
  // collector changes no segment, so the prefixes cover it. Each prefix's
  // repair was made at its declaration: none is computed here.)
  for (std::size_t k = 1; k <= dead_.size(); ++k)
    if (serves(team_.repaired(dead_.data(), k).plan)) return true;
  return false;
}

bool OcRole::discard(const DataItem& item) {
  ++discarded_of_[AgentId(item.by)];
  if (item.kind == ItemKind::kMeasured) discarded_[static_cast<std::size_t>(item.key)] = 1;
  return true;  // acked: its holder lets go; lost with the revoked agent
}

bool OcRole::of_revoked(const DataItem& item) const {
  if (item.by < 0 || item.by >= team_.agents()) return false;
  const double at = revoked_at_[AgentId(item.by)];
  return at >= 0 && !(item.kind == ItemKind::kMeasured && item.picked_up_by >= 0 && item.picked_up_at <= at + 1e-9);
}

void OcRole::declare_dead(AgentId agent, double now, Outbox& out, bool revoke) {
  const plan::AgentAssignment before = assigned(agent);
  PerAgent<uint8_t> served_by_it(team_.agents(), 0);  // whose goals it had
  served_by_it[agent] = 1;
  if (before.collector)
    for (AgentId a : ids<AgentId>(team_.agents()))
      if (!assigned(a).collector && assigned(a).delivers_to == before.delivers_to) served_by_it[a] = 1;
  dead_.push_back(static_cast<int16_t>(agent.value()));
  if (revoke) revoked_ |= 1u << (dead_.size() - 1);
  declared_at_[agent] = now;
  repair_ = &team_.repaired(dead_.data(), dead_.size());
  // What was its own is declared lost now: the goals of the requests issued
  // so far that it (a worker) or its workers (a collector) had not resolved.
  // News from a survivor that still holds one overrides this (open()).
  for (std::size_t i = 0; i < requested(); ++i) {
    mission::GoalRecord& g = goals_[i];
    if (resolved_[i] || !g.worker.valid() || !served_by_it[g.worker]) continue;
    g.lost_at = now;
    resolve(g, mission::GoalState::kLostWithAgent);
  }
  // The requests to come go by the repaired plan.
  for (std::size_t i = requested(); i < goals_.size(); ++i) {
    mission::GoalRecord& g = goals_[i];
    const bool was_unassigned = !g.worker.valid();
    g.segment = SegmentId(repair_->plan.labels[cell_of_[i]]);
    g.worker = g.segment.valid() ? team_.worker_of_segment(g.segment) : AgentId();
    g.deadline = !g.worker.valid() || !assigned(g.worker).delivers_to.valid() ? std::numeric_limits<double>::infinity()
                                                                              : team_.deadline(g.worker, g.cycle);
    if (!g.worker.valid() && !was_unassigned) unassigned_.push_back(g.id);
  }
  // Workers that now deliver to the OC: as long to come as they had to be
  // heard of before (they learn of it by their own timeout, then walk).
  for (AgentId a : ids<AgentId>(team_.agents()))
    if (!repair_->dead[a] && served_by_it[a]) grace_until_[a] = now + team_.silent_timeout(team_.plan, a);
  if (issued_ > 0) issue(issued_ - 1, kBroadcast, now, out);  // the news, to whoever is in the coverage
}

std::size_t OcRole::close(double now) {
  closed_.assign(goals_.size(), 0);
  std::size_t n = 0;
  for (std::size_t i = 0; i < requested(); ++i) {
    mission::GoalRecord& g = goals_[i];
    if (resolved_[i]) continue;
    g.lost_at = std::max(now, g.requested_at);
    resolve(g, mission::GoalState::kLostWithAgent);
    closed_[i] = 1, ++n;
  }
  return n;
}

void OcRole::resolve(mission::GoalRecord& g, mission::GoalState state, int16_t by) {
  g.state = state;
  resolved_[g.id.index()] = 1;
  resolved_by_[g.id.index()] = by;
  ++resolved_count_;
}

bool OcRole::apply(const DataItem& item, AgentId sender, double now) {
  // The worker that measured it (expired, skipped) and the collector that
  // took it on (-1: none), as the item names them: agents of the team.
  if (item.by < 0 || item.by >= team_.agents() || item.picked_up_by < -1 || item.picked_up_by >= team_.agents())
    return false;
  // Who may hand it in (its sender is sure: per-link keys, docs/security.md):
  // a measured item that a collector took on, that collector, from one of
  // its workers; one no collector took, its worker; a notice, its worker or
  // the worker's collector. A robot that claims what another measured is
  // refused.
  const bool picked = item.kind == ItemKind::kMeasured && item.picked_up_by >= 0;
  const bool from_collector = team_.links.upstream()[static_cast<std::size_t>(item.by)] == sender.value();
  if (picked ? item.picked_up_by != sender.value() || !from_collector
             : item.by != sender.value() && (item.kind == ItemKind::kMeasured || !from_collector))
    return false;
  const AgentId by(item.by);
  if (item.kind == ItemKind::kSkipped) {
    const int c = skipped_request(item.key);
    if (c < 0 || c >= issued_ || skipped_worker(item.key) != item.by) return false;
    if (!(item.at >= issued_at_[static_cast<std::size_t>(c)] - 1e-6) || !(item.at <= now + 1e-6)) return false;
    if (of_revoked(item)) return discard(item);
    for (std::size_t i = first_[static_cast<std::size_t>(c)]; i < first_[static_cast<std::size_t>(c) + 1]; ++i) {
      mission::GoalRecord& g = goals_[i];
      if (g.worker != by || !open(g.id)) continue;
      g.expired_at = std::max(item.at, g.requested_at);
      resolve(g, mission::GoalState::kExpired, item.by);
    }
    return true;
  }
  const GoalId goal(item.key);  // a measured, expired or dropped item's key is its goal
  if (!goal.within(static_cast<int>(requested()))) return false;
  mission::GoalRecord& g = goals_[goal.index()];
  // Its worker, or the one whose segment its cell is in since a repair (a
  // request issued before the repair, learned after it).
  bool new_owner = false;
  if (g.worker != by) {
    const int32_t now_in = repair_ ? repair_->plan.labels[cell_of_[goal.index()]] : 0;
    new_owner = now_in > 0 && team_.worker_of_segment(SegmentId(now_in)) == by;
    // Another worker's measurement (its view of who is dead differed from
    // the OC's for a while, and it took over a segment the OC gave another):
    // the data is real, and acked either way; refused, it would be lost. Its
    // notices (expired, dropped, unreachable) are the owner's to give.
    if (!new_owner && item.kind != ItemKind::kMeasured) return false;
    if (!new_owner && !could_serve(by, goal)) return false;
  }
  // Times a worker and a collector could have: after the request, not after now.
  const double eps = 1e-6;
  if (!(item.at >= g.requested_at - eps && item.at <= now + eps)) return false;
  if (item.kind == ItemKind::kMeasured && item.picked_up_by >= 0 &&
      !(item.picked_up_at >= item.at - 1e-3 && item.picked_up_at <= now + eps))
    return false;
  if (of_revoked(item)) return discard(item);
  if (!open(goal, &item)) {
    ++duplicates_;
    return true;
  }
  // The deadline the worker applied counts from when the request reached
  // it: a collector late on its timetable handed it over late (never
  // earlier than the timetable's, which the OC knows).
  if (std::isfinite(item.deadline) && item.deadline > g.deadline) g.deadline = item.deadline;
  // Its deadline is the new worker's (goals.csv keeps the worker it was
  // issued to; measured_by says who measured it).
  if (new_owner)
    g.deadline =
        !assigned(by).delivers_to.valid() ? std::numeric_limits<double>::infinity() : team_.deadline(by, g.cycle);
  switch (item.kind) {
    case ItemKind::kMeasured:
      // A worker of a collector that brings its own data works for the OC
      // (it found its collector silent before the OC declared it dead): its
      // deadline started when it learned the request, as for every worker
      // of the OC, which the OC's record could not know at the issue.
      if (item.at > g.deadline && item.picked_up_by < 0 && sender == by && team_.assignment(sender).delivers_to.valid())
        g.deadline = std::numeric_limits<double>::infinity();
      if (item.at > g.deadline + 1e-9) {  // measured too late: it expired, whatever the data says
        ++late_;
        g.expired_at = std::max(g.deadline, g.requested_at);
        resolve(g, mission::GoalState::kExpired, item.by);  // its own data, late: sent again, still late
        break;
      }
      g.measured_at = item.at, g.measured_by = by;
      g.picked_up_at = item.picked_up_at;
      g.picked_up_by = AgentId(item.picked_up_by);  // checked above: an agent, or none
      g.delivered_at = now, g.delivered_by = sender;
      ++delivered_by_[sender];
      resolve(g, mission::GoalState::kDelivered);
      break;
    case ItemKind::kExpired:
      g.expired_at = std::max(item.at, g.requested_at);
      resolve(g, mission::GoalState::kExpired, item.by);
      break;
    case ItemKind::kDropped:
      g.measured_at = item.at, g.measured_by = by;
      g.dropped_at = item.at;
      resolve(g, mission::GoalState::kDropped, item.by);
      break;
    case ItemKind::kUnreachable:
      g.unreachable_at = std::max(item.at, g.requested_at);
      resolve(g, mission::GoalState::kUnreachable, item.by);
      break;
    default: return false;
  }
  return true;
}

void OcRole::step(double now, const Message* const* inbox, std::size_t n, Outbox& out) {
  // A request every period: broadcast to whoever is in the coverage.
  while (issued_ < team_.params.cycles && now >= issued_ * team_.period - 1e-9) {
    for (std::size_t i = first_[static_cast<std::size_t>(issued_)]; i < first_[static_cast<std::size_t>(issued_) + 1];
         ++i)
      goals_[i].requested_at = now;
    issued_at_[static_cast<std::size_t>(issued_)] = now;
    ++issued_;
    issue(issued_ - 1, kBroadcast, now, out);
  }
  // A goal in no worker's segment (a plan whose labels leave reachable cells
  // out) expires when the next request is due, as in the simulator.
  for (std::size_t k = 0; k < unassigned_.size();) {
    mission::GoalRecord& g = goals_[unassigned_[k].index()];
    const double due = (g.cycle + 1) * team_.period;
    if (g.cycle < issued_ && now >= due - 1e-9) {
      g.expired_at = due;
      resolve(g, mission::GoalState::kExpired);
      unassigned_[k] = unassigned_.back();
      unassigned_.pop_back();
    } else {
      ++k;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Message& m = *inbox[i];
    if (m.h.sender < 0 || m.h.sender >= team_.agents()) continue;
    const AgentId s(m.h.sender);
    heard_[s] = now;
    if (m.h.kind == Kind::kState && !assigned(s).collector) back_by_[s] = std::max(back_by_[s], m.state.back_by);
    if (assigned(s).collector) delay_[s] = std::max(0.0, m.h.delay);
    if (m.h.kind == Kind::kState && assigned(s).collector)  // its news of its workers
      for (std::size_t k = 0; k < std::min<std::size_t>(m.state.heard_count, kMaxHeard); ++k) {
        const AgentId w(m.state.heard_agent[k]);
        if (w.within(team_.agents()) && m.state.heard_at[k] <= now)
          heard_[w] = std::max(heard_[w], m.state.heard_at[k]);
      }
    const bool addressed = m.h.dest == kOc;
    if (addressed && m.h.kind == Kind::kData) {
      acks_.clear();
      const std::size_t count = std::min<std::size_t>(m.data.count, kMaxBatch);
      for (std::size_t k = 0; k < count; ++k) {
        if (!apply(m.data.items[k], s, now)) ++invalid_;
        acks_.push_back(m.data.items[k].key);  // acked either way: its sender lets go
      }
      if (Message* a = send(out, Kind::kAck, m.h.sender, now)) {
        a->ack.count = static_cast<uint16_t>(acks_.size());
        std::copy(acks_.begin(), acks_.end(), a->ack.keys);
      }
    } else if (addressed && m.h.kind == Kind::kState) {
      if (Message* a = send(out, Kind::kAck, m.h.sender, now)) a->ack.count = 0;  // "heard you"
    }
    // Collectors and workers of the OC take requests from the OC: one that
    // lacks the newest gets it, at once when it asked (data, hello), else
    // once a resend interval (its beacon: the broadcast may have been lost).
    // So does one that lacks the newest declarations of dead agents, and
    // any agent that asks (a worker whose collector went silent comes to
    // the OC before the OC's repair says so).
    const plan::AgentAssignment& a = assigned(s);
    const bool from_oc = a.collector || !a.delivers_to.valid() || addressed;
    const bool lags = m.h.request < issued_ - 1 || m.h.dead < known_declarations();
    double& answered = answered_at_[s];
    if (from_oc && issued_ > 0 && lags &&
        ((addressed && answered < now) || now - answered >= team_.params.resend_after)) {
      answered = now;
      issue(issued_ - 1, m.h.sender, now, out);
    }
  }
  // An agent unheard for longer than its timeout is declared dead.
  for (AgentId a : ids<AgentId>(team_.agents())) {
    if (declared_at_[a] >= 0 || dead_.size() >= static_cast<std::size_t>(kMaxDead)) continue;
    // A collector's worker is heard of through its collector: its silence
    // counts up to the collector's latest report (a silent collector is
    // declared first, and its workers then get their grace).
    const plan::AgentAssignment& as = assigned(a);
    const double news =
        !as.collector && as.delivers_to.valid() ? std::min(now, heard_[team_.collector_agent(as.delivers_to)]) : now;
    // Not before it is late on when it said it would be back (a robot
    // slower than planned is not a dead one), or, for a collector, on its
    // timetable as late as it last was.
    const double timeout = team_.silent_timeout(current_plan(), a) + delay_[a];
    if (news - heard_[a] > timeout && now > back_by_[a] + team_.period && now > grace_until_[a])
      declare_dead(a, now, out);
  }
}

}  // namespace agent
}  // namespace gather
