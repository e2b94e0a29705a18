#include "gather_oc/plan_markers.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "gather_core/figures/palette.hpp"

namespace gather {
namespace view {
namespace {

using visualization_msgs::Marker;

// Label runs merged into rectangles: rows of equal runs (same columns and
// label) one above the other become one rectangle.
struct Rect {
  int row0, row1, col0, col1;  // inclusive
  int32_t label;
};

std::vector<Rect> label_rects(const LabelImage& labels) {
  const int width = labels.width(), height = labels.height();
  std::vector<Rect> done;
  std::map<std::pair<int, int>, Rect> open;  // by (col0, col1)
  for (int r = 0; r < height; ++r) {
    std::map<std::pair<int, int>, Rect> next;
    for (int c = 0; c < width;) {
      const int32_t l = labels[static_cast<std::size_t>(r) * width + c];
      int e = c;
      while (e + 1 < width && labels[static_cast<std::size_t>(r) * width + e + 1] == l) ++e;
      if (l > 0) {
        auto it = open.find({c, e});
        if (it != open.end() && it->second.label == l) {
          Rect rect = it->second;
          rect.row1 = r;
          next[{c, e}] = rect;
          open.erase(it);
        } else {
          next[{c, e}] = Rect{r, r, c, e, l};
        }
      }
      c = e + 1;
    }
    for (auto& kv : open) done.push_back(kv.second);
    open.swap(next);
  }
  for (auto& kv : open) done.push_back(kv.second);
  return done;
}

}  // namespace

Point2 point_at(const std::vector<Point2>& line, double s) {
  if (line.empty()) return Point2{};
  for (std::size_t i = 1; i < line.size(); ++i) {
    const double len = std::hypot(line[i].x - line[i - 1].x, line[i].y - line[i - 1].y);
    if (s <= len && len > 0) {
      const double f = std::max(0.0, s) / len;
      return Point2{line[i - 1].x + f * (line[i].x - line[i - 1].x), line[i - 1].y + f * (line[i].y - line[i - 1].y)};
    }
    s -= len;
  }
  return line.back();
}

visualization_msgs::MarkerArray plan_markers(const agent::TeamSetup& team, const Style& style, const std::string& frame,
                                             const ros::Time& stamp) {
  visualization_msgs::MarkerArray out;
  const OccupancyGrid& grid = team.world.scenario.grid;
  const mission::MissionPlan& plan = team.plan;
  const double res = grid.resolution();
  const Point2 o = grid.origin();

  // Segments, coloured so that neighbours differ.
  const int segments = plan.file.workers;
  const auto& palette = figures::segment_palette();
  const PerSegment<int> colour = figures::colour_segments(plan.labels, segments, static_cast<int>(palette.size()));
  Marker seg = marker(frame, stamp, "segments", 0, Marker::TRIANGLE_LIST);
  for (const Rect& r : label_rects(plan.labels)) {
    const double x0 = o.x + r.col0 * res, x1 = o.x + (r.col1 + 1) * res;
    const double y0 = o.y + r.row0 * res, y1 = o.y + (r.row1 + 1) * res;
    const std_msgs::ColorRGBA c =
        rgba(palette[static_cast<std::size_t>(colour[SegmentId(r.label)]) % palette.size()], 0.5f);
    for (const auto& p : {pt(x0, y0), pt(x1, y0), pt(x1, y1), pt(x0, y0), pt(x1, y1), pt(x0, y1)}) {
      seg.points.push_back(p);
      seg.colors.push_back(c);
    }
  }
  seg.pose.position.z = kZSegments;
  if (!seg.points.empty()) out.markers.push_back(seg);

  // Segment ids at the segment cell nearest its centroid.
  std::vector<double> sx(static_cast<std::size_t>(segments) + 1), sy(sx.size()), n(sx.size());
  for (int r = 0; r < plan.labels.height(); ++r)
    for (int c = 0; c < plan.labels.width(); ++c) {
      const int32_t l = plan.labels.at(Cell{r, c});
      if (l <= 0 || l > segments) continue;
      sx[static_cast<std::size_t>(l)] += c, sy[static_cast<std::size_t>(l)] += r, n[static_cast<std::size_t>(l)] += 1;
    }
  std::vector<double> best(sx.size(), 1e300);
  std::vector<Cell> at(sx.size());
  for (int r = 0; r < plan.labels.height(); ++r)
    for (int c = 0; c < plan.labels.width(); ++c) {
      const int32_t l = plan.labels.at(Cell{r, c});
      if (l <= 0 || l > segments) continue;
      const std::size_t k = static_cast<std::size_t>(l);
      const double d = std::pow(c - sx[k] / n[k], 2) + std::pow(r - sy[k] / n[k], 2);
      if (d < best[k]) best[k] = d, at[k] = Cell{r, c};
    }
  for (int k = 1; k <= segments; ++k) {
    if (n[static_cast<std::size_t>(k)] == 0) continue;
    Marker t = marker(frame, stamp, "segment_ids", k, Marker::TEXT_VIEW_FACING);
    const Point2 p = grid.cell_center(at[static_cast<std::size_t>(k)]);
    t.pose.position = pt(p.x, p.y, kZLabels);
    t.scale.z = style.unit * 1.1;
    t.color = rgba(0.25f, 0.25f, 0.3f, 0.9f);
    t.text = "S" + std::to_string(k);
    out.markers.push_back(t);
  }

  // The OC.
  const Point2 oc = team.world.scenario.oc;
  Marker ocm = marker(frame, stamp, "oc", 0, Marker::CUBE);
  ocm.pose.position = pt(oc.x, oc.y, kZAgents);
  ocm.scale.x = ocm.scale.y = style.unit * 1.4, ocm.scale.z = style.unit * 0.4;
  ocm.color = style.oc;
  out.markers.push_back(ocm);
  Marker oct = marker(frame, stamp, "oc", 1, Marker::TEXT_VIEW_FACING);
  oct.pose.position = pt(oc.x + style.unit * 1.5, oc.y + style.unit * 1.5, kZLabels);
  oct.scale.z = style.unit * 1.3;
  oct.color = style.oc;
  oct.text = "OC";
  out.markers.push_back(oct);

  // The coverage's outline: every edge between a covered and an uncovered cell.
  Marker cov = marker(frame, stamp, "coverage", 0, Marker::LINE_LIST);
  cov.scale.x = std::max(res, style.unit * 0.12);
  cov.color = rgba(0.85f, 0.1f, 0.1f, 0.85f);
  cov.pose.position.z = kZCoverage;
  const int w = grid.width(), h = grid.height();
  auto covered = [&](int r, int c) { return r >= 0 && c >= 0 && r < h && c < w && team.world.covered(Cell{r, c}); };
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      if (!covered(r, c)) continue;
      const double x0 = o.x + c * res, x1 = x0 + res, y0 = o.y + r * res, y1 = y0 + res;
      if (!covered(r, c - 1)) cov.points.push_back(pt(x0, y0)), cov.points.push_back(pt(x0, y1));
      if (!covered(r, c + 1)) cov.points.push_back(pt(x1, y0)), cov.points.push_back(pt(x1, y1));
      if (!covered(r - 1, c)) cov.points.push_back(pt(x0, y0)), cov.points.push_back(pt(x1, y0));
      if (!covered(r + 1, c)) cov.points.push_back(pt(x0, y1)), cov.points.push_back(pt(x1, y1));
    }
  if (!cov.points.empty()) out.markers.push_back(cov);

  // Routes, their ids and the meeting areas.
  for (const plan::CollectorRoute& route : plan.file.routes) {
    const std_msgs::ColorRGBA c = style.collector(route.collector);
    const int k = route.collector.value();  // marker ids
    Marker line = marker(frame, stamp, "routes", k, Marker::LINE_STRIP);
    line.scale.x = style.unit * 0.3;
    line.color = c;
    line.pose.position.z = kZRoutes;
    for (const Point2& p : route.waypoints) line.points.push_back(pt(p.x, p.y));
    if (line.points.size() >= 2) out.markers.push_back(line);

    Marker id = marker(frame, stamp, "route_ids", k, Marker::TEXT_VIEW_FACING);
    const Point2 mid = point_at(route.waypoints, route.length * 0.5);
    id.pose.position = pt(mid.x, mid.y + style.unit, kZLabels);
    id.scale.z = style.unit * 1.3;
    id.color = c;
    id.text = "C" + std::to_string(k);
    out.markers.push_back(id);

    for (const plan::MeetingArea& m : route.meetings) {
      Marker disc = marker(frame, stamp, "meetings", k * 10000 + m.segment.label(), Marker::CYLINDER);
      disc.pose.position = pt(m.point.x, m.point.y, kZMeetings);
      disc.scale.x = disc.scale.y = style.unit * 2.2, disc.scale.z = 0.02;
      disc.color = style.collector(route.collector, 0.35f);
      out.markers.push_back(disc);
      Marker passes = marker(frame, stamp, "meetings", 5000000 + k * 10000 + m.segment.label(), Marker::SPHERE_LIST);
      passes.scale.x = passes.scale.y = passes.scale.z = style.unit * 0.7;
      passes.color = style.collector(route.collector, 0.45f);
      passes.pose.position.z = kZMeetings;
      for (double s : m.passes) {
        const Point2 p = point_at(route.waypoints, s);
        passes.points.push_back(pt(p.x, p.y));
      }
      if (!passes.points.empty()) out.markers.push_back(passes);
    }
  }
  legend(out, style, reachable_box(team.world.reachable), frame, stamp);
  return out;
}

void legend(visualization_msgs::MarkerArray& out, const Style& style, const Box& below, const std::string& frame,
            const ros::Time& stamp) {
  struct Item {
    const char* text;
    int type;
    std_msgs::ColorRGBA colour;
  };
  const Item items[] = {
      {"goal pending", Marker::CUBE, style.goal_pending},
      {"carried", Marker::CUBE, style.goal_carried},
      {"delivered", Marker::CUBE, style.goal_delivered},
      {"expired", Marker::CUBE, style.goal_expired},
      {"lost with agent", Marker::CUBE, style.goal_lost},
      {"collector", Marker::CUBE, style.collector(CollectorId(0))},
      {"its worker", Marker::CYLINDER, style.collector(CollectorId(0))},
      {"OC worker", Marker::CYLINDER, style.oc_worker},
      {"radio link", Marker::LINE_LIST, style.link},
      {"hand-over", Marker::LINE_LIST, style.handover},
      {"coverage", Marker::LINE_LIST, style.oc},
      {"dead agent", Marker::CYLINDER, style.dead},
      {"laser hit", Marker::CUBE, style.laser},
  };
  const double u = style.unit, h = u * 1.1;  // text height
  double x = below.x0;
  double y = below.y0 - u * 1.8;
  int id = 0;
  for (const Item& it : items) {
    // A second row when this item would pass the box's right side.
    const double item_w = u * 1.6 + 0.62 * h * static_cast<double>(std::strlen(it.text));
    if (x > below.x0 && x + item_w > below.x1) x = below.x0, y -= u * 1.6;
    Marker sym = marker(frame, stamp, "legend", id++, it.type);
    sym.color = it.colour;
    sym.scale.x = sym.scale.y = u * 0.9, sym.scale.z = 0.05;
    sym.pose.position = pt(x + u * 0.5, y, kZLabels);
    if (it.type == Marker::LINE_LIST) {
      sym.pose.position = pt(0, 0, kZLabels);
      sym.scale.x = it.colour.a < 0.9f ? u * 0.12 : u * 0.3;
      sym.points = {pt(x, y), pt(x + u * 1.2, y)};
      sym.color.a = 1.0f;
    }
    out.markers.push_back(sym);
    Marker t = marker(frame, stamp, "legend", id++, Marker::TEXT_VIEW_FACING);
    const double w = 0.62 * h * static_cast<double>(std::strlen(it.text));  // about the text's width
    t.pose.position = pt(x + u * 1.6 + w / 2, y, kZLabels);
    t.scale.z = h;
    t.color = rgba(0.92f, 0.92f, 0.92f);
    t.text = it.text;
    out.markers.push_back(t);
    x += u * 1.6 + w + u * 1.4;
  }
}

}  // namespace view
}  // namespace gather
