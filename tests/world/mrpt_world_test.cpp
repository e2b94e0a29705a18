// mrpt_world: MRPT robots behind the robot interface reach the waypoints
// they are sent to (and say when), report one they cannot reach as failed,
// see each other, and do the same again for the same commands, bit for bit.
#include "gather_world/mrpt_world.hpp"

#include <gtest/gtest.h>

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
  // 2 m at 0.5 m/s: 4 s at best; accelerating, turning: a little more.
  EXPECT_GT(s0.reached_at[0], 4.0);
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

TEST(MrptWorld, TheSameCommandsGiveTheSameRunBitForBit) {
  const OccupancyGrid map = room();
  const std::vector<NavCommand> cmds = {go(0, 1, {Point2{7.0, 2.0}}), go(1, 1, {Point2{6.5, 3.0}})};
  const Drive a = drive(map, cmds, 30.0), b = drive(map, cmds, 30.0);
  ASSERT_EQ(a.trace.size(), b.trace.size());
  EXPECT_EQ(std::memcmp(a.trace.data(), b.trace.data(), a.trace.size() * sizeof(double)), 0);
}

}  // namespace
}  // namespace world
}  // namespace gather
