#include "gather_agent/runner/team.hpp"

#include <algorithm>
#include <string>

#include "gather_agent/motion/route_base.hpp"
#include "gather_agent/motion/simulated_base.hpp"
#include "gather_agent/roles/collector_role.hpp"
#include "gather_agent/roles/worker_role.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {

AgentUnit make_agent(TeamSetup& team, AgentId agent, const Point2* at, NavCommandSink* robot,
                     const RobotBaseParams& robot_params) {
  if (!agent.within(team.agents()))
    throw Error(team.plan.source.empty() ? "plan" : team.plan.source,
                to_string(agent) + " is not in the team of " + std::to_string(team.agents()));
  AgentUnit u;
  const Point2 start = at ? *at : team.start_pose(agent);
  if (robot)
    u.motion =
        std::make_unique<RobotBase>(team.world.scenario.grid, agent.value(), start, team.speed, *robot, robot_params);
  if (team.assignment(agent).collector) {
    const mission::RouteTimetable& route = team.routes[team.assignment(agent).delivers_to];
    // An idle route's collector stays at the OC: the ideal base is where its
    // timetable puts it (the route's one point), a robot where it is.
    const Point2 at_oc = route.idle() && !route.waypoints().empty() ? route.waypoints().front() : start;
    if (!robot)
      u.motion = std::make_unique<RouteBase>(route, at_oc, std::max<std::size_t>(1, route.waypoints().size()));
    u.role = std::make_unique<CollectorRole>(team, agent, *u.motion);
  } else {
    const std::size_t legs = static_cast<std::size_t>(team.params.goals_per_request) + 2;
    if (!robot)
      u.motion = std::make_unique<SimulatedBase>(team.world.scenario.grid, team.paths(), start, legs, team.speed,
                                                 &team.world.coverage_field, &team.world.coverage);
    u.role = std::make_unique<WorkerRole>(team, agent, *u.motion);
  }
  return u;
}

AgentUnit make_oc(TeamSetup& team) {
  AgentUnit u;
  u.motion = std::make_unique<Station>(team.world.scenario.oc);
  u.role = std::make_unique<OcRole>(team, *u.motion);
  return u;
}

std::vector<Revocation> revocations(const OcRole& oc) {
  std::vector<Revocation> out;
  for (std::size_t i = 0; i < oc.dead().size(); ++i) {
    const AgentId a(oc.dead()[i]);
    if (!((oc.revoked_mask() >> i) & 1u)) continue;
    out.push_back(Revocation{a.value(), oc.revoked_at(a), oc.refused_revoked(i), oc.discarded_of(a)});
  }
  std::sort(out.begin(), out.end(), [](const Revocation& x, const Revocation& y) { return x.agent < y.agent; });
  return out;
}

const Revocation* revocation_of(const std::vector<Revocation>& revoked, int agent) {
  for (const Revocation& r : revoked)
    if (r.agent == agent) return &r;
  return nullptr;
}

std::string describe(const Revocation& r) {
  return "agent " + std::to_string(r.agent) + "'s keys revoked at " + std::to_string(static_cast<int64_t>(r.at)) +
         " s: the OC dropped " + std::to_string(r.oc_refused) + " of its messages and refused " +
         std::to_string(r.oc_discarded) + " of its items from others; what it held is lost with it";
}

void count_measured(std::vector<uint8_t>& measured, int32_t goal) {
  if (goal >= 0 && static_cast<std::size_t>(goal) < measured.size() && measured[static_cast<std::size_t>(goal)] < 255)
    ++measured[static_cast<std::size_t>(goal)];
}

void check_conservation(const OcRole& oc, const std::vector<uint8_t>& measured, std::vector<int32_t>& custody,
                        double now) {
  std::sort(custody.begin(), custody.end());
  custody.erase(std::unique(custody.begin(), custody.end()), custody.end());
  auto delivered_goal = [&](GoalId goal) {
    return oc.resolved(goal) && oc.goals()[goal.index()].state == mission::GoalState::kDelivered;
  };
  auto carried_goal = [&](GoalId goal) { return std::binary_search(custody.begin(), custody.end(), goal.value()); };
  auto fail = [&](const GoalId goal, const std::string& what) {
    throw RuntimeError("conservation", "at t = " + std::to_string(now) + " s: " + to_string(goal) + " " + what);
  };
  // Carried: in someone's custody (a dead agent's too) and not delivered;
  // the OC may already have declared it lost with an agent.
  int64_t carried = 0, lost_carried = 0;
  for (int32_t key : custody) {
    const GoalId goal(key);  // a measured item's key is its goal
    if (!goal.within(static_cast<int>(oc.goals().size()))) continue;
    if (goal.index() >= measured.size() || measured[goal.index()] == 0)
      fail(goal, "is carried, but nobody measured it");
    if (delivered_goal(goal)) continue;
    ++carried;
    lost_carried += oc.resolved(goal) && oc.goals()[goal.index()].state == mission::GoalState::kLostWithAgent;
  }
  int64_t delivered = 0, expired = 0, dropped = 0, lost = 0;
  for (const mission::GoalRecord& g : oc.goals()) {
    const uint8_t times = g.id.index() < measured.size() ? measured[g.id.index()] : 0;
    // Each goal measured and stored is delivered, carried, or refused as a
    // revoked agent's (OcRole::of_revoked). A goal two workers measured (a
    // repair's new owner and the one it replaced, still at work until it
    // learned of the repair) needs one copy only: the other may be held
    // where it can go no more.
    const bool delivered_now = delivered_goal(g.id);
    if (times > 0 && !delivered_now && !carried_goal(g.id) && !oc.discarded(g.id))
      fail(g.id,
           "was measured " + std::to_string(times) + " time(s), but is neither delivered nor carried (data lost)");
    if (times == 0 && delivered_now) fail(g.id, "is delivered, but nobody measured it");
    if (!oc.resolved(g.id)) continue;
    delivered += g.state == mission::GoalState::kDelivered;
    expired += g.state == mission::GoalState::kExpired || g.state == mission::GoalState::kUnreachable;
    dropped += g.state == mission::GoalState::kDropped;
    lost += g.state == mission::GoalState::kLostWithAgent;
  }
  const int64_t requested = static_cast<int64_t>(oc.requested());
  const int64_t pending = requested - delivered - carried - expired - dropped - (lost - lost_carried);
  if (pending < 0)
    throw RuntimeError("conservation", "at t = " + std::to_string(now) + " s: requested " + std::to_string(requested) +
                                           " < delivered " + std::to_string(delivered) + " + carried " +
                                           std::to_string(carried) + " + expired " + std::to_string(expired) +
                                           " + dropped " + std::to_string(dropped) + " + lost with an agent " +
                                           std::to_string(lost - lost_carried));
}

}  // namespace agent
}  // namespace gather
