#include "gather_agent/transport/fleet_links.hpp"

#include "gather_agent/messages.hpp"

namespace gather {
namespace agent {

FleetLinks::FleetLinks(std::vector<int16_t> upstream) : upstream_(std::move(upstream)), downstream_(upstream_.size()) {
  for (std::size_t a = 0; a < upstream_.size(); ++a)
    if (upstream_[a] >= 0 && static_cast<std::size_t>(upstream_[a]) < upstream_.size())
      downstream_[static_cast<std::size_t>(upstream_[a])].push_back(static_cast<int16_t>(a));
}

bool FleetLinks::linked(int16_t a, int16_t b) const {
  if (!valid(a) || !valid(b) || a == b) return false;
  if (a == kOc || b == kOc) return true;
  return upstream_[static_cast<std::size_t>(a)] == b || upstream_[static_cast<std::size_t>(b)] == a;
}

bool FleetLinks::hears(int16_t receiver, int16_t sender, int16_t dest) const {
  if (receiver == sender) return false;
  return (dest == kBroadcast || dest == receiver) && linked(sender, receiver);
}

void FleetLinks::receivers(int16_t sender, int16_t dest, std::vector<int16_t>& out) const {
  out.clear();
  if (!valid(sender)) return;
  if (dest != kBroadcast) {
    if (linked(sender, dest)) out.push_back(dest);
    return;
  }
  if (sender == kOc) {
    for (int a = 0; a < agents(); ++a) out.push_back(static_cast<int16_t>(a));
    return;
  }
  out.push_back(kOc);
  const int16_t up = upstream_[static_cast<std::size_t>(sender)];
  const std::vector<int16_t>& down = downstream_[static_cast<std::size_t>(sender)];
  // By id: the collector among its workers' ids would be out of order only
  // for a worker, which has no workers of its own.
  if (valid(up) && up >= 0) out.push_back(up);
  out.insert(out.end(), down.begin(), down.end());
}

std::vector<int16_t> FleetLinks::peers(int16_t id) const {
  std::vector<int16_t> out;
  receivers(id, kBroadcast, out);
  return out;
}

}  // namespace agent
}  // namespace gather
