#include "gather_oc/mission_publisher.hpp"

#include <rosbag/bag.h>

#include "gather_oc/plan_markers.hpp"
#include "gather_oc/ros_conversions.hpp"

namespace gather {
namespace {

constexpr double kRefreshEvery = 5.0;  // [s] of mission time: goals and paths again (for late subscribers, bag seeks)

}  // namespace

template <class M>
Outlet<M>::Outlet(ros::NodeHandle* nh, rosbag::Bag* bag, const std::string& topic, int queue, bool latch) : bag_(bag) {
  if (!bag) {
    pub_ = nh->advertise<M>(topic, queue, latch);
    return;
  }
  topic_ = topic.front() == '/' ? topic : "/" + topic;  // as the root namespace resolves it
  header_ = boost::make_shared<ros::M_string>();
  (*header_)["type"] = ros::message_traits::datatype<M>();
  (*header_)["md5sum"] = ros::message_traits::md5sum<M>();
  (*header_)["message_definition"] = ros::message_traits::definition<M>();
  (*header_)["callerid"] = "/oc";
  if (latch) (*header_)["latching"] = "1";
}

template <class M>
void Outlet<M>::put(const M& msg, const ros::Time& t) {
  if (bag_)
    bag_->write(topic_, std::max(t, ros::TIME_MIN), msg, header_);
  else
    pub_.publish(msg);
}

MissionPublisher::MissionPublisher(ros::NodeHandle& nh, const agent::TeamSetup& team, const OccupancyGrid& map,
                                   const PublisherOptions& options)
    : MissionPublisher(&nh, nullptr, team, map, options) {}

MissionPublisher::MissionPublisher(rosbag::Bag& bag, const agent::TeamSetup& team, const OccupancyGrid& map,
                                   const PublisherOptions& options)
    : MissionPublisher(nullptr, &bag, team, map, [&] {
        PublisherOptions o = options;
        o.sim_time = true;
        return o;
      }()) {}

MissionPublisher::MissionPublisher(ros::NodeHandle* nh, rosbag::Bag* bag, const agent::TeamSetup& team,
                                   const OccupancyGrid& map, const PublisherOptions& options)
    : team_(team), map_(map), options_(options), style_(map), view_(team, style_, options.frame) {
  view_.show_robots(options.robots);
  if (options_.sim_time) clock_ = {nh, bag, "/clock", 10, false};
  if (options_.publish_map) map_pub_ = {nh, bag, "map", 1, true};
  plan_ = {nh, bag, "gather/plan_markers", 1, true};
  team_markers_ = {nh, bag, "gather/team_markers", 1, true};
  goals_ = {nh, bag, "gather/goal_markers", 1, true};
  paths_ = {nh, bag, "gather/path_markers", 1, true};
  tf_ = {nh, bag, "/tf", 100, false};
  agents_ = {nh, bag, "gather/agents", 10, true};
  status_ = {nh, bag, "gather/status", 10, true};
  cycles_ = {nh, bag, "gather/cycle", 100, true};
  for (int a = 0; a < team.agents(); ++a)
    poses_.push_back({nh, bag, "gather/agent_" + std::to_string(a) + "/pose", 10, false});
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
    clock_.put(c, c.clock);
  }
  if (options_.publish_map) map_pub_.put(to_map_msg(map_, options_.frame, now), now);
  // No DELETEALL first: with one in these arrays RViz 1.14 (llvmpipe)
  // crashed in 2 of 6 test sessions, in none of 12 without. A new run's
  // markers replace an earlier run's by id.
  plan_.put(view::plan_markers(team_, style_, options_.frame, now), now);
  const gather_msgs::MissionStatus status = view_.status(master.oc(), "waiting", 0.0, 0.0, now);
  visualization_msgs::MarkerArray team = view_.team_markers(agents, 0.0, false, now);
  team.markers.push_back(view_.status_text(status));
  team_markers_.put(team, now);
  tf_.put(view_.transforms(agents, now), now);
  status_.put(status, now);
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
  team_markers_.put(team, now);
  // Goals: when one was measured or resolved, and every few seconds for
  // late subscribers and replays that start in the middle.
  if (!events_.measured.empty() || oc.resolved_count() != resolved_shown_ || state != "running" ||
      t - last_goals_ >= kRefreshEvery) {
    goals_.put(view_.goal_markers(oc, now), now);
    resolved_shown_ = oc.resolved_count();
    last_goals_ = t;
  }
  if (view_.paths_changed(agents) || t - last_paths_ >= kRefreshEvery) {
    paths_.put(view_.path_markers(agents, now), now);
    last_paths_ = t;
  }
  if (now != last_tf_) {  // the same stamp twice makes TF listeners complain
    const tf2_msgs::TFMessage tf = view_.transforms(agents, now);
    tf_.put(tf, now);
    for (std::size_t a = 0; a < tf.transforms.size() && a < poses_.size(); ++a) {
      geometry_msgs::PoseStamped p;
      p.header = tf.transforms[a].header;
      p.pose.position.x = tf.transforms[a].transform.translation.x;
      p.pose.position.y = tf.transforms[a].transform.translation.y;
      p.pose.orientation = tf.transforms[a].transform.rotation;
      poses_[a].put(p, now);
    }
    last_tf_ = now;
  }
  if (t >= next_state_ || state != "running") {
    agents_.put(view_.agent_states(agents, oc, now), now);
    status_.put(status, now);
    next_state_ = t + options_.state_period;
  }
  for (const gather_msgs::CycleStats& c : view_.resolved_cycles(oc, now)) cycles_.put(c, now);
}

void MissionPublisher::after_tick(agent::LockstepMaster& master, double rate) {
  const double t = master.last_tick_time();
  if (options_.sim_time) {
    rosgraph_msgs::Clock c;
    c.clock = stamp(t);
    clock_.put(c, c.clock);
  }
  if (t + 1e-9 < next_view_) return;
  views(master, t, rate, "running");
  next_view_ = t + options_.view_period;
}

void MissionPublisher::finish(agent::LockstepMaster& master, const std::string& state, double rate) {
  views(master, master.last_tick_time(), rate, state);
}

}  // namespace gather
