// roles/collector_role: a collector driven by hand acks and stores once,
// refuses when full, delivers in the coverage and relays requests; on a
// robot (a RobotBase fed by a scripted robot) its delay is what the robot
// reports, it hands requests on where the robot is, and reports its loops'
// lateness.
#include "gather_agent/roles/collector_role.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "corridor_team.hpp"
#include "gather_agent/motion/robot_base.hpp"
#include "gather_agent/runner/robot_world.hpp"
#include "scripted_world.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;
using agent_testing::measured;
using agent_testing::message;
using agent_testing::request;
using agent_testing::RobotScript;
using agent_testing::ScriptedRobot;
using agent_testing::Stepper;

TEST(CollectorRole, AcksStoresOnceRefusesWhenFullDeliversInCoverageRelaysRequests) {
  CorridorTeam c(2);
  c.team->params.data_capacity = 2;
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper k{make_agent(*c.team, AgentId(0))};
  k.step(0.0, {request(0, 0, {{19.05, 0.25}}, grid, kOc, kBroadcast)});
  // Its worker's data at t = 5 s (both at x ~ 5.5 m): acked, picked up now.
  Message d = message(Kind::kData, 1, 0, 0, Point2{5.5, 0.25});
  d.data.count = 1, d.data.items[0] = measured(0, 1, 4.5);
  k.step(5.0, {d});
  const Message* ack = k.sent(Kind::kAck);
  ASSERT_NE(ack, nullptr);
  EXPECT_EQ(ack->ack.count, 1u);
  // The same item again (its ack was lost): acked again, stored once.
  k.step(5.1, {d});
  ASSERT_NE(k.sent(Kind::kAck), nullptr);
  EXPECT_EQ(k.unit.role->custody()->data(), 1u);
  EXPECT_EQ(k.unit.role->custody()->item(0).picked_up_by, 0);
  EXPECT_NEAR(k.unit.role->custody()->item(0).picked_up_at, 5.0, 1e-9);
  // Two more: one fits (capacity 2), the other is refused and not acked.
  Message two = message(Kind::kData, 1, 0, 1, Point2{5.7, 0.25});
  two.data.count = 2, two.data.items[0] = measured(1, 1, 5.0), two.data.items[1] = measured(2, 1, 5.1);
  k.step(5.2, {two});
  ASSERT_NE(k.sent(Kind::kAck), nullptr);
  EXPECT_EQ(k.sent(Kind::kAck)->ack.count, 1u);
  EXPECT_EQ(k.unit.role->report().refused_full, 1);
  // The meeting area (arc 14.5 m) at 14.5 s: request 0 goes to the worker.
  bool relayed = false, delivered_early = false;
  double t = 5.3;
  for (; t < 15.0; t += 0.1) {
    k.step(t);
    if (const Message* r = k.sent(Kind::kRequest)) relayed = relayed || (r->h.dest == 1 && std::abs(t - 14.5) < 0.15);
    delivered_early = delivered_early || k.sent(Kind::kData);
  }
  EXPECT_TRUE(relayed);
  EXPECT_FALSE(delivered_early);  // out of the OC's coverage all along
  // Back in the coverage at 26.95 s: its data goes to the OC.
  double delivered = -1;
  for (; t < 30.0 && delivered < 0; t += 0.1) {
    k.step(t);
    if (const Message* m = k.sent(Kind::kData)) {
      delivered = t;
      EXPECT_EQ(m->h.dest, kOc);
    }
  }
  EXPECT_NEAR(delivered, 26.95, 0.15);
}
// A collector on a robot behind the robot interface (a RobotBase), its
// robot a scripted one: each tick of 0.1 s the robot takes the commands sent
// the tick before, moves and reports; then the role steps.
struct CollectorOnRobot {
  CorridorTeam c{2};
  CommandQueue queue;
  AgentUnit unit;
  ScriptedRobot robot;
  Outbox out{64};
  int64_t tick = 0;
  explicit CollectorOnRobot(RobotScript script)
      : unit(make_agent(*c.team, AgentId(0), nullptr, &queue)), robot(0, c.team->start_pose(AgentId(0)), script) {}
  RobotBase& base() { return static_cast<RobotBase&>(*unit.motion); }
  CollectorRole& role() { return static_cast<CollectorRole&>(*unit.role); }
  void step(double t, std::vector<Message> in = {}) {
    for (const NavCommand& cmd : queue.commands) robot.command(cmd);
    queue.commands.clear();
    robot.step(t);
    base().on_pose(robot.pose(tick), t);
    base().on_status(robot.status(tick), t);
    ++tick;
    unit.motion->update(t);
    std::vector<const Message*> inbox;
    for (const Message& m : in) inbox.push_back(&m);
    out.clear();
    unit.role->step(t, inbox.data(), inbox.size(), out);
  }
  const Message* sent(Kind k, int16_t dest) const {
    for (std::size_t i = 0; i < out.size(); ++i)
      if (out[i].h.kind == k && out[i].h.dest == dest) return &out[i];
    return nullptr;
  }
};

double metres(Point2 a, Point2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// On an ideal base (RouteBase) the collector is never late: its delay is 0
// at every step, the request goes to its worker at the meeting arc's time
// on the timetable (14.5 s), and its first loop ends on time.
TEST(CollectorRole, OnTimeItsDelayIsZeroAndItsLoopIsNotLate) {
  CorridorTeam c(2);
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper k{make_agent(*c.team, AgentId(0))};
  auto& role = static_cast<CollectorRole&>(*k.unit.role);
  k.step(0.0, {request(0, 0, {{19.05, 0.25}}, grid, kOc, kBroadcast)});
  double handed = -1.0;
  for (int i = 1; i <= 300; ++i) {
    const double t = i * 0.1;
    k.step(t);
    ASSERT_EQ(role.delay(), 0.0) << t;
    for (std::size_t m = 0; m < k.out.size(); ++m) {
      EXPECT_EQ(k.out[m].h.delay, 0.0);  // every message carries it
      if (k.out[m].h.kind == Kind::kRequest && k.out[m].h.dest == 1 && handed < 0) handed = t;
    }
  }
  EXPECT_NEAR(handed, 14.5, 0.15);
  const RoleReport r = role.report();
  EXPECT_EQ(r.loops, 1);  // back at the OC at 29 s
  EXPECT_EQ(r.loop_late_median_s, 0.0);
  EXPECT_EQ(r.loop_late_max_s, 0.0);
  EXPECT_EQ(r.legs, 2);
  EXPECT_EQ(r.legs_late, 0);
  EXPECT_EQ(r.nav_failures, 0);
}

// On a robot at half the team speed: its delay is how far behind its
// timetable the robot is (about half of the time driven), the
// request goes to its worker when the robot actually passes the meeting arc
// (where the timetable shifted by the delay is: about 29 s instead of
// 14.5 s), and the loop's lateness is reported at its end.
TEST(CollectorRole, OnALateRobotItsDelayIsTheLatenessAndItHandsTheRequestWhereItIs) {
  RobotScript half;
  half.speed = 0.5;
  CollectorOnRobot k(half);
  const OccupancyGrid& grid = k.c.scenario.grid;
  const std::vector<Point2>& way = k.c.team->routes[CollectorId(0)].waypoints();
  ASSERT_EQ(way.size(), 3u);
  const Point2 start = k.c.team->start_pose(AgentId(0));
  // When the robot reaches the far end and is back at the OC.
  const double far_end = metres(start, way[1]) / 0.5;
  const double back = far_end + metres(way[1], way[2]) / 0.5;
  ASSERT_GT(far_end, 20.0);
  k.step(0.0, {request(0, 0, {{19.05, 0.25}}, grid, kOc, kBroadcast)});
  ASSERT_EQ(k.queue.commands.size(), 1u);  // the first loop, commanded at once
  EXPECT_EQ(k.queue.commands[0].n, 2u);
  EXPECT_EQ(k.queue.commands[0].tolerance[1], k.c.team->params.protocol.place_tolerance_m);  // the OC: a place
  double handed = -1.0, delay_when_handed = -1.0;
  double t = 0.0;
  for (int i = 1; t < back + 0.55; ++i) {
    t = i * 0.1;
    k.step(t);
    if (const Message* r = k.sent(Kind::kRequest, 1); r && handed < 0) handed = t, delay_when_handed = r->h.delay;
    if (i == 100 || i == 200) {
      // On its way out, half as far as planned: 0.5 t behind.
      const double on_way = (k.robot.at().x - way[0].x) / 1.0;  // [s] of timetable its position is at
      EXPECT_NEAR(k.role().delay(), t - on_way, 0.06) << t;
      EXPECT_NEAR(k.role().timetable_time(), t - k.role().delay(), 1e-9) << t;
    }
    if (i == 400) {
      // On its way back (it turned at far_end, 14.5 s late).
      const double on_way = 14.5 + (way[1].x - k.robot.at().x);
      EXPECT_NEAR(k.role().delay(), t - on_way, 0.06) << t;
      EXPECT_GT(k.role().delay(), 14.5);
    }
  }
  // Handed where the robot passed the meeting arc (x = 15.05 m), not at 14.5 s.
  EXPECT_NEAR(handed, far_end, 0.25);
  EXPECT_NEAR(delay_when_handed, far_end - 14.5, 0.25);
  const RoleReport r = k.role().report();
  EXPECT_EQ(r.loops, 1);
  EXPECT_NEAR(r.loop_late_max_s, back - 29.0, 1e-6);  // back at the OC that late (exact: the robot's own times)
  EXPECT_NEAR(r.loop_late_median_s, back - 29.0, 0.05);
  EXPECT_EQ(r.legs, 2);
  EXPECT_EQ(r.legs_late, 2);
  EXPECT_NEAR(r.late_max_s, back - 29.0, 1e-6);
  // Back late, it departed at once (a new command) on the latest loop of
  // the timetable that has started: as late as that loop's departure.
  EXPECT_EQ(k.base().path_revision(), 2u);  // its second command (go, go)
  const double depart = std::max(29.0, k.c.team->routes[CollectorId(0)].schedule().last_departure(back));
  EXPECT_NEAR(k.role().delay(), t - depart, 0.5);
  EXPECT_EQ(k.base().state(), NavState::kActive);
}
}  // namespace
}  // namespace agent
}  // namespace gather
