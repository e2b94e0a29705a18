// roles/worker_role: a worker driven by hand on the corridor measures, hands
// over in contact, resends a lost ack, reports expiry, and ignores a request
// larger than its mission's; on a robot (a RobotBase fed by a scripted
// robot) a goal its robot fails is unreachable, one it reaches after the
// deadline expires, and a worker of the OC moved out of touch while it
// waits goes back in.
#include "gather_agent/roles/worker_role.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "corridor_team.hpp"
#include "gather_agent/motion/robot_base.hpp"
#include "gather_agent/runner/robot_world.hpp"
#include "gather_agent/runner/team_runner.hpp"
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

TEST(WorkerRole, MeasuresHandsOverInContactResendsALostAckAndReportsExpiry) {
  CorridorTeam c(3);
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper w{make_agent(*c.team, AgentId(1))};
  // Request 0 from the OC: goals at x = 5.05 (4.5 m from the OC) and 19.05.
  w.step(0.0, {request(0, 0, {{5.05, 0.25}, {19.05, 0.25}}, grid, kOc, kBroadcast)});
  auto& role = static_cast<WorkerRole&>(*w.unit.role);
  EXPECT_EQ(role.phase(), WorkerRole::Phase::kMoving);
  const Message* data = nullptr;
  double t = 0.0;
  for (; t < 10.0 && !data; t += 0.1) {
    w.step(t);
    data = w.sent(Kind::kData);
  }
  // Measured on arrival (about 4.5 m at 1 m/s from its start next to the OC),
  // in radio contact with the collector driving alongside: sent at once.
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(data->h.dest, 0);
  ASSERT_EQ(data->data.count, 1u);
  EXPECT_EQ(data->data.items[0].key, 0);
  // Measured on arrival: it heard the request at t = 0.1 s and walked from
  // its start pose at 1 m/s.
  const double walk = 5.05 - c.team->start_pose(AgentId(1)).x;
  EXPECT_NEAR(data->data.items[0].at, 0.1 + walk, 0.15);
  const double first = t;
  // No ack: sent again after resend_after (1 s) while in contact.
  double again = -1;
  for (; t < first + 3.0 && again < 0; t += 0.1) {
    w.step(t);
    if (w.sent(Kind::kData)) again = t;
  }
  EXPECT_NEAR(again - first, 1.0, 0.15);
  Message ack = message(Kind::kAck, 0, 1, 1, w.unit.motion->pose());
  ack.ack.count = 1, ack.ack.keys[0] = 0;
  w.step(t, {ack});
  EXPECT_EQ(role.custody()->data(), 0u);
  // The goal at 19.05 cannot be measured before the collector brings request
  // 1 (114.5 s): unless the worker gets there, it expires then, as a notice.
  for (t += 0.1; t < 130.0; t += 0.1) w.step(t);
  const RoleReport r = role.report();
  EXPECT_EQ(r.measured + r.expired, 2);
}

TEST(WorkerRole, IgnoresARequestLargerThanTheMissionsOwn) {
  CorridorTeam c(3);  // goals_per_request 4
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper w{make_agent(*c.team, AgentId(1))};
  std::vector<Point2> five = {{3.05, 0.25}, {4.05, 0.25}, {5.05, 0.25}, {6.05, 0.25}, {7.05, 0.25}};
  w.step(0.0, {request(0, 0, five, grid, kOc, kBroadcast)});
  EXPECT_EQ(static_cast<WorkerRole&>(*w.unit.role).phase(), WorkerRole::Phase::kStart);
  EXPECT_EQ(w.unit.role->newest_request(), -1);
}
// A worker on a robot behind the robot interface (a RobotBase), its robot a
// scripted one: each tick of 0.1 s the robot takes the commands sent the
// tick before, moves and reports; then the role steps.
struct WorkerOnRobot {
  CorridorTeam c{2};
  CommandQueue queue;
  AgentUnit unit;
  ScriptedRobot robot;
  Outbox out{64};
  int64_t tick = 0;
  std::vector<int32_t> go_ids;  // the id of every GO command sent (repeats too)
  explicit WorkerOnRobot(RobotScript script)
      : unit(make_agent(*c.team, AgentId(1), nullptr, &queue)), robot(1, c.team->start_pose(AgentId(1)), script) {}
  RobotBase& base() { return static_cast<RobotBase&>(*unit.motion); }
  WorkerRole& role() { return static_cast<WorkerRole&>(*unit.role); }
  void step(double t, std::vector<Message> in = {}) {
    for (const NavCommand& cmd : queue.commands) {
      if (cmd.kind == NavCommand::Kind::kGo) go_ids.push_back(cmd.id);
      robot.command(cmd);
    }
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
  const Message* sent(Kind k) const {
    for (std::size_t i = 0; i < out.size(); ++i)
      if (out[i].h.kind == k) return &out[i];
    return nullptr;
  }
  // Custody items of `kind`.
  std::vector<DataItem> held(ItemKind kind) const {
    std::vector<DataItem> items;
    const Custody& custody = *unit.role->custody();
    for (std::size_t i = 0; i < custody.size(); ++i)
      if (custody.item(i).kind == kind) items.push_back(custody.item(i));
    return items;
  }
};

// Its robot gives up the goal (FAILED on the goal's waypoint): the goal is
// unreachable, reported as a notice of its own kind, never measured nor
// expired, and handed on like any notice.
TEST(WorkerRole, AGoalItsRobotFailsIsUnreachable) {
  RobotScript fails;
  fails.fail_waypoint = 0;  // the first waypoint it is sent to: the goal
  WorkerOnRobot w(fails);
  const OccupancyGrid& grid = w.c.scenario.grid;
  w.step(0.0, {request(0, 0, {{5.05, 0.25}}, grid, kOc, kBroadcast)});
  ASSERT_EQ(w.role().phase(), WorkerRole::Phase::kMoving);
  ASSERT_EQ(w.queue.commands.size(), 1u);
  ASSERT_EQ(w.queue.commands[0].n, 2u);  // the goal, then the pass
  EXPECT_EQ(w.queue.commands[0].points[0].x, grid.cell_center(grid.world_to_cell(Point2{5.05, 0.25})).x);
  const Message* notice = nullptr;
  double t = 0.0;
  for (int i = 1; i <= 50; ++i) {
    t = i * 0.1;
    w.step(t);
    if (!notice && (notice = w.sent(Kind::kData)) != nullptr) {
      EXPECT_EQ(notice->h.dest, 0);  // to its collector, alongside at the start
      ASSERT_EQ(notice->data.count, 1u);
      EXPECT_EQ(notice->data.items[0].kind, ItemKind::kUnreachable);
      EXPECT_EQ(notice->data.items[0].key, 0);
      EXPECT_EQ(notice->data.items[0].by, 1);
    }
  }
  EXPECT_NE(notice, nullptr);
  const RoleReport r = w.role().report();
  EXPECT_EQ(r.unreachable, 1);
  EXPECT_EQ(r.nav_failures, 1);
  EXPECT_EQ(r.measured, 0);
  EXPECT_EQ(r.expired, 0);
  EXPECT_EQ(r.pending, 0);
  const std::vector<DataItem> given_up = w.held(ItemKind::kUnreachable);
  ASSERT_EQ(given_up.size(), 1u);
  EXPECT_EQ(given_up[0].key, 0);
  EXPECT_EQ(given_up[0].by, 1);
  EXPECT_NEAR(given_up[0].at, 0.1, 1e-9);  // when its robot said so
  EXPECT_EQ(given_up[0].deadline, w.c.team->deadline(AgentId(1), 0));
  EXPECT_TRUE(w.held(ItemKind::kMeasured).empty());
  EXPECT_TRUE(w.held(ItemKind::kExpired).empty());
  // From where it is, it decided again: the goal is not sent again.
  EXPECT_EQ(w.role().phase(), WorkerRole::Phase::kMoving);
  EXPECT_EQ(w.role().report().unreachable, 1);
}

// Its robot reaches a goal, after the goal's deadline: an expiry, reported
// with the deadline as its time, not a measurement. The deadline is the
// timetable's (100 s) shifted by the 0.05 s its collector was late handing
// the request over, 100.05 s, between two ticks: the robot's report of the
// waypoint (100.07 s) comes in the tick at 100.1 s, before the deadline
// itself would expire the goal. In time (99.9 s): measured.
TEST(WorkerRole, AGoalItsRobotReachesAfterItsDeadlineExpires) {
  for (const double arrival : {100.07, 99.9}) {
    CorridorTeam c(2);
    const Point2 start = c.team->start_pose(AgentId(1));
    const Point2 goal = c.scenario.grid.cell_center(c.scenario.grid.world_to_cell(Point2{5.05, 0.25}));
    RobotScript slow;
    slow.speed = std::hypot(goal.x - start.x, goal.y - start.y) / arrival;
    WorkerOnRobot w(slow);
    Message r = request(0, 0, {goal}, w.c.scenario.grid, 0, 1);  // from its collector,
    r.h.delay = 0.05;                                            // late by 0.05 s
    w.step(0.0, {r});
    ASSERT_EQ(w.role().phase(), WorkerRole::Phase::kMoving) << arrival;
    double t = 0.0;
    for (int i = 1; i <= 1003; ++i) w.step(t = i * 0.1);
    ASSERT_GE(w.base().legs_done(), 1u) << arrival;  // the robot got there
    EXPECT_NEAR(w.base().arrived_at(0), arrival, 1e-6);
    const RoleReport rep = w.role().report();
    if (arrival > 100.05) {
      EXPECT_EQ(rep.measured, 0);
      EXPECT_EQ(rep.expired, 1);
      const std::vector<DataItem> expired = w.held(ItemKind::kExpired);
      ASSERT_EQ(expired.size(), 1u);
      EXPECT_EQ(expired[0].key, 0);
      EXPECT_NEAR(expired[0].at, 100.05, 1e-9);
      EXPECT_NEAR(expired[0].deadline, 100.05, 1e-9);
      EXPECT_TRUE(w.held(ItemKind::kMeasured).empty());
    } else {
      EXPECT_EQ(rep.measured, 1);
      EXPECT_EQ(rep.expired, 0);
      const std::vector<DataItem> data = w.held(ItemKind::kMeasured);
      ASSERT_EQ(data.size(), 1u);
      EXPECT_NEAR(data[0].at, 99.9, 1e-6);
      EXPECT_NEAR(data[0].deadline, 100.05, 1e-9);  // the deadline it applied, for the OC
    }
    EXPECT_EQ(rep.unreachable, 0);
    EXPECT_GE(rep.legs, 1);  // its robot's legs are counted
  }
}
// Its robot is slow (half the plan's speed): its arrival estimate drifts
// past the guard again and again, and the worker decides again each time;
// the decisions drive the same way, so the command under way is kept (a new
// command would restart the robot's navigation: a real robot turns on the
// spot, re-plans, and never gets anywhere). The goal is still measured.
TEST(WorkerRole, DecidingAgainTheSameWayKeepsItsRobotsCommand) {
  CorridorTeam c(2);
  RobotScript slow;
  slow.speed = 0.5 * c.team->speed;
  slow.eta = false;  // the agent estimates its arrival from the pose, at the plan's speed: it drifts
  WorkerOnRobot w(slow);
  const Point2 goal = c.scenario.grid.cell_center(c.scenario.grid.world_to_cell(Point2{5.05, 0.25}));
  w.step(0.0, {request(0, 0, {goal}, w.c.scenario.grid, 0, 1)});
  ASSERT_EQ(w.role().phase(), WorkerRole::Phase::kMoving);
  for (int i = 1; i <= 400 && w.base().legs_done() == 0; ++i) w.step(i * 0.1);
  ASSERT_GE(w.base().legs_done(), 1u);
  ASSERT_FALSE(w.go_ids.empty());
  // Sent again every second while under way (the robot ignores repeats): one id.
  EXPECT_GT(w.go_ids.size(), 3u);
  for (int32_t id : w.go_ids) EXPECT_EQ(id, w.go_ids.front());
  EXPECT_EQ(w.role().report().measured, 1);
}

// A worker of the OC on a robot, with the robot protocol (homes apart): an
// open floor, agent 0 owning it; the OC answers every hello and acks every
// item.
struct OcWorkerOnRobot {
  Scenario scenario = testing_support::one_agent_floor();
  mission::World world{scenario};
  mission::MissionPlan plan = testing_support::corridor_plan_without_collector(scenario);
  MissionParams params;
  std::unique_ptr<TeamSetup> team;
  CommandQueue queue;
  std::unique_ptr<AgentUnit> unit;
  std::unique_ptr<ScriptedRobot> robot;
  Outbox out{64};
  int64_t tick = 0;
  std::vector<Message> replies;  // the OC's answers to what the worker sent, in the next step
  std::vector<int32_t> go_ids;
  std::vector<Point2> go_ends;  // the last waypoint of each new GO command
  OcWorkerOnRobot() {
    params.cycles = 3;
    params.goals_per_request = 4;
    params.protocol = mission::robot_protocol(params.protocol);
    team = std::make_unique<TeamSetup>(world, plan, params);
    unit = std::make_unique<AgentUnit>(make_agent(*team, AgentId(0), nullptr, &queue));
    robot = std::make_unique<ScriptedRobot>(0, team->start_pose(AgentId(0)), RobotScript{});
  }
  RobotBase& base() { return static_cast<RobotBase&>(*unit->motion); }
  WorkerRole& role() { return static_cast<WorkerRole&>(*unit->role); }
  void step(double t, std::vector<Message> in = {}) {
    for (const NavCommand& cmd : queue.commands) {
      if (cmd.kind == NavCommand::Kind::kGo && (go_ids.empty() || go_ids.back() != cmd.id)) {
        go_ids.push_back(cmd.id);
        go_ends.push_back(cmd.points[cmd.n - 1]);
      }
      robot->command(cmd);
    }
    queue.commands.clear();
    robot->step(t);
    base().on_pose(robot->pose(tick), t);
    base().on_status(robot->status(tick), t);
    ++tick;
    unit->motion->update(t);
    for (Message& m : replies) in.push_back(m);
    replies.clear();
    std::vector<const Message*> inbox;
    for (const Message& m : in) inbox.push_back(&m);
    out.clear();
    unit->role->step(t, inbox.data(), inbox.size(), out);
    for (std::size_t i = 0; i < out.size(); ++i) {
      const Message& m = out[i];
      if (m.h.dest != kOc || !team->linked(m.h.pos, scenario.oc)) continue;
      Message a = message(Kind::kAck, kOc, 0, 0, scenario.oc, 0);
      a.ack.count = 0;
      if (m.h.kind == Kind::kData)
        for (uint16_t k = 0; k < m.data.count; ++k) a.ack.keys[a.ack.count++] = m.data.items[k].key;
      replies.push_back(a);
    }
  }
  bool told_oc(Kind k) const {
    for (std::size_t i = 0; i < out.size(); ++i)
      if (out[i].h.kind == k && out[i].h.dest == kOc) return true;
    return false;
  }
};

// On robots a worker of the OC comes back to a home of its own, tells the
// OC when it sets off when it will be back, and, waiting, goes back in when
// its robot is moved out of touch with the OC (it stepped aside for
// another robot): it would never hear the next request there.
TEST(WorkerRole, AWorkerOfTheOcOutOfTouchWhileWaitingGoesBackIn) {
  OcWorkerOnRobot w;
  const Cell home = w.role().policy().home();
  ASSERT_TRUE(w.world.covered(home));
  const Point2 home_at = w.scenario.grid.cell_center(home);
  const Point2 goal = w.scenario.grid.cell_center(w.scenario.grid.world_to_cell(Point2{5.05, 3.05}));
  w.step(0.0, {request(0, 0, {goal}, w.scenario.grid, kOc, kBroadcast)});
  ASSERT_EQ(w.role().phase(), WorkerRole::Phase::kMoving);
  EXPECT_TRUE(w.told_oc(Kind::kState));  // when it will be back, before it leaves the coverage
  ASSERT_EQ(w.go_ids.size(), 0u);        // the command goes out in the next step
  double t = 0.0;
  for (int i = 1; i <= 300 && !(w.role().phase() == WorkerRole::Phase::kWaiting); ++i) w.step(t = i * 0.1);
  ASSERT_EQ(w.role().phase(), WorkerRole::Phase::kWaiting);
  EXPECT_EQ(w.role().report().measured, 1);
  EXPECT_EQ(w.role().custody()->data(), 0u);  // delivered
  // Its command went to the goal and back to its home, not to the border.
  ASSERT_FALSE(w.go_ends.empty());
  EXPECT_EQ(w.go_ends.front().x, home_at.x);
  EXPECT_EQ(w.go_ends.front().y, home_at.y);
  const Point2 at = w.robot->pose(0).at;
  EXPECT_LE(std::hypot(at.x - home_at.x, at.y - home_at.y), w.params.protocol.place_tolerance_m);
  // Waiting there, it stays (no new command).
  const std::size_t commands = w.go_ids.size();
  for (int i = 0; i < 20; ++i) w.step(t += 0.1);
  EXPECT_EQ(w.go_ids.size(), commands);
  EXPECT_EQ(w.role().phase(), WorkerRole::Phase::kWaiting);
  // Moved out of touch (x = 4 m: the coverage ends at 2.6 m): it drives
  // back home and waits there again.
  w.robot->place(Point2{4.05, 3.05});
  for (int i = 0; i < 100 && !(w.go_ids.size() > commands && w.role().phase() == WorkerRole::Phase::kWaiting); ++i)
    w.step(t += 0.1);
  ASSERT_GT(w.go_ids.size(), commands);
  EXPECT_EQ(w.go_ends.back().x, home_at.x);
  EXPECT_EQ(w.role().phase(), WorkerRole::Phase::kWaiting);
  const Point2 back = w.robot->pose(0).at;
  EXPECT_TRUE(w.world.covered(w.scenario.grid.world_to_cell(back)));
  EXPECT_TRUE(w.team->linked(back, w.scenario.oc));
}

// A worker of the OC on a robot at half the team speed, whose arrival
// estimate drifts from the plan (it decides again about every second on
// the way): its robot's pace counts the whole way to its first goal, not
// the bit since it last decided, so the time it tells the OC it will be
// back by is its robot's, not the plan's (the OC declares it dead on that
// time).
TEST(WorkerRole, ASlowRobotsPaceCountsTheWholeWayAndTellsTheOcWhenItWillBeBack) {
  OcWorkerOnRobot w;
  RobotScript slow;
  slow.speed = 0.5 * w.team->speed;
  slow.eta = false;  // the agent estimates its arrival from the pose, at the plan's speed: it drifts
  w.robot = std::make_unique<ScriptedRobot>(0, w.team->start_pose(AgentId(0)), slow);
  const OccupancyGrid& grid = w.scenario.grid;
  const Point2 near = grid.cell_center(grid.world_to_cell(Point2{5.05, 3.05}));
  const Point2 far = grid.cell_center(grid.world_to_cell(Point2{8.05, 3.05}));
  w.step(0.0, {request(0, 0, {near, far}, grid, kOc, kBroadcast)});
  double t = 0.0;
  for (int i = 1; i <= 600 && w.base().legs_done() == 0; ++i) w.step(t = i * 0.1);
  ASSERT_EQ(w.base().legs_done(), 1u);
  EXPECT_EQ(w.role().report().measured, 1);
  // Its next beacon says when it will be back home.
  double back_by = -1.0, told_at = 0.0;
  for (int i = 0; i < 100 && back_by < 0.0; ++i) {
    w.step(t += 0.1);
    for (std::size_t k = 0; k < w.out.size(); ++k)
      if (w.out[k].h.kind == Kind::kState && w.out[k].h.dest == kBroadcast)
        back_by = w.out[k].state.back_by, told_at = t;
  }
  ASSERT_GE(back_by, 0.0);
  for (int i = 0; i < 2000 && w.role().phase() != WorkerRole::Phase::kWaiting; ++i) w.step(t += 0.1);
  ASSERT_EQ(w.role().phase(), WorkerRole::Phase::kWaiting);
  EXPECT_EQ(w.role().report().measured, 2);
  // Back when it said, give or take a tenth of the way (at the plan's pace
  // it would have said half the time).
  EXPECT_NEAR(back_by, t, 0.1 * (t - told_at)) << "told at " << told_at;
}

}  // namespace
}  // namespace agent
}  // namespace gather
