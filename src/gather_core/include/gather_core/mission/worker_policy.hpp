#pragma once
// A worker's decisions, shared by the analytic simulator (which runs every
// worker's timeline in closed form) and the worker role of the agent runtime
// (which executes them tick by tick, over messages): which goals of its
// request it measures and in which order, where and when it meets its
// collector, when a request reaches it, and for a worker of the OC how it
// comes back into the coverage. One protocol, one code (docs/simulator.md,
// "Model"; docs/runtime.md).
//
// The policy also owns the worker's distance tables (geodesic distances by
// FMM between its goals, from its rendezvous cells, from where it came back
// into the coverage). After the first request it decides without allocating:
// its buffers are sized for `max_goals` goals a request at construction and
// the FMM workspaces keep their memory.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/mission/route_timetable.hpp"
#include "gather_core/mission/segment_window.hpp"
#include "gather_core/mission/tour.hpp"
#include "gather_core/mission/world.hpp"

namespace gather {
namespace mission {

// A goal of the worker's current request as the worker knows it.
struct KnownGoal {
  GoalId id;
  Cell cell;
  double deadline = 0.0;  // [s] unmeasured by then = expired
};

// Where a worker stands when it decides: its cell, and which precomputed
// distance table applies there (a march from the cell otherwise).
struct Spot {
  Cell cell;
  int rendezvous = -1;   // >= 0: at that rendezvous of its collector
  bool landing = false;  // OC worker: where it came back into the coverage
  bool meeting = false;  // collector worker: at its meeting point, waiting for a request
};

// Tables every worker of a world shares: the FMM workspace on the whole map
// (marches that leave a worker's window) and the distances from the OC's cell
// (every worker starts there in the simulator; `from_oc` false leaves it out,
// e.g. for an agent that starts elsewhere: 4 B/cell less). One per
// simulator; an agent process has its own.
struct SharedDistances {
  explicit SharedDistances(const World& world, bool from_oc = true);
  fmm::FastMarching fm;  // unit speed, the whole map
  Field from_oc;         // [m] geodesic distance of every cell from the OC's cell (or empty)
};

// The protocol's tuning that changes decisions: every worker of a team, in
// the simulator and in the agents, must run with the same values.
struct ProtocolParams {
  // [m] of route between two samples of a rendezvous' link window (the arcs
  // around a pass over which the radio link holds). Range [0.01, 1].
  double link_step_m = 0.1;
  // [m] a worker's segment window reaches past its segment (SegmentWindow):
  // its marches between goals stay in the segment dilated by this, and a
  // way found there is taken even if a shorter one leaves it. The planner's
  // estimate walks the same windows (PlannerOptions::protocol). Range [0, 100].
  double window_margin_m = 1.0;
  // 2-opt passes at most over a worker's tour through its goals
  // (mission::order_tour; bounded work per control step), range [0, 10000].
  int two_opt_rounds = kOpenTourTwoOptRounds;
  // Real motion (the agents' worker role; an ideal base never triggers
  // them). [s] a worker decides again while driving when its robot's
  // arrival estimate is this much later than planned, or its collector's
  // delay moved by this much since it planned. Range [0.1, 600].
  double replan_guard_s = 1.0;
  // A worker waiting at a pass for a collector it has not heard since the
  // pass was due assumes it late and waits on, at most this many of the
  // collector's loops past the planned pass; then it tries a later pass.
  // Range [0, 10].
  double wait_loops = 0.5;
  // [m] how close a robot must come to a place it drives to (a rendezvous,
  // a meeting point, its home in the coverage, the OC at the end of a
  // collector's loop) for it to count as there; goals take the robot's own
  // tolerance. Range [0.05, 10].
  double place_tolerance_m = 1.0;
  // [m] a worker of the OC waits for requests at a home with at least this
  // much room around it (the nearest such coverage cell to its plain home,
  // World::oc_worker_home): robots parked in a doorway block the others.
  // 0: its plain home (ideal bases need no room). Range [0, 5].
  double home_clearance_m = 0.0;
};
// Throws gather::Error("protocol params", "<field> = <value> must be in
// <range>") for a field outside its range.
void check_params(const ProtocolParams& params);

// The protocol for a team on robots (gather run --robots mrpt, mission.launch
// robots:=mrpt, robot.launch): `base` with homes that leave room to pass
// (home_clearance_m). Its ideal-base runs, compared with the robots', run it
// too (`gather run --protocol robots`).
ProtocolParams robot_protocol(ProtocolParams base);

// The homes of the workers of the OC on robots (World::oc_worker_homes for
// the segments of `plan`'s workers of the OC), by agent id: {-1, -1} for a
// collector, a worker of a collector, or a segment that reaches no coverage.
// Every agent computes the same.
std::vector<Cell> oc_worker_homes(const World& world, const MissionPlan& plan, double clearance);

// Where each agent of `plan` stands when the mission starts, by agent id.
// `oc_homes`: oc_worker_homes on robots, empty with the ideal protocol
// (home_clearance_m 0). Ideal: packed next to the OC (start_poses,
// kStartSpacing apart), as the planner assumes. Robots: each worker of the
// OC parked at its home, the others next to the OC kStartSpacing clear of
// them (a worker whose home is closer than that to an earlier one starts
// there too). A team packed around the OC would leave it as one crowd: in
// the cave the first two cycles delivered half of what ideal bases did
// (docs/robots.md). The agents and the robot world both use it, so a robot
// starts where its agent believes it is.
std::vector<Point2> team_start_poses(const World& world, const MissionPlan& plan, const std::vector<Cell>& oc_homes);

// When request `cycle` (issued at cycle * period [s]) reaches a worker of
// the collector driving `route`, whose meeting area is at arc `meeting_arc`
// [m]: the collector has it when next inside the OC's coverage at or after
// the issue, and hands it over when it next passes the meeting area.
// Request 0 is known from the start (0).
double request_reaches_worker(const RouteTimetable& route, double meeting_arc, int cycle, double period);

// The one expiry rule, for every worker (docs/simulator.md, "Expiry"): a
// request's goals stay valid for one request period after the request
// reached the worker (`reached` [s]), and no longer than until the next
// request reaches it (`next_reached`, +inf when not known), which supersedes
// them. Measured data never expires.
inline double request_deadline(double reached, double next_reached, double period) {
  return reached + period < next_reached ? reached + period : next_reached;
}

// A hand-over is planned to end this long [s] before its pass's link window
// does: 0.5 s, at most half the window (`window_s` [s]). Room for an agent's
// control period and its message round trip (docs/simulator.md, "Hand-over").
inline double handover_guard(double window_s) { return window_s < 1.0 ? 0.5 * window_s : 0.5; }

// What a worker on a real robot knows that the plan did not (the
// simulator, on ideal bases, keeps the defaults).
struct WorkerFacts {
  // [s] how far behind its timetable the worker believes its collector to
  // be: its passes come that much later.
  double collector_delay = 0.0;
  // Its robot's pace: its speed over the team speed, as measured on the
  // way so far (1: as planned); travel times are planned at the team speed
  // times this (WorkerPolicy::Decision::pace).
  double pace = 1.0;
};

class WorkerPolicy {
 public:
  enum class Action {
    kDone,            // nothing left, no request to come
    kGoToRendezvous,  // walk to rendezvous `rendezvous` (only when the meeting point cannot be reached)
    kGoToMeeting,     // walk to the meeting point (`landing`), where the next request is handed over;
                      // OC worker: to its home in the coverage (`landing`), where it waits for requests
    kWait,            // wait where it is for the next request
    kWork,            // measure tour[0..k), then (collector worker) walk to `rendezvous` and hand over by `handover`
    kBackToCoverage,  // OC worker: walk to `landing` (the nearest coverage cell)
  };
  struct Decision {
    Action action = Action::kDone;
    std::size_t k = 0;  // goals to measure: local indices tour[0..k), reached at at[0..k) [s]
    const int* tour = nullptr;
    const double* at = nullptr;
    int rendezvous = -1;      // collector worker: where it hands over
    double arrive = 0.0;      // [s] at the rendezvous (or the landing cell)
    double handover = 0.0;    // [s] when the hand-over there is planned to end (the link held for transfer_s)
    double link_until = 0.0;  // [s] when that pass's link window ends (the worker gives up after it)
    double pass = 0.0;        // [s] when the collector passes the rendezvous then
    Cell landing;             // kBackToCoverage: the coverage cell; kGoToMeeting: the meeting point's cell
    double pace = 1.0;        // the robot's pace the times assume (Facts::pace, or 1: tours_at_team_speed)
  };

  // Worker `agent` of `plan` (not a collector). `route`: its collector's
  // timetable (nullptr for a worker of the OC); it must outlive the policy,
  // as must `world` and `shared`. Throws gather::Error (naming "plan") when
  // the plan does not fit: a bad segment or collector, no meeting area or no
  // reachable pass of the collector next to the segment, or `protocol` out
  // of its ranges. On robots, `oc_homes` is oc_worker_homes(world, plan,
  // protocol.home_clearance_m) when the caller has it (the search takes
  // ~30 ms on the cave: once for a team, not once per worker); nullptr:
  // searched here.
  WorkerPolicy(const World& world, const MissionPlan& plan, const plan::AgentAssignment& agent,
               const RouteTimetable* route, SharedDistances& shared, std::size_t max_goals,
               const ProtocolParams& protocol, const std::vector<Cell>* oc_homes = nullptr);
  ~WorkerPolicy();
  WorkerPolicy(WorkerPolicy&&) noexcept;

  AgentId agent() const { return agent_; }
  SegmentId segment() const { return segment_; }
  CollectorId collector() const { return collector_; }  // none: delivers to the OC
  bool delivers_to_oc() const { return !collector_.valid(); }
  const RouteTimetable* route() const { return route_; }
  const std::vector<Cell>& rendezvous() const { return rendezvous_; }
  Point2 rendezvous_point(int r) const;
  double meeting_arc() const { return meeting_arc_; }  // [m] on the route
  // The arcs [m] of the route around rendezvous r's pass over which the
  // radio link between the rendezvous point and the collector holds without
  // a break (sampled every ProtocolParams::link_step_m; docs/simulator.md,
  // "Hand-over").
  std::pair<double, double> link_window(int r) const { return link_window_[static_cast<std::size_t>(r)]; }
  // Most goals one hand-over can carry: the longest link window, less the
  // guard, over one goal's transfer time (max_goals when transfers are
  // instant; 0: this worker can hand nothing over, and measures nothing).
  std::size_t handover_capacity() const { return capacity_; }
  // A reachable cell of this worker's segment (where its goals are).
  bool in_segment(Cell c) const { return segment_index(c) >= 0; }
  // Where a worker with nothing to do waits for the next request: the cell
  // of its meeting point on the route, where the collector hands requests
  // over (so the worker hears it there). Invalid (row -1) when that cell is
  // not reachable; it then waits at its nearest pass.
  Cell meeting_cell() const { return meeting_cell_; }
  // Workers of the OC: where they wait for requests, the coverage cell
  // nearest their segment (row -1 when there is none).
  Cell home() const { return home_; }

  // Collector workers: when request `cycle` (issued at cycle * period [s])
  // reaches the worker. Its collector has it when next inside the OC's
  // coverage at or after the issue, and hands it over when it next passes
  // the worker's meeting area. Request 0 is known from the start (t = 0).
  // A request's goals expire by request_deadline: deadline(c) =
  // min(learn_time(c) + period, learn_time(c + 1)). Workers of the OC learn a
  // request when they are next in the coverage, which this cannot know: +inf
  // here, and request_deadline(the time they learned it, ...) when they do.
  double learn_time(int cycle, double period) const;
  double deadline(int cycle, double period) const;

  // Learns a request: the goals of its segment (at most max_goals), which
  // replace the previous request's; one march per goal to the later goals.
  // Throws gather::Error when a goal is outside the segment or there are more
  // than max_goals.
  void learn(const KnownGoal* goals, std::size_t n);
  std::size_t goals() const { return n_; }
  std::size_t max_goals() const { return max_goals_; }
  // Room for `max_goals` goals a request (allocates; learn() then does not).
  void reserve(std::size_t max_goals);
  // For a control loop that must not allocate (an agent): every table and
  // FMM work list up front, instead of on first use. Allocates.
  void reserve_all();
  const KnownGoal& goal(std::size_t local) const { return goals_[local]; }

  using Facts = WorkerFacts;

  // The next step of a worker at `at` at time t [s] whose unmeasured goals
  // of the current request are `known` (local indices, deadlines not yet
  // passed), carrying `carried` measured goals not yet handed over, with
  // `more_requests` still to come. Collector workers: `no_meeting_before` [s] excludes meetings
  // before then (after a pass where the link failed). The returned pointers
  // stay valid until the next call.
  Decision decide(const Spot& at, double t, const int* known, std::size_t n_known, std::size_t carried,
                  bool more_requests, double no_meeting_before = 0.0, const Facts& facts = Facts{});

  // OC workers: where they come back into the coverage from `from` and the
  // way's length [m]: the nearest cell of the coverage (the labelled march
  // from the coverage border); on robots (homes apart, home_clearance_m >
  // 0) on through that cell to the worker's home, so that robots coming
  // back do not all stop on the same border cell of a corridor (the way
  // through the border cell: an upper bound of the shortest). Throws
  // gather::Error when the coverage cannot be reached.
  std::pair<Cell, double> way_back(Cell from) const;
  // On robots: the way back ends at the worker's home (see way_back).
  bool back_to_home() const { return !home_to_border_.empty(); }
  // On robots a worker of the OC plans its times at the team speed, not at
  // its robot's pace: a goal its robot may still reach in time is worth the
  // drive (reached late, it is cut on the way; planned at the pace, goals
  // it would have reached were left out: docs/robots.md). It tells the OC
  // when it will be back as it sets off, at its robot's pace. A worker of a
  // collector plans at the pace: it has to be at a pass on time.
  bool tours_at_team_speed() const { return delivers_to_oc() && back_to_home(); }

  // Distances [m] between the current request's goals (local indices), and
  // from goal i to rendezvous r.
  double between(std::size_t i, std::size_t j) const { return from_[i * stride_ + j]; }
  double goal_to_rendezvous(std::size_t i, std::size_t r) const { return from_[i * stride_ + n_ + r]; }

 private:
  void distances_from(const Spot& at);  // fills from_position_ for goals then rendezvous
  void march(Cell from, const std::vector<Cell>& targets, double* out);
  void march_one(Cell from, Cell to, double& out);
  void march_in_window(Cell from, const std::vector<Cell>& targets, double* out);
  void from_landing(Cell landing, const Cell* targets, std::size_t n, double* out);
  void order_tour(const int* known, std::size_t n_known);
  std::size_t arrival_times(double t);
  // A hand-over at one pass of the collector: the worker there from
  // `arrive`, the transfer from `start` to `done`, the link until `until` [s].
  struct Meeting {
    int rv = -1;
    double start = 0.0, done = 0.0, until = 0.0, pass = 0.0;
  };
  Meeting meeting_at(std::size_t r, double arrive, std::size_t load, double delay) const;
  Meeting earliest_meeting(std::size_t k, double t, double no_meeting_before, std::size_t load, double delay) const;

  const World& world_;
  SharedDistances& shared_;
  const RouteTimetable* route_ = nullptr;
  AgentId agent_;
  SegmentId segment_;
  CollectorId collector_;
  double speed_ = 1.0;  // [m/s] the team's
  double v_ = 1.0;      // [m/s] the speed of the decision under way (the team's times the robot's pace)
  double meeting_arc_ = 0.0;
  int two_opt_rounds_ = kOpenTourTwoOptRounds;          // ProtocolParams::two_opt_rounds
  std::vector<Cell> rendezvous_;                        // cells of its collector's passes next to its segment
  std::vector<double> rendezvous_arc_;                  // [m] their arc positions on the route
  std::vector<std::pair<double, double>> link_window_;  // [m] arcs of the route linked to each rendezvous
  std::size_t capacity_ = 0;                            // goals per hand-over (handover_capacity)
  // Geodesic distances [m] from each rendezvous to every cell of the segment
  // (by the cell's index in its segment) and to the other rendezvous.
  std::vector<std::vector<float>> rendezvous_to_cell_;
  std::vector<std::vector<double>> rendezvous_to_rendezvous_;
  std::vector<Cell> segment_cells_;  // by index in the segment
  // Index in segment_cells_ of each cell of the segment's bounding box (-1:
  // not of the segment).
  int32_t segment_index(Cell c) const;
  Cell box_origin_;
  int box_width_ = 0, box_height_ = 0;
  std::vector<int32_t> box_index_;
  Cell meeting_cell_{-1, -1};
  Cell home_{-1, -1};
  // On robots (homes apart): [m] from the home to each coverage border cell
  // (World::coverage_border), and how near its home a robot that came back
  // stands at home (ProtocolParams::place_tolerance_m). Empty otherwise.
  std::vector<double> home_to_border_;
  double place_tolerance_m_ = 0.0;
  std::vector<float> meeting_to_cell_;  // [m] from the meeting point to every cell of the segment
  std::vector<double> meeting_to_rv_;   // [m] from the meeting point to each rendezvous
  // Marches between goals stay in the segment's window (a way that leaves
  // it is re-marched on the whole map).
  std::unique_ptr<SegmentWindow> window_;
  // OC workers: distances [m] from the coverage cells they came back to, to
  // every cell of the segment (filled on first use, at most kMaxLandings).
  std::vector<std::pair<std::size_t, std::vector<float>>> landing_to_cell_;

  // The current request (capacity max_goals): goals, then the distance
  // matrix from_[i * stride_ + j] to goal j (j < n_) and rendezvous n_ + r.
  std::size_t max_goals_ = 0;
  std::size_t n_ = 0;
  std::size_t stride_ = 0;
  std::vector<KnownGoal> goals_;
  std::vector<Cell> cells_;  // goals then rendezvous cells
  std::vector<double> from_;
  std::vector<double> from_position_;  // [target]
  std::vector<double> position_to_rv_;
  // Decision buffers.
  std::vector<int> tour_;
  std::size_t tour_n_ = 0;
  std::vector<double> at_;
  std::vector<char> used_;
  // March scratch.
  std::vector<Cell> targets_;
  std::vector<double> tmp_;
  std::vector<fmm::Source> source_;
  fmm::SolveOptions solve_options_;
};

}  // namespace mission
}  // namespace gather
