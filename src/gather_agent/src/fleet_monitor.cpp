#include "gather_agent/fleet_monitor.hpp"

#include <algorithm>

namespace gather {

FleetMonitor::Verdict FleetMonitor::on_message(const void* data, int size, double now_s) {
  gather_lcm::agent_state_t m{};
  if (m.decode(data, 0, size) != size) {
    ++rejected_;
    return Verdict::kUndecodable;
  }
  if (m.schema_version != gather_lcm::agent_state_t::SCHEMA_VERSION) {
    ++rejected_;
    return Verdict::kWrongSchema;
  }
  if (m.agent_id < 0 || static_cast<std::size_t>(m.agent_id) >= agents_.size()) {
    ++rejected_;
    return Verdict::kUnknownAgent;
  }
  AgentRecord& r = agents_[static_cast<std::size_t>(m.agent_id)];
  if (r.heard && m.seq <= r.last_seq) {
    ++r.out_of_order;
    return Verdict::kAccepted;
  }
  if (!r.heard) {
    r.first_seq = m.seq;
    r.first_heard_s = now_s;
  } else {
    r.missed += m.seq - r.last_seq - 1;
  }
  r.heard = true;
  r.last_seq = m.seq;
  ++r.heartbeats;
  r.role = static_cast<Role>(m.role);
  r.pose = Point2{m.x, m.y};
  r.yaw = m.yaw;
  r.last_heard_s = now_s;
  return Verdict::kAccepted;
}

int FleetMonitor::heard() const {
  return static_cast<int>(std::count_if(agents_.begin(), agents_.end(), [](const AgentRecord& r) { return r.heard; }));
}

}  // namespace gather
