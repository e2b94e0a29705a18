#include "gather_core/mission/mission_plan.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "gather_core/error.hpp"
#include "gather_core/grid/map_image.hpp"
#include "gather_core/input_ranges.hpp"
#include "gather_core/scenario/scenario.hpp"

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
  m.labels = LabelImage(GridFrame{img.width, img.height});
  for (int r = 0; r < img.height; ++r)
    for (int c = 0; c < img.width; ++c) {
      const int label = img.pixels[static_cast<std::size_t>(img.height - 1 - r) * img.width + c];
      if (label > m.file.workers)
        throw Error(png.string(), "label " + std::to_string(label) + " exceeds the plan's " +
                                      std::to_string(m.file.workers) + " workers");
      m.labels.at(Cell{r, c}) = label;
    }
  return m;
}

void check_plan(const MissionPlan& p, int team, const OccupancyGrid& grid) {
  const plan::PlanFile& pf = p.file;
  const std::string where = p.source.empty() ? "plan" : p.source;
  const int n = static_cast<int>(pf.agents.size());
  if (!p.labels.frame().same_size(grid.frame()))
    throw Error(where, "label image is " + p.labels.frame().size_text() + ", the scenario's planning grid " +
                           grid.frame().size_text());
  if (n != team)
    throw Error(where, "plans " + std::to_string(n) + " agents, the scenario's team has " + std::to_string(team));
  if (pf.collectors < 0 || pf.workers < 1 || pf.collectors + pf.workers != n)
    throw Error(where, "collectors (" + std::to_string(pf.collectors) + ") + workers (" + std::to_string(pf.workers) +
                           ") must be the " + std::to_string(n) + " agents");
  if (static_cast<int>(pf.routes.size()) != pf.collectors)
    throw Error(where,
                std::to_string(pf.routes.size()) + " routes for " + std::to_string(pf.collectors) + " collectors");
  check_range(range::kCyclePeriod, pf.cycle_period_s, where);
  check_range(range::kAreaTile, pf.area_tile_m, where);
  // A tile smaller than a cell of the planning grid counts each cell as an
  // area of its own (and below, the tile index overflows): at least a cell.
  if (pf.area_tile_m < grid.resolution()) {
    std::ostringstream s;
    s.precision(12);
    s << "area_tile_m = " << pf.area_tile_m << " must be in [" << grid.resolution() << ", "
      << input_range(range::kAreaTile).hi << "] m (at least a cell of the planning grid)";
    throw Error(where, s.str());
  }
  PerAgent<char> id_seen(n, 0);
  PerSegment<char> segment_seen(pf.workers, 0);
  for (AgentId k : ids<AgentId>(n)) {
    const plan::AgentAssignment& a = pf.agents[k];
    const std::string who = to_string(a.id);
    // (Listed by id below implies once each; this names the usual mistake.)
    if (!a.id.within(n) || id_seen[a.id])
      throw Error(where, who + ": ids must be 0.." + std::to_string(n - 1) + ", once each");
    id_seen[a.id] = 1;
    // Repairs and the roles index the table by id (read_plan_file sorts it so).
    if (a.id != k)
      throw Error(where, who + ": agents must be listed by id (it is entry " + std::to_string(k.value()) + ")");
    if (a.collector != (a.id.value() < pf.collectors))
      throw Error(where, who + ": agents 0.." + std::to_string(pf.collectors - 1) +
                             " must be the collectors, the others workers");
    if (a.collector) {
      // Collector k is agent k (the plan's convention; distinct as the ids are).
      if (a.delivers_to.value() != a.id.value()) throw Error(where, who + ": a collector's index must be its own id");
      continue;
    }
    if (!a.segment.within(pf.workers) || segment_seen[a.segment])
      throw Error(where, who + ": segment must be 1.." + std::to_string(pf.workers) + ", one worker each");
    segment_seen[a.segment] = 1;
    if (a.delivers_to.value() < -1 || a.delivers_to.value() >= pf.collectors)
      throw Error(where, who + ": collector must be -1 (the OC) or 0.." + std::to_string(pf.collectors - 1));
    if (!a.delivers_to.valid()) continue;
    const plan::CollectorRoute& r = pf.routes[a.delivers_to];
    if (std::none_of(r.meetings.begin(), r.meetings.end(),
                     [&](const plan::MeetingArea& m) { return m.segment == a.segment; }))
      throw Error(where,
                  to_string(a.delivers_to) + " has no meeting area for " + to_string(a.segment) + " (" + who + ")");
  }
  const double x0 = grid.origin().x - 1.0, y0 = grid.origin().y - 1.0;
  const double x1 = grid.origin().x + grid.width() * grid.resolution() + 1.0;
  const double y1 = grid.origin().y + grid.height() * grid.resolution() + 1.0;
  for (CollectorId c : ids<CollectorId>(pf.routes.count())) {
    const plan::CollectorRoute& r = pf.routes[c];
    const std::string route = "route of " + to_string(c);
    if (r.collector != c) throw Error(where, route + ": its collector index must be " + std::to_string(c.value()));
    double polyline = 0.0;
    for (std::size_t i = 0; i < r.waypoints.size(); ++i) {
      const Point2& q = r.waypoints[i];
      if (!(q.x >= x0 && q.x <= x1 && q.y >= y0 && q.y <= y1))
        throw Error(where, route + ": a waypoint is not finite or outside the map");
      if (i > 0) polyline += std::hypot(q.x - r.waypoints[i - 1].x, q.y - r.waypoints[i - 1].y);
    }
    const double most = polyline + 1e-3;  // arcs [m]: on the route (its length is recomputed from the waypoints)
    auto arc_ok = [&](double s) { return s >= 0.0 && s <= most; };
    if (!(r.length >= 0.0 && r.length <= most))
      throw Error(where, route + ": length_m is not finite or not the route's");
    for (double u : r.coverage_entries)
      if (!arc_ok(u)) throw Error(where, route + ": a coverage entry is not finite or off the route");
    for (SegmentId seg : r.segments)
      if (!seg.within(pf.workers)) throw Error(where, route + ": " + to_string(seg) + " does not exist");
    for (const plan::MeetingArea& m : r.meetings) {
      if (!m.segment.within(pf.workers))
        throw Error(where, route + ": a meeting area's " + to_string(m.segment) + " does not exist");
      if (!arc_ok(m.arc_m)) throw Error(where, route + ": a meeting area is not finite or off the route");
      for (double pass : m.passes)
        if (!arc_ok(pass)) throw Error(where, route + ": a pass is not finite or off the route");
    }
  }
}

PerCollector<AgentId> collector_agents(const plan::PlanFile& pf) {
  PerCollector<AgentId> out(pf.collectors);
  for (const plan::AgentAssignment& a : pf.agents)
    if (a.collector && a.delivers_to.within(out.count())) out[a.delivers_to] = a.id;
  return out;
}

}  // namespace mission
}  // namespace gather
