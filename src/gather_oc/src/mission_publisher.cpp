#include "gather_oc/mission_publisher.hpp"

#include <geometry_msgs/PoseStamped.h>
#include <rosgraph_msgs/Clock.h>

#include "gather_oc/plan_markers.hpp"
#include "gather_oc/ros_conversions.hpp"

namespace gather {
namespace {

constexpr double kRefreshEvery = 5.0;  // [s] of mission time: goals and paths again (for late subscribers, bag seeks)

}  // namespace

MissionPublisher::MissionPublisher(ros::NodeHandle& nh, const agent::TeamSetup& team, const OccupancyGrid& map,
                                   const PublisherOptions& options)
    : team_(team), map_(map), options_(options), style_(map), view_(team, style_, options.frame) {
  view_.show_robots(options.robots);
  if (options_.sim_time) clock_ = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  if (options_.publish_map) map_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
  plan_ = nh.advertise<visualization_msgs::MarkerArray>("gather/plan_markers", 1, true);
  team_markers_ = nh.advertise<visualization_msgs::MarkerArray>("gather/team_markers", 1, true);
  goals_ = nh.advertise<visualization_msgs::MarkerArray>("gather/goal_markers", 1, true);
  paths_ = nh.advertise<visualization_msgs::MarkerArray>("gather/path_markers", 1, true);
  tf_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
  agents_ = nh.advertise<gather_msgs::AgentStates>("gather/agents", 10, true);
  status_ = nh.advertise<gather_msgs::MissionStatus>("gather/status", 10, true);
  cycles_ = nh.advertise<gather_msgs::CycleStats>("gather/cycle", 100, true);
  for (int a = 0; a < team.agents(); ++a)
    poses_.push_back(nh.advertise<geometry_msgs::PoseStamped>("gather/agent_" + std::to_string(a) + "/pose", 10));
}

ros::Time MissionPublisher::stamp(double t) const {
  return options_.sim_time ? ros::Time(std::max(0.0, t)) : ros::Time::now();
}

void MissionPublisher::before_start(agent::LockstepMaster& master) {
  const ros::Time now = stamp(0.0);
  const std::vector<agent::Reply>& agents = master.agents();
  if (options_.sim_time) {
    rosgraph_msgs::Clock c;
    c.clock = now;
    clock_.publish(c);
  }
  if (options_.publish_map) map_pub_.publish(to_map_msg(map_, options_.frame, now));
  // No DELETEALL first: with one in these arrays RViz 1.14 (llvmpipe)
  // crashed in 2 of 6 test sessions, in none of 12 without. A new run's
  // markers replace an earlier run's by id.
  plan_.publish(view::plan_markers(team_, style_, options_.frame, now));
  const gather_msgs::MissionStatus status = view_.status(master.oc(), "waiting", 0.0, 0.0, now);
  visualization_msgs::MarkerArray team = view_.team_markers(agents, 0.0, false, now);
  team.markers.push_back(view_.status_text(status));
  team_markers_.publish(team);
  tf_.publish(view_.transforms(agents, now));
  status_.publish(status);
}

void MissionPublisher::views(agent::LockstepMaster& master, double t, double rate, const std::string& state) {
  const ros::Time now = stamp(t);
  const std::vector<agent::Reply>& agents = master.agents();
  const agent::OcRole& oc = master.oc();
  master.take_events(events_);
  view_.take(events_, oc);
  const gather_msgs::MissionStatus status = view_.status(oc, state, t, rate, now);
  visualization_msgs::MarkerArray team = view_.team_markers(agents, t, true, now, &oc);
  team.markers.push_back(view_.status_text(status));
  team_markers_.publish(team);
  // Goals: when one was measured or resolved, and every few seconds for
  // late subscribers and replays that start in the middle.
  if (!events_.measured.empty() || oc.resolved_count() != resolved_shown_ || state != "running" ||
      t - last_goals_ >= kRefreshEvery) {
    goals_.publish(view_.goal_markers(oc, now));
    resolved_shown_ = oc.resolved_count();
    last_goals_ = t;
  }
  if (view_.paths_changed(agents) || t - last_paths_ >= kRefreshEvery) {
    paths_.publish(view_.path_markers(agents, now));
    last_paths_ = t;
  }
  if (now != last_tf_) {  // the same stamp twice makes TF listeners complain
    const tf2_msgs::TFMessage tf = view_.transforms(agents, now);
    tf_.publish(tf);
    for (std::size_t a = 0; a < tf.transforms.size() && a < poses_.size(); ++a) {
      geometry_msgs::PoseStamped p;
      p.header = tf.transforms[a].header;
      p.pose.position.x = tf.transforms[a].transform.translation.x;
      p.pose.position.y = tf.transforms[a].transform.translation.y;
      p.pose.orientation = tf.transforms[a].transform.rotation;
      poses_[a].publish(p);
    }
    last_tf_ = now;
  }
  if (t >= next_state_ || state != "running") {
    agents_.publish(view_.agent_states(agents, oc, now));
    status_.publish(status);
    next_state_ = t + options_.state_period;
  }
  for (const gather_msgs::CycleStats& c : view_.resolved_cycles(oc, now)) cycles_.publish(c);
}

void MissionPublisher::after_tick(agent::LockstepMaster& master, double rate) {
  const double t = master.last_tick_time();
  if (options_.sim_time) {
    rosgraph_msgs::Clock c;
    c.clock = stamp(t);
    clock_.publish(c);
  }
  if (t + 1e-9 < next_view_) return;
  views(master, t, rate, "running");
  next_view_ = t + options_.view_period;
}

void MissionPublisher::finish(agent::LockstepMaster& master, const std::string& state, double rate) {
  views(master, master.last_tick_time(), rate, state);
}

}  // namespace gather
