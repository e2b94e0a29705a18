#include "gather_agent/heartbeat.hpp"

namespace gather {

const char* role_name(Role role) {
  switch (role) {
    case Role::kWorker: return "worker";
    case Role::kCollector: return "collector";
    case Role::kUnassigned: break;
  }
  return "unassigned";
}

gather_lcm::agent_state_t Heartbeat::next(int64_t stamp_us) {
  gather_lcm::agent_state_t m;
  m.schema_version = gather_lcm::agent_state_t::SCHEMA_VERSION;
  m.agent_id = id_;
  m.role = static_cast<int8_t>(role_);
  m.seq = seq_++;
  m.stamp_us = stamp_us;
  m.x = pose_.x;
  m.y = pose_.y;
  m.yaw = yaw_;
  return m;
}

}  // namespace gather
