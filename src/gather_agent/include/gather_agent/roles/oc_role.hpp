#pragma once
// The OC role: issues a request every period (the goals drawn as the
// analytic simulator draws them: mission::draw_goals), passes the newest one
// to a collector or a worker of the OC that lacks it, acks every item it
// receives and keeps the ledger of every goal (requested, measured, picked
// up, delivered, expired, dropped), from which the mission's goals.csv is
// written. The mission is done when every request is issued and every goal
// resolved.
#include <cstdint>
#include <vector>

#include "gather_agent/roles/role.hpp"
#include "gather_core/mission/simulator.hpp"

namespace gather {
namespace agent {

class OcRole : public Role {
 public:
  OcRole(TeamSetup& team, MotionBackend& station);

  void step(double now, const Message* const* inbox, std::size_t n, Outbox& out) override;
  // Revokes the keys due by now (MissionParams::revoke).
  void before_control(double now, Outbox& out) override;
  RoleKind kind() const override { return RoleKind::kOcRole; }
  RoleReport report() const override;
  int32_t newest_request() const override { return issued_ - 1; }

  bool done() const { return issued_ == team_.params.cycles && resolved_count_ == goals_.size(); }
  int issued() const { return issued_; }
  // Goals of the requests issued so far (ids 0 .. requested() - 1).
  std::size_t requested() const;
  const std::vector<mission::GoalRecord>& goals() const { return goals_; }
  bool resolved(GoalId goal) const { return resolved_[goal.index()] != 0; }
  std::size_t resolved_count() const { return resolved_count_; }
  int64_t invalid_items() const { return invalid_; }
  int64_t duplicate_items() const { return duplicates_; }
  // Measurements that came in after the deadline their worker applied
  // (recorded as expiries: a worker turns a late arrival into an expiry
  // itself, so this stays 0 unless a worker misbehaves).
  int64_t late_items() const { return late_; }
  // Items each agent delivered.
  int64_t delivered_by(AgentId agent) const { return delivered_by_[agent]; }
  // Faults (docs/faults.md): when the OC declared each agent dead (-1: it
  // did not), and goals it had declared lost that a survivor resolved later.
  double declared_dead_at(AgentId agent) const { return declared_at_[agent]; }
  int64_t recovered() const { return recovered_; }
  // Measurements of goals another agent's notice (or the OC) had resolved
  // without data, delivered all the same (open()).
  int64_t overridden() const { return overridden_; }
  // Revocation (docs/security.md): when the OC revoked each agent's keys
  // (-1: it did not); the items of it that others handed in after that and
  // the OC refused (what it held then, picked up from it later), and
  // whether goal g's measurement was refused so.
  double revoked_at(AgentId agent) const { return revoked_at_[agent]; }
  int64_t discarded_of(AgentId agent) const { return discarded_of_[agent]; }
  bool discarded(GoalId goal) const { return discarded_[goal.index()] != 0; }
  // The plan the OC runs now (the original until it declares a death).
  const mission::MissionPlan& current_plan() const { return repair_ ? repair_->plan : team_.plan; }
  // A team on robots at the end of its time: every goal not resolved yet is
  // lost with the agent that owes it (a robot stuck far away with what it
  // carries, or one that never came back), at `now`. Returns how many; they
  // are marked (closed_at_end()).
  std::size_t close(double now);
  bool closed_at_end(GoalId goal) const { return !closed_.empty() && closed_[goal.index()] != 0; }

 private:
  void issue(int cycle, int16_t dest, double now, Outbox& out);
  // Applies one item from `sender` at `now`; false if it names no goal of
  // this mission (it is acked all the same, so its sender lets go).
  bool apply(const DataItem& item, AgentId sender, double now);
  // Resolves g as `state`; `by`: the agent whose notice said so (-1: data,
  // or the OC itself).
  void resolve(mission::GoalRecord& g, mission::GoalState state, int16_t by = -1);
  // A goal resolved by news from an agent: unresolved, or declared lost
  // with an agent (the news overrides that; counted as recovered), or, for
  // a measurement (`item`), resolved without data by a notice of another
  // agent or by the OC: expired, dropped, unreachable (the data is real: a
  // worker that took the segment over measured what its owner gave up;
  // counted as overridden). A worker contradicting its own notice is not.
  bool open(GoalId goal, const DataItem* item = nullptr);
  const plan::AgentAssignment& assigned(AgentId agent) const { return current_plan().file.agents[agent]; }
  // Declares `agent` dead at `now`: repairs the plan, declares lost what was
  // its own (docs/faults.md), and tells whoever is in the coverage.
  void declare_dead(AgentId agent, double now, Outbox& out, bool revoke = false);
  // An item of a revoked agent handed in by another (not one its collector
  // took from it before the revocation): refused (apply() asks, once the
  // item passed every check of who may hand it in and when: discard()
  // counts it).
  bool of_revoked(const DataItem& item) const;
  // Whether worker `w` could have been given `goal`'s cell: by the plan, or
  // by a repair after some of the OC's declarations so far (in their order:
  // a worker may lag behind them; one that suspects its collector repairs
  // its plan alone, which changes no segment). A measurement by any other
  // worker is a claim no plan gave it: refused.
  bool could_serve(AgentId w, GoalId goal);
  bool discard(const DataItem& item);

  TeamSetup& team_;
  std::vector<std::size_t> first_;          // first goal id of each cycle's request, and the total at the end
  std::vector<mission::GoalRecord> goals_;  // every cycle's, drawn up front; requested_at set at the issue
  std::vector<uint32_t> cell_of_;           // grid index of each goal's cell
  std::vector<uint8_t> resolved_;
  std::vector<int16_t> resolved_by_;  // by goal: the agent whose notice resolved it (-1: the OC, or data)
  std::vector<GoalId> unassigned_;    // goals in no worker's segment, not yet expired
  std::vector<double> issued_at_;     // [s] by cycle
  std::size_t resolved_count_ = 0;
  int issued_ = 0;
  PerAgent<double> answered_at_;  // [s] last time it was passed the newest request
  PerAgent<int64_t> delivered_by_;
  std::vector<int32_t> acks_;
  int64_t invalid_ = 0, duplicates_ = 0, late_ = 0;
  // Liveness: the latest news of each agent [s] (its own messages, or a
  // collector's report of its worker), and the repair in force.
  PerAgent<double> heard_;
  // [s] when each agent said it would be back in touch (a worker's
  // back_by), and each collector's latest delay behind its timetable.
  PerAgent<double> back_by_, delay_;
  PerAgent<double> declared_at_;
  PerAgent<double> grace_until_;  // [s] no declaration before (workers moved to the OC)
  const mission::RepairedPlan* repair_ = nullptr;
  int64_t recovered_ = 0, overridden_ = 0;
  std::vector<uint8_t> closed_;  // by goal: lost at the mission's end (close())
  PerAgent<double> revoked_at_;
  PerAgent<int64_t> discarded_of_;
  std::vector<uint8_t> discarded_;  // by goal
};

}  // namespace agent
}  // namespace gather
