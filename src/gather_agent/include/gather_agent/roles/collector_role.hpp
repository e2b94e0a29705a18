#pragma once
// The collector role: drives its route loop after loop on the plan's
// timetable (mission::RouteTimetable, loops synchronised with the OC's
// requests), commanding its robot one loop at a time and reading back where
// it got: its delay is how far behind the timetable its robot is (from the
// waypoints reached and when, and its pose), and every message it sends
// carries it. It takes the newest request from the OC and hands it to each
// of its workers as it passes their meeting area (where it is: the
// timetable shifted by its delay), takes their data under custody (acks
// what it stored, refuses what does not fit) and delivers it to the OC
// whenever it is inside the coverage. It reports to the OC when it last
// heard each of its workers, and passes the OC's declarations of dead agents
// on with the requests.
#include <cstdint>
#include <vector>

#include "gather_agent/motion/leg_stats.hpp"
#include "gather_agent/roles/role.hpp"

namespace gather {
namespace agent {

class CollectorRole : public Role {
 public:
  // Collector `agent` of team.plan (its route is team.routes[its index]).
  CollectorRole(TeamSetup& team, AgentId agent, MotionBackend& motion);

  void step(double now, const Message* const* inbox, std::size_t n, Outbox& out) override;
  RoleKind kind() const override { return RoleKind::kCollector; }
  RoleReport report() const override;
  const Custody* custody() const override { return &custody_; }
  int32_t newest_request() const override { return complete_ ? request_id_ : -1; }
  double delay() const override { return delay_; }
  CollectorId collector() const { return collector_; }
  void restore(const DataItem* items, std::size_t n, const Progress& progress, double now) override;
  // Declared dead while alive (its messages were lost): it stops for good.
  bool retired() const override { return retired_; }
  // The timetable's time [s] at the collector's progress (now - delay).
  double timetable_time() const { return timetable_now_; }

 private:
  struct Served {
    int16_t agent;
    double meeting_arc;           // [m]
    int32_t handed = -1;          // newest request handed to it
    std::size_t handed_dead = 0;  // declarations of dead agents handed with it
    double heard_at = 0.0;        // [s] its latest message (reported to the OC: docs/faults.md)
  };
  void on_request(const RequestPart& part, double now);
  void hand_request(Served& w, double now, Outbox& out);
  Served* served(int16_t agent);
  // Its robot's progress: loops commanded when due, waypoints it failed
  // skipped, the delay measured.
  void drive(double now);
  // Commands the loop of planned departure `depart` from route vertex `first` on.
  void command_loop(double depart, std::size_t first, double now);
  double planned_at(std::size_t vertex) const;  // [s] on the loop being driven

  TeamSetup& team_;
  CollectorId collector_;
  const mission::RouteTimetable& route_;
  Custody custody_;
  std::vector<Served> workers_;
  // The newest request, as received (every part), to pass on as it is.
  std::vector<RequestPart> parts_;
  int32_t request_id_ = -1;
  uint64_t seen_ = 0;
  bool complete_ = false;
  // Driving the route.
  std::vector<Waypoint> legs_;
  bool driving_ = false;                                // a loop commanded and not yet reached
  double loop_depart_ = 0.0;                            // [s] planned departure of the loop driven
  std::size_t loop_first_ = 1;                          // route vertex of the command's first waypoint
  double next_depart_ = 0.0;                            // [s] the next loop's planned departure, at the earliest
  double delay_ = 0.0;                                  // [s]
  double timetable_prev_ = -1.0, timetable_now_ = 0.0;  // [s] the timetable's time at the previous step and now
  bool contact_prev_ = false;
  double next_beacon_ = 0.0;
  RoleReport counters_;
  LegStats legs_stats_, loop_stats_;
  std::size_t legs_seen_ = 0;  // waypoints of the loop commanded already counted in legs_stats_
  std::vector<int32_t> acks_;
  bool retired_ = false;
};

}  // namespace agent
}  // namespace gather
