// world_move_base: move_base's ROS interface on top of one of gather_world's
// robots (MRPT: a differential drive, the reactive navigator, A* on the map),
// so that robot_bridge and robot.launch run against a robot that plans its
// own way, on one machine (tests/e2e/bridge_e2e.py). Goals come on
// move_base_simple/goal (geometry_msgs/PoseStamped) and go to gather_world
// as one-waypoint navigation commands over the robot interface (as an agent
// would send them, ~robot_url: gather_world's, not robot_bridge's); its
// goals' states go out on move_base/status (actionlib_msgs/GoalStatusArray:
// ACTIVE, SUCCEEDED, ABORTED when the robot gives up, PREEMPTED when a new
// goal or a cancel on move_base/cancel replaces it), the robot's pose on /tf
// (~map_frame -> ~base_frame). Exit status: 0 on shutdown, 2 bad input.
#include <actionlib_msgs/GoalID.h>
#include <actionlib_msgs/GoalStatusArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <cstdio>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "gather_agent/transport/lcm_robot.hpp"
#include "gather_oc/params.hpp"
#include "gather_oc/view_style.hpp"

namespace {

using gather::agent::NavCommand;
using gather::agent::NavState;

struct Goal {
  actionlib_msgs::GoalStatus status;
  int32_t command = 0;  // the navigation command that carries it
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "world_move_base");
  ros::NodeHandle nh, pnh("~");
  int agent = -1;
  std::string robot_url, key_file, map_frame, base_frame;
  bool insecure = false;
  double tolerance = 0.2, rate_hz = 20.0;
  std::string bad;
  for (const std::string& e :
       {gather::typed_param(pnh, "agent", agent, -1), gather::typed_param<std::string>(pnh, "robot_url", robot_url, ""),
        gather::typed_param<std::string>(pnh, "key_file", key_file, ""),
        gather::typed_param(pnh, "insecure", insecure, false),
        gather::typed_param<std::string>(pnh, "map_frame", map_frame, "map"),
        gather::typed_param<std::string>(pnh, "base_frame", base_frame, "base_link"),
        gather::typed_param(pnh, "tolerance", tolerance, 0.2), gather::typed_param(pnh, "rate", rate_hz, 20.0)})
    if (bad.empty()) bad = e;
  if (bad.empty() && (agent < 0 || agent >= gather::agent::kMaxTeam)) bad = "~agent must be a robot of gather_world";
  if (bad.empty() && robot_url.empty()) bad = "~robot_url must be gather_world's robot interface URL";
  if (bad.empty() && !(tolerance >= 0.01 && tolerance <= 10)) bad = "~tolerance must be in [0.01, 10] m";
  if (bad.empty() && !(rate_hz >= 1 && rate_hz <= 100)) bad = "~rate must be in [1, 100] Hz";
  if (!bad.empty()) {
    std::fprintf(stderr, "world_move_base: %s\n", bad.c_str());
    return 2;
  }
  std::unique_ptr<gather::agent::LcmRobotLink> link;
  try {
    link = std::make_unique<gather::agent::LcmRobotLink>(
        robot_url, gather::agent::LcmRobotLink::Side::kAgent, std::vector<int>{agent},
        gather::agent::robot_key_from_options(key_file, insecure, "world_move_base", "~key_file", "~insecure"));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "world_move_base: %s\n", e.what());
    return 2;
  }
  std::deque<Goal> goals;  // the last few, newest last
  NavCommand command{};
  command.agent = static_cast<int16_t>(agent);
  ros::Time sent;
  int next_goal = 0;
  auto send = [&] {
    link->send(command);
    sent = ros::Time::now();
  };
  gather::Point2 at{};
  auto end_current = [&](uint8_t state) {
    if (goals.empty() || goals.back().status.status != actionlib_msgs::GoalStatus::ACTIVE) return;
    goals.back().status.status = state;
    std::printf("world_move_base %d: %s %s at (%.2f, %.2f) after %.1f s\n", agent,
                goals.back().status.goal_id.id.c_str(),
                state == actionlib_msgs::GoalStatus::SUCCEEDED ? "succeeded"
                : state == actionlib_msgs::GoalStatus::ABORTED ? "aborted"
                                                               : "preempted",
                at.x, at.y, (ros::Time::now() - goals.back().status.goal_id.stamp).toSec());
    std::fflush(stdout);
  };
  ros::Subscriber goal_sub = nh.subscribe<geometry_msgs::PoseStamped>(
      "move_base_simple/goal", 10, [&](const geometry_msgs::PoseStamped::ConstPtr& g) {
        end_current(actionlib_msgs::GoalStatus::PREEMPTED);
        Goal n;
        n.status.goal_id.stamp = ros::Time::now();
        n.status.goal_id.id = "world-" + std::to_string(agent) + "-" + std::to_string(++next_goal);
        n.status.status = actionlib_msgs::GoalStatus::ACTIVE;
        command.id += 1, command.kind = NavCommand::Kind::kGo, command.n = 1;
        command.points[0] = {g->pose.position.x, g->pose.position.y};
        command.after[0] = 0.0, command.tolerance[0] = tolerance;
        n.command = command.id;
        goals.push_back(n);
        if (goals.size() > 8) goals.pop_front();
        send();
      });
  ros::Subscriber cancel_sub =
      nh.subscribe<actionlib_msgs::GoalID>("move_base/cancel", 10, [&](const actionlib_msgs::GoalID::ConstPtr& c) {
        if (goals.empty() || (!c->id.empty() && c->id != goals.back().status.goal_id.id)) return;
        end_current(actionlib_msgs::GoalStatus::PREEMPTED);
        command.id += 1, command.kind = NavCommand::Kind::kStop, command.n = 0;
        send();
      });
  ros::Publisher status_pub = nh.advertise<actionlib_msgs::GoalStatusArray>("move_base/status", 10);
  tf2_ros::TransformBroadcaster tf;
  ros::Rate rate(rate_hz);
  while (ros::ok()) {
    ros::spinOnce();
    link->handle(0);
    for (const gather::agent::RobotPose& p : link->poses()) {
      at = p.at;
      tf.sendTransform(gather::view::planar_transform(map_frame, base_frame, ros::Time::now(), p.at, p.heading));
    }
    link->poses().clear();
    for (const gather::agent::NavStatus& s : link->statuses()) {
      if (goals.empty() || s.command != goals.back().command) continue;
      if (s.state == NavState::kReached) end_current(actionlib_msgs::GoalStatus::SUCCEEDED);
      if (s.state == NavState::kFailed) end_current(actionlib_msgs::GoalStatus::ABORTED);
    }
    link->statuses().clear();
    // The command again every second while one is under way (the contract).
    if (command.id > 0 && (ros::Time::now() - sent).toSec() >= 1.0) send();
    actionlib_msgs::GoalStatusArray a;
    a.header.stamp = ros::Time::now();
    for (const Goal& g : goals) a.status_list.push_back(g.status);
    status_pub.publish(a);
    rate.sleep();
  }
  return 0;
}
