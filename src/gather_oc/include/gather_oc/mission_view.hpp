#pragma once
// What changes during a mission, as ROS messages, built from the OC's
// ledger (agent::OcRole), the agents' last tick replies and the events the
// lockstep master observed (goals measured, custody hand-overs):
//   /gather/team_markers   agents by role (collector squares, worker discs in
//                          their collector's colour, workers of the OC black;
//                          orange before the mission starts, grey once the OC
//                          declared them dead) with their ids,
//                          radio links between agents in range (thin grey)
//                          and custody hand-overs of the last seconds (green);
//                          a status line above the map (time, request, goals)
//   /gather/goal_markers   goals of the newest two requests by state (pending
//                          orange, carried blue, delivered green, expired red,
//                          dropped purple), and every goal still carried
//   /gather/path_markers   each worker's planned path
//   /tf                    map -> agent_<k>/base_link (REP-105 names)
//   /gather/agent_<k>/pose geometry_msgs/PoseStamped
//   /gather/agents         gather_msgs/AgentStates
//   /gather/status         gather_msgs/MissionStatus
//   /gather/cycle          gather_msgs/CycleStats, once a cycle's goals are all resolved
// With the wall clock there are no tick replies: agents are where the OC's
// process last heard them, no goal shows as carried, no path is drawn.
#include <gather_msgs/AgentStates.h>
#include <gather_msgs/CycleStats.h>
#include <gather_msgs/MissionStatus.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "gather_agent/roles/oc_role.hpp"
#include "gather_agent/runner/lockstep.hpp"
#include "gather_oc/view_style.hpp"

namespace gather {
namespace view {

// The frame of agent `id`'s base (REP-105, one prefix per robot).
std::string agent_frame(int id);

class MissionView {
 public:
  MissionView(const agent::TeamSetup& team, const Style& style, std::string frame);
  // The team drives robots: team_markers() draws each robot's footprint
  // (the scenario's radius, to scale) and heading where it reports it is.
  void show_robots(bool on) { robots_ = on; }

  // Takes what the master observed since the last call (goal ids outside
  // the OC's ledger are ignored).
  void take(const agent::ViewEvents& events, const agent::OcRole& oc);

  visualization_msgs::MarkerArray team_markers(const std::vector<agent::Reply>& agents, double t, bool started,
                                               const ros::Time& stamp, const agent::OcRole* ledger = nullptr);
  visualization_msgs::MarkerArray goal_markers(const agent::OcRole& oc, const ros::Time& stamp) const;
  // True when some worker's planned path changed since the last path_markers().
  bool paths_changed(const std::vector<agent::Reply>& agents) const;
  visualization_msgs::MarkerArray path_markers(const std::vector<agent::Reply>& agents, const ros::Time& stamp);
  tf2_msgs::TFMessage transforms(const std::vector<agent::Reply>& agents, const ros::Time& stamp);
  gather_msgs::AgentStates agent_states(const std::vector<agent::Reply>& agents, const agent::OcRole& oc,
                                        const ros::Time& stamp) const;
  gather_msgs::MissionStatus status(const agent::OcRole& oc, const std::string& state, double t, double rate,
                                    const ros::Time& stamp);
  // One line above the map: mission time, the request, goals by state
  // (namespace "status" of /gather/team_markers).
  visualization_msgs::Marker status_text(const gather_msgs::MissionStatus& status) const;
  // Cycles whose goals have all been resolved since the last call, in order.
  std::vector<gather_msgs::CycleStats> resolved_cycles(const agent::OcRole& oc, const ros::Time& stamp);

  // The view's state of goal `id` (for tests): 0 pending, 1 carried, 2 delivered, 3 expired, 4 dropped,
  // 5 lost with an agent (final only at the mission's end: a survivor may
  // still resolve it).
  int goal_state(const agent::OcRole& oc, GoalId id) const;

 private:
  // Moves the cursor past the goals resolved since (goals resolve in no
  // particular order; the cursor stops at the first unresolved one), adding
  // them to the totals and to their cycle's row; a cycle whose goals are all
  // past the cursor is ready to report. Work per view: the goals not yet
  // resolved, the newest requests'.
  void settle(const agent::OcRole& oc);
  struct Totals {
    uint32_t requested = 0, delivered = 0, expired = 0, dropped = 0, lost = 0;
    double refresh_sum = 0.0, refresh_max = 0.0;
  };
  void add(Totals& t, const agent::OcRole& oc, std::size_t goal) const;

  const agent::TeamSetup& team_;
  Style style_;
  std::string frame_;
  bool robots_ = false;
  std::vector<uint8_t> measured_;                // by goal id: reported measured by its worker
  std::vector<agent::HandoverEvent> handovers_;  // recent ones
  PerAgent<uint32_t> shown_path_;                // path revision shown
  PerAgent<double> yaw_;                         // from its last motion
  PerAgent<Point2> last_pose_;
  Box box_;                  // where the team can be
  std::size_t settled_ = 0;  // goals [0, settled_) are all resolved
  bool over_ = false;        // the mission is over: lost goals are final
  Totals settled_totals_;    // of those
  int row_cycle_ = -1;       // the cycle being added up
  Totals row_;               // its goals so far
  double row_requested_at_ = 0.0;
  std::vector<gather_msgs::CycleStats> ready_;  // rows of cycles resolved, not yet taken
};

}  // namespace view
}  // namespace gather
