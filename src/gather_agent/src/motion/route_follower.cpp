#include "gather_agent/motion/route_follower.hpp"

#include "gather_core/error.hpp"

namespace gather {
namespace agent {

void RouteFollower::go(const Waypoint*, std::size_t, double) {
  throw Error("motion", "a collector drives its route; it takes no waypoints");
}

}  // namespace agent
}  // namespace gather
