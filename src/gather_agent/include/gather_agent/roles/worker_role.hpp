#pragma once
// The worker role: visits the goals of its segment and hands their data on,
// to its collector (meeting it on the move at a pass of its route) or to the
// OC (coming back into the coverage). Its decisions are the analytic
// simulator's (mission::WorkerPolicy); this class executes them tick by tick
// over messages: requests arrive as messages, data leaves under custody
// (kept until acked), expired goals and skipped requests are reported to the
// OC as notices. docs/runtime.md describes the states.
#include <cstdint>
#include <memory>
#include <vector>

#include "gather_agent/motion/leg_stats.hpp"
#include "gather_agent/roles/role.hpp"

namespace gather {
namespace agent {

class WorkerRole : public Role {
 public:
  // Worker `agent` of team.plan. Throws gather::Error when the plan gives it
  // no segment, or its collector no meeting area for it.
  WorkerRole(TeamSetup& team, AgentId agent, MotionBackend& motion);

  void step(double now, const Message* const* inbox, std::size_t n, Outbox& out) override;
  RoleKind kind() const override { return RoleKind::kWorker; }
  RoleReport report() const override;
  const Custody* custody() const override { return &custody_; }
  const std::vector<GoalId>* measured_in_step() const override { return &measured_in_step_; }
  int32_t newest_request() const override { return std::max(resolved_, request_.complete() ? request_.id : -1); }

  enum class Phase { kStart, kReady, kMoving, kAtPass, kSettling, kWaiting, kDone };
  Phase phase() const { return phase_; }
  // "start", "ready", "moving", "at_pass", "settling", "waiting", "done"; "?" out of range.
  static const char* phase_name(int phase);
  const mission::WorkerPolicy& policy() const { return *policy_; }
  bool delivers_to_oc() const { return policy_->delivers_to_oc(); }
  bool retired() const override { return retired_; }
  uint64_t progress_version() const override { return progress_version_ + revoked_bits(); }
  void progress(Progress& out) const override;
  void restore(const DataItem* items, std::size_t n, const Progress& progress, double now) override;
  // Its collector went silent for longer than the OC waits to declare it
  // dead: it works for the OC until told otherwise (docs/faults.md).
  bool suspects_collector() const { return suspected_ >= 0; }
  int16_t upstream() const { return upstream_; }  // its collector's agent id, or kOc

 private:
  // The newest request being received (parts may come in several messages).
  struct Incoming {
    int32_t id = -1;
    uint16_t parts = 0;
    uint64_t seen = 0;                     // bit per part
    double delay = 0.0;                    // [s] its courier's delay when it handed it over (0: from the OC)
    std::vector<mission::KnownGoal> mine;  // goals of this worker's segment
    bool complete() const { return id >= 0 && parts > 0 && seen == (parts >= 64 ? ~0ull : ((1ull << parts) - 1)); }
  };

  void on_request(const RequestPart& part, int16_t sender, double delay);
  void measure(int local, double at);
  double goal_deadline(GoalId goal) const;  // [s] of a goal of the current request (+inf: not one)
  // Its robot's progress on the plan: goals reached measured, a waypoint it
  // could not reach given up, a plan that drifted decided again.
  void follow_progress(double now);
  void notice(ItemKind kind, int32_t key, double at);
  void skip_overdue(double now);
  void expire_overdue(double now);
  bool settled(double now, bool contact);
  void settle();            // back in the coverage: it waits to hear the OC
  bool reaches_oc() const;  // in the coverage, and its radio reaches the OC from where it is
  // [s] when its robot will be where the plan under way ends: the plan's
  // time, stretched by its robot's pace where the plan assumed another.
  double back_by(double now) const;
  void decide(double now);
  bool contact(double now) const;  // with its upstream, as predicted by the radio model
  double due_time() const;         // [s] when the next request should reach it
  // [s] of request `cycle`'s goals here (inf: a worker of the OC), for a
  // request its collector handed over `delay` [s] behind its timetable.
  double deadline(int cycle, double delay) const;
  // Executes the plan repaired for the deaths it knows (the OC's, and its
  // collector if it suspects it): a new policy when its segment or its
  // collector changed, or retirement when it is declared dead itself.
  void repair(double now);

  TeamSetup& team_;
  std::unique_ptr<mission::WorkerPolicy> policy_;
  bool retired_ = false;
  uint64_t progress_version_ = 0;  // bumped whenever progress() changes
  int16_t suspected_ = -1;         // the collector (agent id) it suspects dead, -1 none
  double upstream_heard_ = 0.0;    // [s] the latest message from its collector
  double suspect_after_ = 0.0;     // [s] of silence from its collector before it suspects it
  int64_t served_cells_ = 0;       // cells of the label it serves (grows when a segment is merged into it)
  Custody custody_;
  int16_t upstream_ = kOc;
  Phase phase_ = Phase::kStart;
  Incoming request_;                      // newest request received (maybe not yet learned)
  int32_t resolved_ = -1;                 // every request up to this one is learned or skipped
  std::vector<GoalId> measured_in_step_;  // goals measured in the last step
  std::vector<int> known_;                // local indices of the learned request's unmeasured goals
  // The plan being executed.
  std::vector<Waypoint> legs_;
  std::vector<int> leg_goal_;       // local goal index per leg, -1 for the pass / landing
  std::vector<Waypoint> old_legs_;  // scratch: the plan under way while deciding again
  std::vector<int> old_goal_;
  // [s] each leg's travel time at the team speed as first planned (kept
  // when a decision again keeps the leg; < 0: a leg whose planned time is
  // not travel alone, left out of the pace), and when the leg under way
  // began.
  std::vector<double> leg_nominal_, old_nominal_;
  double leg_began_ = 0.0;
  std::size_t n_legs_ = 0, legs_seen_ = 0;
  bool plan_is_work_ = false;
  int target_rv_ = -1, at_rv_ = -1;
  bool ends_at_landing_ = false, at_landing_ = false;
  bool ends_at_meeting_ = false, at_meeting_ = false;
  bool into_coverage_ = false;  // a worker of the OC on from its landing towards the OC, into the coverage
  // A worker of the OC on robots driving back in to its home
  // (WorkerPolicy::back_to_home): in touch with the OC on the way, it settles.
  bool back_in_ = false;
  double handover_ = 0.0, link_until_ = 0.0, no_meeting_before_ = 0.0;
  double pass_ = 0.0;  // [s] when the plan under way expects its collector at the rendezvous
  // Its collector's delay [s]: as the collector's latest message said
  // (collector_delay_), and as the plan under way assumed (delay_used_).
  double collector_delay_ = 0.0, delay_used_ = 0.0;
  double learned_delay_ = 0.0;  // [s] the delay the learned request came with (its deadline's shift)
  // Its robot's pace (WorkerPolicy::Facts::pace), measured over the legs it
  // drove: their travel time at the team speed, as first planned, over the
  // time they took from when each began (deciding again on the way changes
  // neither), each sum decaying with the time driven (kPaceHorizon_s); the
  // pace the plan under way assumed.
  static constexpr double kPaceHorizon_s = 120.0, kMinPace = 0.25, kMaxPace = 4.0;
  double pace_ = 1.0, pace_used_ = 1.0, planned_s_ = 0.0, took_s_ = 0.0;
  double eta_base_ = 0.0;        // [s] its robot's first arrival estimate for the plan under way (+inf: none yet)
  double next_replan_ = 0.0;     // [s] no decision again for drift before then
  bool replan_driving_ = false;  // deciding again while its robot drives (the command may be kept)
  // [s] after its robot failed to reach a place, no decision before then.
  static constexpr double kRetryPlace = 5.0;
  double decide_after_ = 0.0;
  // [s] since when the worker is in contact upstream with data on board (-1:
  // not): a hand-over of n goals goes out once that has lasted
  // transfer_s(n) (docs/simulator.md, "Hand-over").
  double transfer_since_ = -1.0;
  bool sent_in_contact_ = false;
  // Contact and state messages.
  bool contact_prev_ = false;
  bool heard_oc_ = false;   // OC workers: the OC answered since it came back into the coverage
  int32_t oc_newest_ = -1;  // the newest request the OC said it has
  double next_beacon_ = 0.0, last_hello_ = -1e300;
  std::vector<mission::KnownGoal> scratch_;
  RoleReport counters_;
  LegStats legs_stats_;
  std::vector<mission::KnownGoal> none_;
};

}  // namespace agent
}  // namespace gather
