// robot_bridge: the robot interface (docs/robots.md) for a robot that runs
// ROS 1 and move_base. It takes its agent's navigation commands
// (GATHER_ROBOT_CMD_<agent>) and gives move_base one waypoint at a time on
// ~goal_topic (geometry_msgs/PoseStamped, move_base_simple/goal: Debian 12
// has no move_base_msgs, so not the action); it reads move_base's progress
// from ~status_topic (actionlib_msgs/GoalStatusArray) and the robot's pose
// from TF (~map_frame -> ~base_frame), and reports both to the agent
// (GATHER_ROBOT_POSE_<agent> at ~pose_rate, GATHER_ROBOT_STATUS_<agent> on
// every change and every second; a pose only when TF has a newer one, with
// its stamp). STOP cancels on ~cancel_topic. What it
// decides is gather_oc/nav_bridge.hpp. Exit status: 0 on shutdown, 2 bad
// input (one line naming the parameter).
#include <actionlib_msgs/GoalID.h>
#include <actionlib_msgs/GoalStatusArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"
#include "gather_agent/transport/lcm_robot.hpp"
#include "gather_core/error.hpp"
#include "gather_oc/nav_bridge.hpp"
#include "gather_oc/params.hpp"

namespace {

struct Settings {
  int agent = -1;
  std::string robot_url, key_file, map_frame, base_frame, goal_topic, status_topic, cancel_topic;
  bool insecure = false;
  double pose_rate = 10.0;
  gather::oc::NavBridgeParams bridge;
};

// One line naming the parameter, or "".
std::string read_settings(const ros::NodeHandle& pnh, Settings& s) {
  using gather::typed_param;
  std::string e;
  auto first = [&e](const std::string& why) {
    if (e.empty()) e = why;
  };
  first(typed_param(pnh, "agent", s.agent, -1));
  first(typed_param<std::string>(pnh, "robot_url", s.robot_url, gather::agent::kRobotFleetUrl));
  first(typed_param<std::string>(pnh, "key_file", s.key_file, ""));
  first(typed_param(pnh, "insecure", s.insecure, false));
  first(typed_param<std::string>(pnh, "map_frame", s.map_frame, "map"));
  first(typed_param<std::string>(pnh, "base_frame", s.base_frame, "base_link"));
  first(typed_param<std::string>(pnh, "goal_topic", s.goal_topic, "move_base_simple/goal"));
  first(typed_param<std::string>(pnh, "status_topic", s.status_topic, "move_base/status"));
  first(typed_param<std::string>(pnh, "cancel_topic", s.cancel_topic, "move_base/cancel"));
  first(typed_param(pnh, "pose_rate", s.pose_rate, 10.0));
  first(typed_param(pnh, "blocked_after", s.bridge.blocked_after_s, 5.0));
  first(typed_param(pnh, "resend_after", s.bridge.resend_after_s, 2.0));
  if (!e.empty()) return e;
  if (s.agent < 0 || s.agent >= gather::agent::kMaxTeam)
    return "~agent must be the robot's agent id, 0.." + std::to_string(gather::agent::kMaxTeam - 1);
  if (!(s.pose_rate >= 1.0 && s.pose_rate <= 100.0)) return "~pose_rate must be in [1, 100] Hz";
  if (!(s.bridge.blocked_after_s >= 0.5 && s.bridge.blocked_after_s <= 600.0))
    return "~blocked_after must be in [0.5, 600] s";
  if (!(s.bridge.resend_after_s >= 0.2 && s.bridge.resend_after_s <= 60.0))
    return "~resend_after must be in [0.2, 60] s";
  if (s.map_frame.empty() || s.base_frame.empty()) return "~map_frame and ~base_frame must not be empty";
  return "";
}

double yaw_of(const geometry_msgs::Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "robot_bridge");
  ros::NodeHandle nh, pnh("~");
  Settings s;
  const std::string bad = read_settings(pnh, s);
  if (!bad.empty()) {
    std::fprintf(stderr, "robot_bridge: %s\n", bad.c_str());
    return 2;
  }
  std::unique_ptr<gather::agent::LcmRobotLink> link;
  try {
    const std::optional<gather::agent::FleetKey> key = gather::agent::robot_key_from_options(
        s.key_file, s.insecure, "robot_bridge " + std::to_string(s.agent), "~key_file", "~insecure");
    link = std::make_unique<gather::agent::LcmRobotLink>(s.robot_url, gather::agent::LcmRobotLink::Side::kRobots,
                                                         std::vector<int>{s.agent}, key);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "robot_bridge: %s\n", e.what());
    return 2;
  }
  gather::oc::NavBridge bridge(s.agent, s.bridge);
  ros::Publisher goal_pub = nh.advertise<geometry_msgs::PoseStamped>(s.goal_topic, 4);
  ros::Publisher cancel_pub = nh.advertise<actionlib_msgs::GoalID>(s.cancel_topic, 4);
  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);
  auto obey = [&](const gather::oc::MoveBaseOrder& o) {
    using Kind = gather::oc::MoveBaseOrder::Kind;
    if (o.kind == Kind::kGoal) {
      geometry_msgs::PoseStamped g;
      g.header.stamp = ros::Time::now();
      g.header.frame_id = s.map_frame;
      g.pose.position.x = o.at.x, g.pose.position.y = o.at.y;
      g.pose.orientation.z = std::sin(o.yaw / 2.0), g.pose.orientation.w = std::cos(o.yaw / 2.0);
      goal_pub.publish(g);
    } else if (o.kind == Kind::kCancel) {
      actionlib_msgs::GoalID c;
      c.id = o.goal_id;  // empty: every goal
      cancel_pub.publish(c);
    }
  };
  std::vector<gather::oc::GoalReport> reports;
  ros::Subscriber status_sub = nh.subscribe<actionlib_msgs::GoalStatusArray>(
      s.status_topic, 10, [&](const actionlib_msgs::GoalStatusArray::ConstPtr& m) {
        reports.clear();
        for (const actionlib_msgs::GoalStatus& g : m->status_list)
          if (g.status <= 9)
            reports.push_back({g.goal_id.id, g.goal_id.stamp.toSec(), static_cast<gather::oc::GoalStatus>(g.status)});
        obey(bridge.goal_status(reports, ros::Time::now().toSec()));
      });
  std::printf("robot_bridge %d: the robot interface on %s, move_base on %s and %s, pose from TF %s -> %s\n", s.agent,
              s.robot_url.c_str(), nh.resolveName(s.goal_topic).c_str(), nh.resolveName(s.status_topic).c_str(),
              s.map_frame.c_str(), s.base_frame.c_str());
  std::fflush(stdout);
  ros::Rate rate(s.pose_rate);
  ros::Time status_said;
  bool tf_said = false;
  double last_pose = -1.0;  // [s] stamp of the last pose sent
  gather::agent::NavState said_state = gather::agent::NavState::kIdle;
  while (ros::ok()) {
    ros::spinOnce();
    link->handle(0);
    const double now = ros::Time::now().toSec();
    for (const gather::agent::NavCommand& c : link->commands()) obey(bridge.command(c, now));
    link->commands().clear();
    try {
      // The newest pose TF has, stamped when it was valid; none when TF has
      // nothing newer (a localisation that stopped falls silent to the agent).
      const geometry_msgs::TransformStamped t = tf.lookupTransform(s.map_frame, s.base_frame, ros::Time(0));
      const double stamp = t.header.stamp.toSec();
      if (stamp > last_pose) {
        last_pose = stamp;
        obey(bridge.pose({t.transform.translation.x, t.transform.translation.y}, yaw_of(t.transform.rotation), stamp));
        gather::agent::RobotPose p = bridge.robot_pose();
        link->publish(p);
      }
      tf_said = false;
    } catch (const tf2::TransformException& e) {
      if (!tf_said) std::fprintf(stderr, "robot_bridge %d: no pose yet: %s\n", s.agent, e.what());
      tf_said = true;
    }
    obey(bridge.tick(now));
    const bool changed = bridge.take_changed();
    const gather::agent::NavState state = bridge.status().state;
    if (changed && state != said_state &&
        (state == gather::agent::NavState::kFailed || state == gather::agent::NavState::kBlocked ||
         said_state == gather::agent::NavState::kBlocked))
      std::fprintf(stderr, "robot_bridge %d: command %d %s at waypoint %d of %d (t = %.1f s)\n", s.agent,
                   bridge.status().command,
                   state == gather::agent::NavState::kFailed    ? "FAILED: move_base gave up"
                   : state == gather::agent::NavState::kBlocked ? "BLOCKED: no progress"
                                                                : "moves again",
                   bridge.status().reached, bridge.waypoints(), now);
    if (changed) said_state = state;
    if (changed || (ros::Time::now() - status_said).toSec() >= 1.0) {
      gather::agent::NavStatus st = bridge.status();
      st.stamp = now;
      link->publish(st);
      status_said = ros::Time::now();
    }
    rate.sleep();
  }
  return 0;
}
