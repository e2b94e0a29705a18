#pragma once
// What does not change during a mission, as RViz markers (published once,
// latched, on /gather/plan_markers). Namespaces a user can toggle:
//   segments      the partition: each worker's segment filled with a colour
//                 that differs from its neighbours' (the figures' palette)
//   segment_ids   "S<k>" at each segment's middle
//   oc            the Operation Center (red cube, "OC")
//   coverage      the outline of the OC's radio coverage (red)
//   routes        each collector's closed route, one colour per collector
//   route_ids     "C<index>" on each route
//   meetings      where each worker meets its collector (discs in the
//                 collector's colour), and the route stretches passing its
//                 segment (small discs)
//   legend        below the map: what the colours and shapes mean
#include <visualization_msgs/MarkerArray.h>

#include <string>

#include "gather_agent/roles/role.hpp"
#include "gather_oc/view_style.hpp"

namespace gather {
namespace view {

visualization_msgs::MarkerArray plan_markers(const agent::TeamSetup& team, const Style& style, const std::string& frame,
                                             const ros::Time& stamp);

// A legend below the box `below` (namespace "legend"): the goals' states,
// the agents' shapes and the lines, in their colours.
void legend(visualization_msgs::MarkerArray& out, const Style& style, const Box& below, const std::string& frame,
            const ros::Time& stamp);

// The point at arc length `s` [m] along a polyline (clamped to its ends).
Point2 point_at(const std::vector<Point2>& line, double s);

}  // namespace view
}  // namespace gather
