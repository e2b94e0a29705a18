#pragma once
// The heartbeat an agent publishes: who it is, its role, where it is.
#include <cstdint>

#include <gather_lcm/agent_state_t.hpp>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

// LCM channel of agent heartbeats.
constexpr const char* kAgentStateChannel = "GATHER_STATE";

enum class Role : int8_t {
  kUnassigned = gather_lcm::agent_state_t::ROLE_UNASSIGNED,
  kWorker = gather_lcm::agent_state_t::ROLE_WORKER,
  kCollector = gather_lcm::agent_state_t::ROLE_COLLECTOR,
};

const char* role_name(Role role);

// Builds consecutive heartbeats of one agent; the sequence number grows by one
// per message so receivers can count what they missed.
class Heartbeat {
 public:
  Heartbeat(int agent_id, Role role, Point2 pose) : id_(agent_id), role_(role), pose_(pose) {}
  void set_pose(Point2 pose, double yaw) { pose_ = pose, yaw_ = yaw; }
  void set_role(Role role) { role_ = role; }
  // The next message, stamped `stamp_us` [us].
  gather_lcm::agent_state_t next(int64_t stamp_us);

 private:
  int id_;
  Role role_;
  Point2 pose_;
  double yaw_ = 0.0;
  int64_t seq_ = 0;
};

}  // namespace gather
