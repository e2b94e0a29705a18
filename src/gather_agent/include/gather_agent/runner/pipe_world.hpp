#pragma once
// gather_world as a child process over a pair of pipes: the RobotWorld of a
// team run in one process (`gather run --robots mrpt`). Each tick the parent
// writes the agents' commands and a step, the world writes one pose and one
// status per robot and a done: the robot interface's messages in their LCM
// encoding (transport/lcm_robot's encode_robot, decode_robot), framed as
// [kind: 1 byte]['length: 4 bytes, little endian][payload]. No network, no
// signing (a parent and its child), and every tick is the same exchange,
// so a run is reproducible.
#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

#include "gather_agent/runner/robot_world.hpp"

namespace gather {
namespace agent {

// The pipe's frame kinds.
enum class PipeFrame : uint8_t {
  kCommand = 'C',  // parent -> world: nav_command_t
  kStep = 'S',     // parent -> world: int64 tick, double t (little endian)
  kPose = 'P',     // world -> parent: robot_pose_t
  kStatus = 'T',   // world -> parent: nav_status_t
  kDone = 'D',     // world -> parent: the tick's poses and statuses are out (empty)
  kError = 'E',    // world -> parent: one line of text, then it exits
  kQuit = 'Q',     // parent -> world: the run is over (empty)
};

// Writes one frame to `fd`; false when the pipe is closed.
bool write_frame(int fd, PipeFrame kind, const uint8_t* payload, uint32_t size);
// Reads one frame from `fd` into `payload` (at most `max` bytes); false at
// the end of the pipe or on a frame longer than `max`.
bool read_frame(int fd, PipeFrame& kind, std::vector<uint8_t>& payload, uint32_t max);

class PipeWorld : public RobotWorld {
 public:
  // Starts `command` (gather_world's binary and its arguments, to which
  // --pipe is added), its stdin and stdout on the pipes; its stderr stays
  // the parent's. `agents`: the team size. Throws gather::Error naming the
  // binary when it cannot start.
  PipeWorld(std::vector<std::string> command, int agents);
  ~PipeWorld() override;
  PipeWorld(const PipeWorld&) = delete;
  PipeWorld& operator=(const PipeWorld&) = delete;

  // Throws gather::RuntimeError("gather_world", ...) when the world ends,
  // says why (an 'E' frame), or sends what does not decode.
  void step(int64_t tick, double t, const std::vector<NavCommand>& commands, std::vector<RobotPose>& poses,
            std::vector<NavStatus>& statuses) override;

 private:
  // Throws what went wrong: `why`, or the world's own error frame when
  // `said` is false and it left one; an Error when it exited with status 2.
  [[noreturn]] void failed(const std::string& why, bool said = false);
  int agents_;
  pid_t pid_ = -1;
  int to_ = -1, from_ = -1;
  std::vector<uint8_t> buffer_;
};

}  // namespace agent
}  // namespace gather
