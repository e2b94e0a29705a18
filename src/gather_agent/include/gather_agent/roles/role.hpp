#pragma once
// What a role is: a state machine that knows only the plan, its own pose and
// clock, and the messages it receives. Each control step takes the time and
// this tick's inbox, and yields the messages to send (an Outbox) and the
// motion to make (commands to its MotionBackend). No LCM, no ROS, no
// threads, no wall clock inside: the same roles run in one process
// (runner/team_runner) and one process per robot (gather_agent).
// Units: every time (`now`, `t`, `at`, deadlines) is mission time [s] since
// the first request; positions are map coordinates [m].
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "gather_agent/messages.hpp"
#include "gather_agent/motion/motion_backend.hpp"
#include "gather_agent/roles/custody.hpp"
#include "gather_agent/transport/fleet_links.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/mission/repair.hpp"
#include "gather_core/mission/route_timetable.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/mission/worker_policy.hpp"
#include "gather_core/mission/world.hpp"
#include "gather_core/path/grid_astar.hpp"
#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace agent {

// The mission the OC runs, as every agent must know it (the OC's plan
// announcement carries it; see runner/lockstep).
struct MissionParams {
  int cycles = 10;
  unsigned seed = 1;
  int goals_per_request = 40;
  std::size_t data_capacity = 0;    // custody buffer: measured items (0: 4 x goals_per_request, at least 64)
  std::size_t notice_capacity = 0;  // custody buffer: notices (0: as data_capacity)
  double beacon_period = 1.0;       // [s] agent state broadcast
  double resend_after = 1.0;        // [s] in contact without an ack: send again
  // [s] after a request is due without it, a worker of the OC asks the OC
  // for it, range [0, 60].
  double ask_after = 0.5;
  // The workers' decisions (mission::WorkerPolicy): the same as the
  // simulator's for the agents to match it.
  mission::ProtocolParams protocol;
  // Faults (docs/faults.md): what becomes of a dead worker's segment, and
  // the OC's liveness timeout in units of an agent's contact interval
  // (mission::silent_timeout), [1.5, 100].
  mission::RepairMode repair = mission::RepairMode::kMerge;
  double silent_intervals = 2.0;
  // Tests: the OC requests these goals (cycle, point [m]) instead of drawing
  // them (only the OC uses it; goals_per_request must be at least the
  // largest count of a cycle).
  std::vector<std::pair<int, Point2>> fixed_goals;
  // The OC revokes these agents' keys at these mission times [s]
  // (docs/security.md, "Revocation"; only the OC uses it): from then on it
  // and, once they learn it, every agent drop their messages, and what they
  // hold is lost with them. At most kMaxDead, each agent once.
  std::vector<std::pair<int16_t, double>> revoke;
};

// Everything the roles of one team share, read-only once built (except the
// FMM workspace in `distances`, used by one role at a time): the world, the
// plan, the collectors' timetables, the radio model. One per process.
class TeamSetup {
 public:
  // Throws gather::Error (naming "plan") when the plan does not fit the
  // world: label image size, agent ids, roles, routes.
  TeamSetup(const mission::World& world, const mission::MissionPlan& plan, const MissionParams& params);

  const mission::World& world;
  const mission::MissionPlan& plan;
  MissionParams params;
  double period = 0.0;  // [s] between two requests
  double speed = 0.0;   // [m/s]
  RadioModel radio;
  PerCollector<mission::RouteTimetable> routes;
  std::unique_ptr<mission::SharedDistances> distances;
  // On robots (protocol.home_clearance_m > 0) the homes of the workers of
  // the OC by agent id (mission::oc_worker_homes), found once for the team;
  // empty otherwise.
  std::vector<Cell> oc_homes;
  mission::AreaWeights areas;  // of the refresh interval (plan.yaml's area_tile_m)
  // Who talks to whom (the plan's links, which a repair keeps): what a role
  // hears, and who a message is signed for.
  FleetLinks links;

  // A* on the reachable cells, for the simulated bases: made on first use
  // (its per-cell arrays are some MB on a large map; an agent on a robot,
  // whose robot plans its own way, never makes it).
  GridAStar& paths();

  // The plan's agents (check_plan: valid, distinct and listed by id).
  int agents() const { return plan.file.agents.count(); }
  const plan::AgentAssignment& assignment(AgentId agent) const { return plan.file.agents[agent]; }
  // Per agent: 1 for a collector, 0 for a worker (LcmFleet::set_team).
  std::vector<uint8_t> collector_flags() const;
  // The agent that drives `collector` (mission::collector_agents).
  AgentId collector_agent(CollectorId collector) const { return collector_agent_[collector]; }
  // The worker of `segment` (none: no worker).
  AgentId worker_of_segment(SegmentId segment) const { return worker_of_segment_[segment]; }
  // Link between two positions [m] (the free-space range first, cheap).
  bool linked(Point2 a, Point2 b) const;
  // Where agent `agent` waits before the mission (free cells next to the OC).
  Point2 start_pose(AgentId agent) const { return start_[agent]; }
  // Deadline [s] of a goal of request `cycle` for worker `agent` of a
  // collector (mission::request_deadline); +inf for workers of the OC, whose
  // deadline starts when they learn the request.
  double deadline(AgentId agent, int cycle) const;

  // The plan the survivors execute once the agents in dead[0..n) are dead
  // (mission::repair_plan with params.repair), computed once per set of
  // dead agents and kept (agents learn the same sets in the same order).
  // `dead` as the messages carry them (RequestPart::dead).
  // Needs the plan's label image: plan.labels, or what reload_labels gives
  // (an agent process drops the image to save memory and reads it again
  // from the plan directory when a repair needs it: rarely).
  const mission::RepairedPlan& repaired(const int16_t* dead, std::size_t n);
  std::function<LabelImage()> reload_labels;
  // How long the OC waits without news of `agent` under `plan` (the
  // repaired one) before it declares it dead [s] (mission::silent_timeout).
  double silent_timeout(const mission::MissionPlan& plan, AgentId agent) const;

 private:
  std::unique_ptr<GridAStar> paths_;
  PerCollector<AgentId> collector_agent_;
  PerSegment<AgentId> worker_of_segment_;  // none: no worker
  PerAgent<double> meeting_arc_;           // [m] (workers of collectors)
  PerAgent<Point2> start_;
  double range_ = 0.0;
  std::vector<std::pair<std::vector<AgentId>, std::unique_ptr<mission::RepairedPlan>>> repaired_;
};

// The plan's links (FleetLinks): each worker of a collector to that
// collector's agent, everyone to the OC.
FleetLinks plan_links(const plan::PlanFile& plan);

// Messages a step sends, at most `capacity` (the rest is refused and counted).
class Outbox {
 public:
  explicit Outbox(std::size_t capacity) : messages_(capacity) {}
  // A message to fill, with its header's kind and destination set; nullptr
  // when the outbox is full.
  Message* add(Kind kind, int16_t dest);
  void clear() { n_ = 0; }
  std::size_t size() const { return n_; }
  const Message& operator[](std::size_t i) const { return messages_[i]; }
  Message& operator[](std::size_t i) { return messages_[i]; }
  int64_t refused() const { return refused_; }

 private:
  std::vector<Message> messages_;
  std::size_t n_ = 0;
  int64_t refused_ = 0;
};

// Per-role counters: what `make run` and the summaries print, and what the
// conservation check adds up.
struct RoleReport {
  RoleKind role = RoleKind::kWorker;
  int id = 0;
  int64_t measured = 0;         // goals measured and stored
  int64_t dropped = 0;          // goals measured whose data could not be stored
  int64_t expired = 0;          // goals expired (notices made)
  int64_t skipped = 0;          // requests skipped (notices made)
  int64_t pending = 0;          // goals known and not yet measured
  int64_t refused_full = 0;     // items refused because the custody buffer was full
  int64_t lost_notices = 0;     // notices that found no room (must stay 0)
  int64_t refused_revoked = 0;  // messages dropped: their sender's keys were revoked (Role::control)
  int64_t requests = 0;         // newest request known
  int64_t dead_known = 0;       // the OC's declarations of dead agents it knows
  // Its robot: waypoints reached, those reached late (LegStats) and by how
  // much [s], commands it failed, goals it could not reach.
  int64_t legs = 0, legs_late = 0;
  double late_median_s = 0.0, late_max_s = 0.0;
  int64_t nav_failures = 0;
  int64_t unreachable = 0;
  // Collectors: loops driven to their end, and how late their robot was
  // back at the OC (its delay at each loop's end) [s].
  int64_t loops = 0;
  double loop_late_median_s = 0.0, loop_late_max_s = 0.0;
};

// What a role keeps across a restart of its process besides its custody
// (runner/journal; docs/faults.md, "Crash and restart").
struct Progress {
  int32_t resolved = -1;                                        // every request up to this one learned or skipped
  int64_t measured = 0, dropped = 0, expired = 0, skipped = 0;  // its counters
  std::vector<int16_t> dead;                                    // the OC's declarations it knows
  uint32_t revoked = 0;                                         // bit i: dead[i]'s keys revoked
  std::vector<mission::KnownGoal> learned;  // the request it works on: its goals here, in learning order
  std::vector<GoalId> known;                // those not yet measured or expired
};

class Role {
 public:
  Role(int16_t id, MotionBackend& motion) : id_(id), motion_(motion) {}
  virtual ~Role() = default;
  Role(const Role&) = delete;
  Role& operator=(const Role&) = delete;

  // One control step at mission time `now` [s], after the motion backend
  // was advanced to `now`: `inbox` holds this tick's messages for this role
  // (already past the range gate), in (sender, seq) order.
  virtual void step(double now, const Message* const* inbox, std::size_t n, Outbox& out) = 0;
  // What the runners call: step() on the inbox without the messages of
  // agents whose keys the OC revoked (docs/security.md, "Revocation"), as
  // far as this role knows; those are dropped and counted.
  void control(double now, const Message* const* inbox, std::size_t n, Outbox& out);
  // What control() does before it filters (the OC revokes keys here).
  virtual void before_control(double /*now*/, Outbox& /*out*/) {}
  virtual RoleKind kind() const = 0;
  virtual RoleReport report() const = 0;
  // Items this role holds in custody (nullptr: none).
  virtual const Custody* custody() const { return nullptr; }
  // The same, for a journal that reads and clears its change log.
  Custody* custody_log() { return const_cast<Custody*>(custody()); }
  // Newest request this role knows (-1: none), carried in every header.
  virtual int32_t newest_request() const = 0;
  // [s] how far behind its timetable it is (collectors), carried in every header.
  virtual double delay() const { return 0.0; }
  // A worker the OC declared dead while it was alive (its messages were
  // lost): it stops for good (docs/faults.md). Its custody stays where it is.
  virtual bool retired() const { return false; }
  // The agents the OC has declared dead, as far as this role knows, in the
  // order the OC declared them.
  const std::vector<int16_t>& dead() const { return dead_; }
  // Of those, the ones whose keys the OC revoked (bit i: dead()[i]).
  uint32_t revoked_mask() const { return revoked_; }
  bool revoked(int16_t agent) const { return revoked_index(agent) >= 0; }
  // Its declaration's index in dead() when its keys were revoked, else -1.
  int revoked_index(int16_t agent) const;
  // Messages control() dropped from dead()[i] after it learned of its
  // revocation, and from all of them.
  int64_t refused_revoked(std::size_t i) const { return i < refused_.size() ? refused_[i] : 0; }
  int64_t refused_revoked() const;

  // Restart support (runner/journal). Changes whenever progress() would.
  virtual uint64_t progress_version() const { return dead_.size() + revoked_bits(); }
  virtual void progress(Progress& out) const {
    out = Progress{};
    out.dead = dead_;
    out.revoked = revoked_;
  }
  // A fresh role takes over what its process's previous life journaled:
  // the items it held (`items`), its progress, at mission time `now`.
  // Custody that does not fit is refused and counted (refused_full).
  // Throws gather::RuntimeError for a role that cannot restart (the OC's).
  virtual void restore(const DataItem* items, std::size_t n, const Progress& progress, double now);

  // Goals this role measured (and stored) in its last step, for views: the
  // OC's picture of which goals are being carried (nullptr: never any).
  virtual const std::vector<GoalId>* measured_in_step() const { return nullptr; }

  int16_t id() const { return id_; }
  MotionBackend& motion() { return motion_; }
  const MotionBackend& motion() const { return motion_; }

 protected:
  // A message with this role's header filled in (sender, time, pose,
  // request, the deaths it knows).
  Message* send(Outbox& out, Kind kind, int16_t dest, double now);
  // Takes the OC's list of dead agents from a request part when it is longer
  // than the one known (the OC only appends to it); true when it grew. The
  // revocations among them are learned too, also when only they are new.
  bool learn_dead(const RequestPart& part);
  // Revoked declarations known (a part of progress_version()).
  uint64_t revoked_bits() const;
  // What a header says the sender knows of the OC's declarations: the
  // deaths and the revocations among them (0 .. 2 kMaxDead). A receiver
  // that knows more passes its list on.
  std::size_t known_declarations() const { return dead_.size() + revoked_bits(); }
  // Writes the known list into a request part passed on.
  void stamp_dead(RequestPart& part) const;
  // A role declared dead while alive (its messages were lost, or its robot
  // was slow to come back) stops its work, but what it holds is still
  // delivered: it drives to the OC and hands its custody over there, then
  // stands still. Takes the OC's acks from `inbox`.
  void hand_in(const TeamSetup& team, double now, const Message* const* inbox, std::size_t n, Outbox& out,
               Custody& custody);

  int16_t id_;
  MotionBackend& motion_;
  std::vector<int16_t> dead_;
  uint32_t revoked_ = 0;                     // bit i: dead_[i]'s keys revoked
  std::array<int64_t, kMaxDead> refused_{};  // control(): messages dropped, by declaration
  std::vector<const Message*> admitted_;     // control(): the inbox without them
  bool handing_in_ = false;                  // driving to the OC with what it holds
  bool hand_in_contact_ = false;             // in contact with the OC at the last step
};

}  // namespace agent
}  // namespace gather
