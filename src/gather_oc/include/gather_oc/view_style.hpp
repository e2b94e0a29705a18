#pragma once
// How the mission looks in RViz: colours (the PNG figures' palette, see
// gather_core/figures/palette.hpp), marker sizes scaled to the map, heights
// that keep overlapping layers in order in a top-down view.
#include <geometry_msgs/TransformStamped.h>
#include <std_msgs/ColorRGBA.h>
#include <visualization_msgs/Marker.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "gather_core/figures/palette.hpp"
#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/ids.hpp"

namespace gather {
namespace view {

std_msgs::ColorRGBA rgba(float r, float g, float b, float a = 1.0f);
std_msgs::ColorRGBA rgba(figures::Rgb c, float a = 1.0f);

// Layer heights [m] (z), bottom to top.
constexpr double kZSegments = 0.01, kZCoverage = 0.02, kZRoutes = 0.04, kZMeetings = 0.05, kZPaths = 0.06,
                 kZGoals = 0.08, kZLinks = 0.10, kZAgents = 0.15, kZLabels = 0.5;

struct Style {
  // Builds the style of a map: `unit` [m] is the size of an agent's marker,
  // about 1/90 of the map's larger side (a 60 m office: 0.67 m).
  explicit Style(const OccupancyGrid& map);
  double unit = 0.5;

  std_msgs::ColorRGBA oc = rgba(0.85f, 0.08f, 0.08f);
  std_msgs::ColorRGBA oc_worker = rgba(0.08f, 0.08f, 0.08f);  // workers that deliver to the OC themselves
  std_msgs::ColorRGBA waiting = rgba(1.0f, 0.55f, 0.0f);      // before the mission starts
  std_msgs::ColorRGBA label = rgba(0.05f, 0.05f, 0.05f);
  std_msgs::ColorRGBA footprint = rgba(1.0f, 1.0f, 1.0f);  // a robot to scale, on its symbol
  std_msgs::ColorRGBA goal_pending = rgba(1.0f, 0.6f, 0.0f);
  std_msgs::ColorRGBA goal_carried = rgba(0.2f, 0.45f, 1.0f);
  std_msgs::ColorRGBA goal_delivered = rgba(0.1f, 0.7f, 0.2f);
  std_msgs::ColorRGBA goal_expired = rgba(0.85f, 0.1f, 0.1f);
  std_msgs::ColorRGBA goal_dropped = rgba(0.6f, 0.0f, 0.6f);
  std_msgs::ColorRGBA goal_lost = rgba(0.35f, 0.2f, 0.1f);  // lost with a dead agent
  std_msgs::ColorRGBA dead = rgba(0.6f, 0.6f, 0.6f, 0.8f);  // an agent the OC declared dead
  std_msgs::ColorRGBA link = rgba(0.45f, 0.45f, 0.5f, 0.4f);
  std_msgs::ColorRGBA handover = rgba(0.0f, 0.85f, 0.3f);
  std_msgs::ColorRGBA laser = rgba(0.95f, 0.05f, 0.55f, 0.9f);  // a robot's laser hits (laser:=true)

  // A collector's colour, its workers' too.
  std_msgs::ColorRGBA collector(CollectorId collector, float a = 1.0f) const;
};

// Where the team can be: the bounding box [m] of the cells reachable from
// the OC (the status line goes above it, the legend below; rviz_view fits
// the view to the free cells with room for both).
struct Box {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
Box reachable_box(const Mask& reachable);

// A point [m] at height z.
geometry_msgs::Point pt(Point2 p, double z = 0.0);
geometry_msgs::Point pt(double x, double y, double z = 0.0);
// The transform from `frame` to `child`: at `at` [m], turned by `yaw` [rad]
// about z (a robot's base, its laser).
geometry_msgs::TransformStamped planar_transform(const std::string& frame, const std::string& child,
                                                 const ros::Time& stamp, Point2 at, double yaw);

// A marker with the frame, stamp, namespace, id and type set, identity pose.
visualization_msgs::Marker marker(const std::string& frame, const ros::Time& stamp, const std::string& ns, int id,
                                  int type);

}  // namespace view
}  // namespace gather
