// mrpt_world: MRPT robots behind the robot interface reach the waypoints
// they are sent to (and say when), report one they cannot reach as failed,
// see each other and make way for each other (in a door, an idle robot on
// the way), say BLOCKED when held up and give the waypoint up later, do
// the same again for the same commands, bit for bit, and scan for views
// without changing any of it.
#include "gather_world/mrpt_world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "../core/predicate_grid.hpp"

namespace gather {
namespace world {
namespace {

using agent::NavCommand;
using agent::NavState;
using agent::NavStatus;
using agent::RobotPose;
using testing_support::predicate_grid;
constexpr double kPi = 3.14159265358979323846;

// 10 m x 6 m at 0.05 m/cell: walls around, a wall across at x = 5 m with a
// 1 m door at y in [2.5, 3.5], and a closed 1 m box at x in [8, 9], y in [4, 5].
OccupancyGrid room() {
  return predicate_grid(
      200, 120,
      [](int r, int c) {
        const double x = (c + 0.5) * 0.05, y = (r + 0.5) * 0.05;
        if (x < 0.1 || x > 9.9 || y < 0.1 || y > 5.9) return false;
        if (std::abs(x - 5.0) < 0.1 && !(y > 2.5 && y < 3.5)) return false;
        const bool box_wall = x > 7.9 && x < 9.1 && y > 3.9 && y < 5.1 && !(x > 8.0 && x < 9.0 && y > 4.0 && y < 5.0);
        return !box_wall;
      },
      0.05);
}

NavCommand go(int agent, int id, std::vector<Point2> points) {
  NavCommand c;
  c.agent = static_cast<int16_t>(agent), c.id = id, c.kind = NavCommand::Kind::kGo;
  c.n = static_cast<uint16_t>(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    c.points[i] = points[i], c.after[i] = 10.0 * (i + 1), c.tolerance[i] = 0.25;
  return c;
}

struct Drive {
  std::vector<RobotPose> poses;
  std::vector<NavStatus> statuses;
  std::vector<double> trace;  // every pose of every tick
};

// Two robots, commands at t = 0; steps to `until` [s].
Drive drive(const OccupancyGrid& map, const std::vector<NavCommand>& commands, double until) {
  MrptWorld w(map, {Point2{1.0, 1.0}, Point2{1.0, 5.0}}, 0.5, 0.2, WorldParams{});
  Drive r;
  for (int64_t k = 0; k * 0.1 <= until + 1e-9; ++k) {
    w.step(k, k * 0.1, k == 1 ? commands : std::vector<NavCommand>{}, r.poses, r.statuses);
    for (const RobotPose& p : r.poses) r.trace.insert(r.trace.end(), {p.at.x, p.at.y, p.heading});
  }
  return r;
}

TEST(MrptWorld, RobotsReachTheirWaypointsThroughTheDoorAndSayWhen) {
  const OccupancyGrid map = room();
  const Drive r = drive(map, {go(0, 1, {Point2{3.0, 1.0}, Point2{7.5, 1.5}}), go(1, 1, {Point2{7.0, 4.5}})}, 90.0);
  for (int a = 0; a < 2; ++a) {
    SCOPED_TRACE(a);
    const NavStatus& s = r.statuses[static_cast<std::size_t>(a)];
    EXPECT_EQ(s.command, 1);
    EXPECT_EQ(s.state, NavState::kReached);
    ASSERT_EQ(s.reached, a == 0 ? 2 : 1);
    for (int i = 0; i < s.reached; ++i) EXPECT_GT(s.reached_at[i], 0.0);
  }
  const NavStatus& s0 = r.statuses[0];
  // 2 m, reached within 0.25 m, at the top speed of 1.15 x the team speed
  // of 0.5 m/s: 3 s at best; accelerating, turning: a little more.
  EXPECT_GT(s0.reached_at[0], 1.75 / 0.575);
  EXPECT_LT(s0.reached_at[0], 12.0);
  // Then through the door: much more than the 4.5 m straight line.
  EXPECT_GT(s0.reached_at[1] - s0.reached_at[0], 9.0);
  EXPECT_NEAR(r.poses[0].at.x, 7.5, 0.3);
  EXPECT_NEAR(r.poses[1].at.y, 4.5, 0.3);
}

TEST(MrptWorld, AWaypointItCannotReachFails) {
  const OccupancyGrid map = room();
  const Drive r = drive(map, {go(0, 1, {Point2{2.0, 1.0}, Point2{8.5, 4.5}, Point2{3.0, 2.0}})}, 20.0);
  const NavStatus& s = r.statuses[0];
  EXPECT_EQ(s.state, NavState::kFailed);
  EXPECT_EQ(s.reached, 1);  // the first, then the box
}

// Robots at `starts`, `commands` at t = 0.1 s (tick 1); steps to `until`
// [s]. Each robot's state and position at every tick in `states`, `at`.
struct Scene {
  std::vector<RobotPose> poses;
  std::vector<NavStatus> statuses;
  std::vector<std::vector<NavState>> states;
  std::vector<std::vector<Point2>> at;
};
Scene run(const OccupancyGrid& map, const std::vector<Point2>& starts, const std::vector<NavCommand>& commands,
          double until, const WorldParams& params = WorldParams{}) {
  MrptWorld w(map, starts, 0.5, 0.2, params);
  Scene r;
  r.states.resize(starts.size()), r.at.resize(starts.size());
  for (int64_t k = 0; k * 0.1 <= until + 1e-9; ++k) {
    w.step(k, k * 0.1, k == 1 ? commands : std::vector<NavCommand>{}, r.poses, r.statuses);
    for (std::size_t i = 0; i < starts.size(); ++i)
      r.states[i].push_back(r.statuses[i].state), r.at[i].push_back(r.poses[i].at);
  }
  return r;
}

TEST(MrptWorld, TwoRobotsMeetingInTheDoorBothGetThrough) {
  const OccupancyGrid map = room();
  const Scene r = run(map, {Point2{3.0, 3.0}, Point2{7.0, 3.0}},
                      {go(0, 1, {Point2{7.5, 3.0}}), go(1, 1, {Point2{2.5, 3.0}})}, 60.0);
  for (int a = 0; a < 2; ++a) {
    SCOPED_TRACE(a);
    EXPECT_EQ(r.statuses[static_cast<std::size_t>(a)].state, NavState::kReached);
  }
  EXPECT_NEAR(r.poses[0].at.x, 7.5, 0.3);
  EXPECT_NEAR(r.poses[1].at.x, 2.5, 0.3);
}

TEST(MrptWorld, AnIdleRobotOnTheWayMakesWayAndStaysClose) {
  const OccupancyGrid map = room();
  // Robot 1 (never commanded) stands in the door robot 0 drives through.
  const Scene r = run(map, {Point2{3.0, 3.0}, Point2{5.0, 3.0}}, {go(0, 1, {Point2{7.5, 3.0}})}, 60.0);
  EXPECT_EQ(r.statuses[0].state, NavState::kReached);
  EXPECT_EQ(r.statuses[1].state, NavState::kIdle);
  EXPECT_LE(std::hypot(r.poses[1].at.x - 5.0, r.poses[1].at.y - 3.0), 1.05);
}

TEST(MrptWorld, ARobotHeldUpSaysBlockedThenGivesTheWaypointUp) {
  // A dead end 0.6 m wide: robot 1 stands at its end, robot 0 is sent past it.
  const OccupancyGrid map = predicate_grid(
      160, 80,
      [](int r, int c) {
        const double x = (c + 0.5) * 0.05, y = (r + 0.5) * 0.05;
        const bool hall = x > 0.1 && x < 3.0 && y > 0.1 && y < 3.9;
        const bool dead_end = x >= 3.0 && x < 7.0 && y > 1.7 && y < 2.3;
        return hall || dead_end;
      },
      0.05);
  WorldParams params;
  params.blocked_after = 5.0, params.give_up_after = 15.0;
  const Scene r = run(map, {Point2{1.5, 2.0}, Point2{6.6, 2.0}}, {go(0, 1, {Point2{6.6, 2.0}})}, 40.0, params);
  const std::vector<NavState>& s = r.states[0];
  const auto first = [&](NavState state) {
    return static_cast<double>(std::find(s.begin(), s.end(), state) - s.begin()) * 0.1;
  };
  EXPECT_LT(first(NavState::kBlocked), 25.0);
  EXPECT_LT(first(NavState::kFailed), 40.0);
  EXPECT_GT(first(NavState::kFailed), first(NavState::kBlocked) + 15.0 - params.blocked_after - 1.0);
  EXPECT_EQ(r.statuses[0].reached, 0);
  // Never ACTIVE standing still (a few centimetres) for longer than blocked_after.
  const std::size_t window = static_cast<std::size_t>(std::lround((params.blocked_after + 0.5) / 0.1));
  for (std::size_t k = window; k < s.size(); ++k) {
    if (s[k] != NavState::kActive) continue;
    double moved = 0.0;
    for (std::size_t j = k - window; j < k; ++j)
      moved = std::max(moved, std::hypot(r.at[0][j].x - r.at[0][k].x, r.at[0][j].y - r.at[0][k].y));
    EXPECT_GT(moved, 0.05) << "ACTIVE and still at t = " << static_cast<double>(k) * 0.1;
  }
}

TEST(MrptWorld, TheSameCommandsGiveTheSameRunBitForBit) {
  const OccupancyGrid map = room();
  const std::vector<NavCommand> cmds = {go(0, 1, {Point2{7.0, 2.0}}), go(1, 1, {Point2{6.5, 3.0}})};
  const Drive a = drive(map, cmds, 30.0), b = drive(map, cmds, 30.0);
  ASSERT_EQ(a.trace.size(), b.trace.size());
  EXPECT_EQ(std::memcmp(a.trace.data(), b.trace.data(), a.trace.size() * sizeof(double)), 0);
}

TEST(MrptWorld, AScanSeesTheWallsAndTheOtherRobotAndChangesNothing) {
  const OccupancyGrid map = room();
  MrptWorld w(map, {Point2{1.0, 1.0}, Point2{1.0, 5.0}}, 0.5, 0.2, WorldParams{});
  std::vector<RobotPose> poses;
  std::vector<NavStatus> statuses;
  w.step(0, 0.0, {}, poses, statuses);
  agent::RobotScan s;
  w.scan(0, s);  // an idle robot: taken now
  ASSERT_EQ(s.rays, 181);
  EXPECT_EQ(s.agent, 0);
  EXPECT_DOUBLE_EQ(s.at.x, 1.0);
  EXPECT_DOUBLE_EQ(s.at.y, 1.0);
  EXPECT_NEAR(s.angle_min, -kPi, 1e-6);
  EXPECT_NEAR(s.angle_increment, 2 * kPi / 181, 1e-6);
  EXPECT_FLOAT_EQ(s.range_max, 5.0f);
  // The walls at x = 0.1 and y = 0.1 m: 0.9 m away; the other robot (a
  // disc of 0.2 m 4 m up, ray 136 within 0.015 rad of it): 3.8 m; rays to
  // the upper right meet nothing within 5 m.
  float nearest = 1e9f;
  int open = 0;
  for (int k = 0; k < s.rays; ++k) {
    nearest = std::min(nearest, s.ranges[k]);
    open += std::isinf(s.ranges[k]);
  }
  EXPECT_NEAR(nearest, 0.9, 0.06);
  EXPECT_NEAR(s.ranges[136], 3.8, 0.06);
  EXPECT_GT(open, 0);
  // Scans for views change nothing the robots do.
  const std::vector<NavCommand> cmds = {go(0, 1, {Point2{7.0, 2.0}}), go(1, 1, {Point2{6.5, 3.0}})};
  const Drive plain = drive(map, cmds, 20.0);
  MrptWorld v(map, {Point2{1.0, 1.0}, Point2{1.0, 5.0}}, 0.5, 0.2, WorldParams{});
  std::vector<double> trace;
  for (int64_t k = 0; k * 0.1 <= 20.0 + 1e-9; ++k) {
    v.step(k, k * 0.1, k == 1 ? cmds : std::vector<NavCommand>{}, poses, statuses);
    for (const RobotPose& p : poses) trace.insert(trace.end(), {p.at.x, p.at.y, p.heading});
    if (k % 3 == 0) v.scan(0, s), v.scan(1, s);
  }
  ASSERT_EQ(trace.size(), plain.trace.size());
  EXPECT_EQ(std::memcmp(trace.data(), plain.trace.data(), trace.size() * sizeof(double)), 0);
}

}  // namespace
}  // namespace world
}  // namespace gather
