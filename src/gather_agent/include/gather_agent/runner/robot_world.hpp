#pragma once
// The robots of a team run in one process (runner/team_runner): something
// that takes the agents' navigation commands and steps every robot to a
// tick's mission time, then says where each is and how its command goes,
// in the robot interface's messages (motion/robot_interface.hpp): so to
// its agent each robot is what a real robot would be. Implementations:
// gather_world over a pipe (runner/pipe_world.hpp, `gather run --robots
// mrpt`), and the tests' scripted robots.
#include <cstdint>
#include <vector>

#include "gather_agent/motion/robot_interface.hpp"

namespace gather {
namespace agent {

class RobotWorld {
 public:
  virtual ~RobotWorld() = default;
  // Takes `commands` (sent in the tick before, in the order they were sent),
  // steps every robot to mission time `t` [s] of lockstep tick `tick`, and
  // fills one pose and one status per robot, by agent id (0..N-1).
  virtual void step(int64_t tick, double t, const std::vector<NavCommand>& commands, std::vector<RobotPose>& poses,
                    std::vector<NavStatus>& statuses) = 0;
};

// The agents' commands in one process, in the order they are sent.
class CommandQueue : public NavCommandSink {
 public:
  void send(const NavCommand& command) override { commands.push_back(command); }
  std::vector<NavCommand> commands;
};

}  // namespace agent
}  // namespace gather
