#include "gather_core/mission/mission_plan.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "gather_core/error.hpp"
#include "gather_core/grid/map_image.hpp"

namespace gather {
namespace mission {

MissionPlan load_mission_plan(const std::string& plan_path) {
  namespace fs = std::filesystem;
  const fs::path yaml = fs::is_directory(plan_path) ? fs::path(plan_path) / "plan.yaml" : fs::path(plan_path);
  if (!fs::exists(yaml)) throw Error(yaml.string(), "no such plan file");
  MissionPlan m;
  m.source = yaml.string();
  m.file = plan::read_plan_file(yaml.string());
  const fs::path png = yaml.parent_path() / m.file.labels_png;
  if (!fs::is_regular_file(png)) throw Error(png.string(), "no such label image (named by " + yaml.string() + ")");
  const Gray16Image img = read_gray16_png(png.string());
  m.width = img.width;
  m.height = img.height;
  m.labels.assign(static_cast<std::size_t>(m.width) * m.height, 0);
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c) {
      const int label = img.pixels[static_cast<std::size_t>(m.height - 1 - r) * m.width + c];
      if (label > m.file.workers)
        throw Error(png.string(), "label " + std::to_string(label) + " exceeds the plan's " +
                                      std::to_string(m.file.workers) + " workers");
      m.labels[static_cast<std::size_t>(r) * m.width + c] = label;
    }
  return m;
}

void check_plan(const MissionPlan& p, int team) {
  const plan::PlanFile& pf = p.file;
  const std::string where = p.source.empty() ? "plan" : p.source;
  const int n = static_cast<int>(pf.agents.size());
  if (n != team) throw Error(where, "plans " + std::to_string(n) + " agents, the scenario's team has " + std::to_string(team));
  if (pf.collectors < 0 || pf.workers < 1 || pf.collectors + pf.workers != n)
    throw Error(where, "collectors (" + std::to_string(pf.collectors) + ") + workers (" + std::to_string(pf.workers) +
                           ") must be the " + std::to_string(n) + " agents");
  if (static_cast<int>(pf.routes.size()) != pf.collectors)
    throw Error(where, std::to_string(pf.routes.size()) + " routes for " + std::to_string(pf.collectors) + " collectors");
  if (!(pf.cycle_period_s > 0) || !std::isfinite(pf.cycle_period_s)) throw Error(where, "cycle_period_s must be > 0");
  std::vector<char> id_seen(static_cast<std::size_t>(n), 0), collector_seen(static_cast<std::size_t>(pf.collectors), 0),
      segment_seen(static_cast<std::size_t>(pf.workers) + 1, 0);
  for (const plan::AgentAssignment& a : pf.agents) {
    const std::string who = "agent " + std::to_string(a.id);
    if (a.id < 0 || a.id >= n || id_seen[static_cast<std::size_t>(a.id)])
      throw Error(where, who + ": ids must be 0.." + std::to_string(n - 1) + ", once each");
    id_seen[static_cast<std::size_t>(a.id)] = 1;
    if (a.collector) {
      if (a.delivers_to < 0 || a.delivers_to >= pf.collectors || collector_seen[static_cast<std::size_t>(a.delivers_to)])
        throw Error(where, who + ": collector index must be 0.." + std::to_string(pf.collectors - 1) + ", once each");
      collector_seen[static_cast<std::size_t>(a.delivers_to)] = 1;
      continue;
    }
    if (a.segment < 1 || a.segment > pf.workers || segment_seen[static_cast<std::size_t>(a.segment)])
      throw Error(where, who + ": segment must be 1.." + std::to_string(pf.workers) + ", one worker each");
    segment_seen[static_cast<std::size_t>(a.segment)] = 1;
    if (a.delivers_to < -1 || a.delivers_to >= pf.collectors)
      throw Error(where, who + ": collector must be -1 (the OC) or 0.." + std::to_string(pf.collectors - 1));
    if (a.delivers_to < 0) continue;
    const plan::CollectorRoute& r = pf.routes[static_cast<std::size_t>(a.delivers_to)];
    if (std::none_of(r.meetings.begin(), r.meetings.end(), [&](const plan::MeetingArea& m) { return m.segment == a.segment; }))
      throw Error(where, "collector " + std::to_string(a.delivers_to) + " has no meeting area for segment " +
                             std::to_string(a.segment) + " (" + who + ")");
  }
  for (std::size_t c = 0; c < pf.routes.size(); ++c) {
    const plan::CollectorRoute& r = pf.routes[c];
    for (const Point2& q : r.waypoints)
      if (!std::isfinite(q.x) || !std::isfinite(q.y))
        throw Error(where, "route of collector " + std::to_string(c) + ": a waypoint is not finite");
    for (const plan::MeetingArea& m : r.meetings) {
      if (!std::isfinite(m.route_s)) throw Error(where, "route of collector " + std::to_string(c) + ": a meeting area is not finite");
      for (double pass : m.passes)
        if (!std::isfinite(pass)) throw Error(where, "route of collector " + std::to_string(c) + ": a pass is not finite");
    }
  }
}

}  // namespace mission
}  // namespace gather
