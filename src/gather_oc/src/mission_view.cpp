#include "gather_oc/mission_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gather_agent/roles/worker_role.hpp"
#include "gather_core/mission/simulator.hpp"

namespace gather {
namespace view {
namespace {

using visualization_msgs::Marker;

constexpr double kHandoverShown = 3.0;  // [s] of mission time a hand-over stays on screen

enum GoalView { kPending = 0, kCarried, kDelivered, kExpired, kDropped, kLost, kGoalViews };

}  // namespace

std::string agent_frame(int id) { return "agent_" + std::to_string(id) + "/base_link"; }

MissionView::MissionView(const agent::TeamSetup& team, const Style& style, std::string frame)
    : team_(team),
      style_(style),
      frame_(std::move(frame)),
      shown_path_(team.agents(), 0),
      yaw_(team.agents(), 0.0),
      last_pose_(team.agents()),
      box_(reachable_box(team.world.reachable)) {
  for (AgentId a : ids<AgentId>(team.agents())) last_pose_[a] = team.start_pose(a);
}

void MissionView::take(const agent::ViewEvents& events, const agent::OcRole& oc) {
  measured_.resize(oc.goals().size(), 0);
  for (const agent::MeasuredEvent& m : events.measured)
    if (m.goal >= 0 && static_cast<std::size_t>(m.goal) < measured_.size())
      measured_[static_cast<std::size_t>(m.goal)] = 1;
  handovers_.insert(handovers_.end(), events.handovers.begin(), events.handovers.end());
}

int MissionView::goal_state(const agent::OcRole& oc, GoalId id) const {
  const mission::GoalRecord& g = oc.goals()[id.index()];
  if (g.delivered_at >= 0) return kDelivered;
  if (g.dropped_at >= 0) return kDropped;
  if (g.expired_at >= 0) return kExpired;
  if (oc.resolved(id)) {
    switch (g.state) {
      case mission::GoalState::kDelivered: return kDelivered;
      case mission::GoalState::kDropped: return kDropped;
      case mission::GoalState::kLostWithAgent: return kLost;
      default: return kExpired;
    }
  }
  if (g.measured_at >= 0 || (id.index() < measured_.size() && measured_[id.index()])) return kCarried;
  return kPending;
}

visualization_msgs::MarkerArray MissionView::team_markers(const std::vector<agent::Reply>& agents, double t,
                                                          bool started, const ros::Time& stamp,
                                                          const agent::OcRole* ledger) {
  visualization_msgs::MarkerArray out;
  const double u = style_.unit;
  // Links: every pair in radio range, the OC included.
  Marker links = marker(frame_, stamp, "links", 0, Marker::LINE_LIST);
  links.scale.x = u * 0.08;
  links.color = style_.link;
  links.pose.position.z = kZLinks;
  const Point2 oc = team_.world.scenario.oc;
  for (std::size_t a = 0; a < agents.size(); ++a) {
    if (team_.linked(agents[a].pose, oc)) links.points.push_back(pt(agents[a].pose)), links.points.push_back(pt(oc));
    for (std::size_t b = a + 1; b < agents.size(); ++b)
      if (team_.linked(agents[a].pose, agents[b].pose))
        links.points.push_back(pt(agents[a].pose)), links.points.push_back(pt(agents[b].pose));
  }
  if (links.points.empty()) links.action = Marker::DELETE;
  out.markers.push_back(links);

  // Hand-overs of the last seconds, between where the two are now.
  handovers_.erase(std::remove_if(handovers_.begin(), handovers_.end(),
                                  [&](const agent::HandoverEvent& h) { return h.t < t - kHandoverShown || h.t > t; }),
                   handovers_.end());
  Marker hand = marker(frame_, stamp, "handovers", 0, Marker::LINE_LIST);
  hand.scale.x = u * 0.3;
  hand.color = style_.handover;
  hand.pose.position.z = kZLinks + 0.01;
  auto where = [&](int16_t id) {
    return id == agent::kOc || id < 0 || static_cast<std::size_t>(id) >= agents.size()
               ? oc
               : agents[static_cast<std::size_t>(id)].pose;
  };
  for (const agent::HandoverEvent& h : handovers_)
    hand.points.push_back(pt(where(h.from))), hand.points.push_back(pt(where(h.to)));
  if (hand.points.empty()) hand.action = Marker::DELETE;
  out.markers.push_back(hand);

  for (const agent::Reply& r : agents) {
    // As the OC runs the plan now (a dead collector's workers deliver to it).
    const AgentId agent(r.agent);
    const plan::AgentAssignment& as = ledger ? ledger->current_plan().file.agents[agent] : team_.assignment(agent);
    const bool collector = as.collector;
    Marker m = marker(frame_, stamp, "agents", r.agent, collector ? Marker::CUBE : Marker::CYLINDER);
    m.pose.position = pt(r.pose, kZAgents);
    m.scale.x = m.scale.y = u * (collector ? 1.1 : 1.0);
    m.scale.z = u * 0.3;
    const bool dead = ledger && ledger->declared_dead_at(agent) >= 0;
    m.color = !started                 ? style_.waiting
              : dead                   ? style_.dead
              : as.delivers_to.valid() ? style_.collector(as.delivers_to)
                                       : style_.oc_worker;
    out.markers.push_back(m);
    Marker id = marker(frame_, stamp, "agent_ids", r.agent, Marker::TEXT_VIEW_FACING);
    id.pose.position = pt(Point2{r.pose.x + u * 0.9, r.pose.y + u * 0.9}, kZLabels);
    id.scale.z = u * 1.1;
    id.color = style_.label;
    id.text = collector ? "C" + std::to_string(as.delivers_to.value()) + " (" + std::to_string(r.agent) + ")"
                        : std::to_string(r.agent);
    if (dead) id.text += ledger->revoked_at(agent) >= 0 ? " revoked" : " dead";
    out.markers.push_back(id);
    if (!robots_) continue;
    // The robot itself, to scale: its footprint and a line along its heading.
    // Above the agent's symbol (which is drawn larger than a robot, to be
    // seen on a whole map), in white to stand out on it.
    Marker f = marker(frame_, stamp, "footprints", r.agent, Marker::LINE_STRIP);
    f.pose.position.z = kZAgents + m.scale.z;
    f.scale.x = std::max(0.02, team_.world.scenario.team.radius * 0.2);
    f.color = style_.footprint;
    const double rad = team_.world.scenario.team.radius;
    for (int k = 0; k <= 24; ++k) {
      const double a = 2.0 * M_PI * k / 24;
      f.points.push_back(pt(Point2{r.pose.x + rad * std::cos(a), r.pose.y + rad * std::sin(a)}));
    }
    f.points.push_back(pt(r.pose));
    f.points.push_back(
        pt(Point2{r.pose.x + 1.8 * rad * std::cos(r.heading), r.pose.y + 1.8 * rad * std::sin(r.heading)}));
    out.markers.push_back(f);
  }
  return out;
}

visualization_msgs::MarkerArray MissionView::goal_markers(const agent::OcRole& oc, const ros::Time& stamp) const {
  static const char* const names[kGoalViews] = {"goals_pending", "goals_carried", "goals_delivered",
                                                "goals_expired", "goals_dropped", "goals_lost"};
  const std_msgs::ColorRGBA colours[kGoalViews] = {style_.goal_pending, style_.goal_carried, style_.goal_delivered,
                                                   style_.goal_expired, style_.goal_dropped, style_.goal_lost};
  visualization_msgs::MarkerArray out;
  std::vector<Marker> lists;
  for (int k = 0; k < kGoalViews; ++k) {
    Marker m = marker(frame_, stamp, names[k], 0, Marker::CUBE_LIST);
    m.scale.x = m.scale.y = style_.unit * (k == kPending ? 0.7 : 0.6);
    m.scale.z = 0.05;
    m.color = colours[k];
    m.pose.position.z = kZGoals + 0.002 * k;
    lists.push_back(m);
  }
  const int newest = oc.issued() - 1;
  const std::size_t n = oc.requested();
  // Goals before the cursor are resolved; of those only the newest two
  // requests' are shown.
  std::size_t first = std::min(settled_, n);
  while (first > 0 && oc.goals()[first - 1].cycle >= newest - 1) --first;
  for (std::size_t i = first; i < n; ++i) {
    const mission::GoalRecord& g = oc.goals()[i];
    const int s = goal_state(oc, GoalId::at_index(i));
    if (g.cycle < newest - 1 && s != kCarried) continue;
    lists[static_cast<std::size_t>(s)].points.push_back(pt(g.point));
  }
  for (Marker& m : lists) {
    if (m.points.empty()) m.action = Marker::DELETE;
    out.markers.push_back(m);
  }
  return out;
}

bool MissionView::paths_changed(const std::vector<agent::Reply>& agents) const {
  for (const agent::Reply& r : agents)
    if (r.path_revision != shown_path_[AgentId(r.agent)]) return true;
  return false;
}

visualization_msgs::MarkerArray MissionView::path_markers(const std::vector<agent::Reply>& agents,
                                                          const ros::Time& stamp) {
  visualization_msgs::MarkerArray out;
  for (const agent::Reply& r : agents) {
    shown_path_[AgentId(r.agent)] = r.path_revision;
    const plan::AgentAssignment& as = team_.assignment(AgentId(r.agent));
    if (as.collector) continue;  // its route is on /gather/plan_markers
    Marker m = marker(frame_, stamp, "paths", r.agent, Marker::LINE_STRIP);
    m.scale.x = style_.unit * 0.12;
    m.color = as.delivers_to.valid() ? style_.collector(as.delivers_to, 0.75f) : rgba(0.1f, 0.1f, 0.1f, 0.6f);
    m.pose.position.z = kZPaths;
    for (const Point2& p : r.path) m.points.push_back(pt(p));
    if (m.points.size() < 2) m.action = Marker::DELETE, m.points.clear();
    out.markers.push_back(m);
  }
  return out;
}

tf2_msgs::TFMessage MissionView::transforms(const std::vector<agent::Reply>& agents, const ros::Time& stamp) {
  tf2_msgs::TFMessage out;
  for (const agent::Reply& r : agents) {
    const AgentId a(r.agent);  // the lockstep master's last reply of each team agent
    const double dx = r.pose.x - last_pose_[a].x, dy = r.pose.y - last_pose_[a].y;
    if (robots_)
      yaw_[a] = r.heading;  // as the robot reports it
    else if (dx * dx + dy * dy > 1e-6)
      yaw_[a] = std::atan2(dy, dx);  // an ideal base: the way it moved
    last_pose_[a] = r.pose;
    out.transforms.push_back(planar_transform(frame_, agent_frame(r.agent), stamp, r.pose, yaw_[a]));
  }
  return out;
}

gather_msgs::AgentStates MissionView::agent_states(const std::vector<agent::Reply>& agents, const agent::OcRole& oc,
                                                   const ros::Time& stamp) const {
  gather_msgs::AgentStates out;
  out.header.frame_id = frame_;
  out.header.stamp = stamp;
  for (const agent::Reply& r : agents) {
    const plan::AgentAssignment& as = team_.assignment(AgentId(r.agent));
    gather_msgs::AgentState s;
    s.id = r.agent;
    s.role = as.collector ? gather_msgs::AgentState::COLLECTOR : gather_msgs::AgentState::WORKER;
    s.role_name = as.collector ? "collector" : "worker";
    s.collector = static_cast<int16_t>(
        !as.collector && as.delivers_to.valid() ? team_.collector_agent(as.delivers_to).value() : -1);
    s.phase = as.collector ? "route" : agent::WorkerRole::phase_name(r.phase);
    s.x = r.pose.x, s.y = r.pose.y;
    s.measured = static_cast<int32_t>(r.report.measured);
    s.carried = r.carried;
    s.pending = static_cast<int32_t>(r.report.pending);
    s.delivered = static_cast<int32_t>(oc.delivered_by(AgentId(r.agent)));
    s.expired = static_cast<int32_t>(r.report.expired);
    s.dropped = static_cast<int32_t>(r.report.dropped);
    s.sent = r.link.sent, s.received = r.link.received, s.gated = r.link.gated, s.lost = r.link.lost;
    out.agents.push_back(s);
  }
  return out;
}

void MissionView::add(Totals& t, const agent::OcRole& oc, std::size_t goal) const {
  ++t.requested;
  switch (goal_state(oc, GoalId::at_index(goal))) {
    case kDelivered: {
      const mission::GoalRecord& g = oc.goals()[goal];
      ++t.delivered;
      t.refresh_sum += g.delivered_at - g.requested_at;
      t.refresh_max = std::max(t.refresh_max, g.delivered_at - g.requested_at);
      break;
    }
    case kExpired: ++t.expired; break;
    case kDropped: ++t.dropped; break;
    case kLost: ++t.lost; break;
    default: break;
  }
}

void MissionView::settle(const agent::OcRole& oc) {
  const std::vector<mission::GoalRecord>& goals = oc.goals();
  auto flush = [&] {
    if (row_cycle_ < 0) return;
    gather_msgs::CycleStats m;
    m.cycle = static_cast<uint32_t>(row_cycle_);
    m.requested_at = row_requested_at_;
    m.requested = row_.requested;
    m.delivered = row_.delivered;
    m.expired = row_.expired;
    m.dropped = row_.dropped;
    m.refresh_mean = row_.delivered > 0 ? row_.refresh_sum / row_.delivered : 0.0;
    m.refresh_max = row_.refresh_max;
    m.total_requested = settled_totals_.requested;
    m.total_delivered = settled_totals_.delivered;
    m.total_refresh_mean =
        settled_totals_.delivered > 0 ? settled_totals_.refresh_sum / settled_totals_.delivered : 0.0;
    m.est_refresh = team_.plan.file.est_refresh_s;
    m.est_goals = team_.plan.file.est_goals;
    ready_.push_back(m);
    row_cycle_ = -1;
    row_ = Totals{};
  };
  const std::size_t n = oc.requested();
  // A goal declared lost with an agent may still be recovered by a
  // survivor: final only once the mission is over.
  while (settled_ < n && oc.resolved(GoalId::at_index(settled_)) &&
         (over_ || goals[settled_].state != mission::GoalState::kLostWithAgent)) {
    const mission::GoalRecord& g = goals[settled_];
    if (g.cycle != row_cycle_) {
      flush();  // the goals of a request are consecutive: the one before is complete
      row_cycle_ = g.cycle;
      row_requested_at_ = g.requested_at;
    }
    add(row_, oc, settled_);
    add(settled_totals_, oc, settled_);
    ++settled_;
  }
  if (settled_ == n && row_cycle_ >= 0 && row_cycle_ < oc.issued()) flush();  // every goal issued so far resolved
}

gather_msgs::MissionStatus MissionView::status(const agent::OcRole& oc, const std::string& state, double t, double rate,
                                               const ros::Time& stamp) {
  over_ = over_ || state == "done" || state == "failed";
  settle(oc);
  gather_msgs::MissionStatus s;
  s.header.frame_id = frame_;
  s.header.stamp = stamp;
  s.state = state;
  s.scenario = team_.world.scenario.path;
  s.plan = team_.plan.source;
  s.method = team_.plan.file.method;
  s.collectors = static_cast<uint16_t>(team_.plan.file.collectors);
  s.agents = static_cast<uint16_t>(team_.agents());
  s.time = t;
  s.period = team_.period;
  s.cycle = static_cast<uint32_t>(std::max(0, oc.issued() - 1));
  s.cycles = static_cast<uint32_t>(team_.params.cycles);
  s.requested = static_cast<uint32_t>(oc.requested());
  Totals open;  // the goals past the cursor
  for (std::size_t i = settled_; i < oc.requested(); ++i) {
    const int st = goal_state(oc, GoalId::at_index(i));
    if (st == kPending) ++s.pending;
    if (st == kCarried) ++s.carried;
    add(open, oc, i);
  }
  s.delivered = settled_totals_.delivered + open.delivered;
  s.expired = settled_totals_.expired + open.expired;
  s.dropped = settled_totals_.dropped + open.dropped;
  s.lost_with_agent = settled_totals_.lost + open.lost;
  s.dead = static_cast<uint16_t>(oc.dead().size());
  s.refresh_mean = s.delivered > 0 ? (settled_totals_.refresh_sum + open.refresh_sum) / s.delivered : 0.0;
  s.refresh_max = std::max(settled_totals_.refresh_max, open.refresh_max);
  s.rate = rate;
  return s;
}

visualization_msgs::Marker MissionView::status_text(const gather_msgs::MissionStatus& s) const {
  Marker m = marker(frame_, s.header.stamp, "status", 0, Marker::TEXT_VIEW_FACING);
  m.pose.position.x = (box_.x0 + box_.x1) / 2;
  m.pose.position.y = box_.y1 + style_.unit * 2.0;
  m.pose.position.z = kZLabels;
  m.scale.z = style_.unit * 1.6;
  m.color = rgba(0.95f, 0.95f, 0.95f);
  char text[256];
  std::snprintf(text, sizeof text,
                "t %.0f s | %s | request %u of %u | goals: %u pending, %u carried, %u delivered, %u expired", s.time,
                s.state.c_str(), s.requested > 0 ? s.cycle + 1 : 0, s.cycles, s.pending, s.carried, s.delivered,
                s.expired);
  m.text = text;
  if (s.dropped > 0) m.text += ", " + std::to_string(s.dropped) + " dropped";
  if (s.lost_with_agent > 0) m.text += ", " + std::to_string(s.lost_with_agent) + " lost with agent";
  if (s.dead > 0) m.text += " | " + std::to_string(s.dead) + " agent" + (s.dead > 1 ? "s" : "") + " dead";
  return m;
}

std::vector<gather_msgs::CycleStats> MissionView::resolved_cycles(const agent::OcRole& oc, const ros::Time& stamp) {
  settle(oc);
  std::vector<gather_msgs::CycleStats> out;
  out.swap(ready_);
  for (gather_msgs::CycleStats& c : out) c.header.stamp = stamp;
  return out;
}

}  // namespace view
}  // namespace gather
