#pragma once
// Starts and stops the N agent processes of a local (simulated) team.
#include <sys/types.h>

#include <string>
#include <vector>

namespace gather {

struct AgentProcess {
  int id = 0;
  pid_t pid = -1;
  bool running = false;
  int exit_status = -1;        // exit code, or 128 + signal when killed by a signal
  bool exited_early = false;   // ended before stop() was called
  double stop_latency_s = -1;  // from SIGTERM to exit
  int restarts = 0;            // times it was started again (respawn)
};

class AgentFleet {
 public:
  // `command` = agent binary + its arguments; "{id}" in an argument is
  // replaced by the agent id. Children get SIGTERM if this process dies.
  AgentFleet(std::vector<std::string> command, int agents);
  ~AgentFleet();
  AgentFleet(const AgentFleet&) = delete;
  AgentFleet& operator=(const AgentFleet&) = delete;

  // Throws gather::Error if a process cannot be started.
  void start();
  // SIGKILL to agent `id` (if it runs), reaped.
  void kill(int id);
  // Starts agent `id` again with `extra` arguments appended (after reaping
  // it, with SIGKILL first if it still runs). Throws gather::Error if it
  // cannot be started.
  void respawn(int id, const std::vector<std::string>& extra);
  // Reaps children that have exited; returns the ids that ended since last call.
  std::vector<int> poll();
  // Waits up to `seconds` for every agent to end by itself; true if all did.
  bool wait(double seconds);
  // SIGTERM to every running agent, waits up to `grace_s`, then SIGKILL.
  void stop(double grace_s);

  const std::vector<AgentProcess>& agents() const { return agents_; }

 private:
  void launch(AgentProcess& a, const std::vector<std::string>& extra);
  std::vector<std::string> command_;
  std::vector<AgentProcess> agents_;
};

// The agent binary: `explicit_path` if non-empty, else lib/gather_agent/gather_agent
// under each CMAKE_PREFIX_PATH entry (catkin devel/install spaces), else PATH.
// Returns "" if not found.
std::string find_agent_binary(const std::string& explicit_path);
// The same for gather_world (package gather_world).
std::string find_world_binary(const std::string& explicit_path);

}  // namespace gather
