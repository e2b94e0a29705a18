#include "gather_core/figures/plan_figures.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>

#include "gather_core/figures/partition_figure.hpp"
#include "map_canvas.hpp"
#include "plot.hpp"

namespace gather {
namespace figures {
namespace {

std::string fmt(const char* f, double v) {
  char b[96];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

cv::Vec3b blend(cv::Vec3b a, cv::Vec3b b, double t) {
  return cv::Vec3b(static_cast<uchar>(a[0] * (1 - t) + b[0] * t), static_cast<uchar>(a[1] * (1 - t) + b[1] * t),
                   static_cast<uchar>(a[2] * (1 - t) + b[2] * t));
}

cv::Vec3b to_vec(cv::Scalar s) {
  return cv::Vec3b(static_cast<uchar>(s[0]), static_cast<uchar>(s[1]), static_cast<uchar>(s[2]));
}

// Paints each reachable cell with colour_of(label), segment borders dark and
// the OC's coverage slightly darker (so it reads as an area).
template <typename ColourOf>
void paint_segments(MapCanvas& canvas, const LabelImage& labels, const Mask& coverage, ColourOf colour_of) {
  require_same_size(labels, canvas.grid().frame(), "plan figures", "the label image");
  require_same_size(coverage, canvas.grid().frame(), "plan figures", "the coverage");
  const int w = labels.width(), h = labels.height();
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      const int k = labels[i];
      if (k <= 0) continue;
      const bool border =
          (c + 1 < w && labels[i + 1] > 0 && labels[i + 1] != k) ||
          (r + 1 < h && labels[i + static_cast<std::size_t>(w)] > 0 && labels[i + static_cast<std::size_t>(w)] != k);
      cv::Vec3b col = colour_of(SegmentId(k));
      if (coverage[i]) col = blend(col, cv::Vec3b(90, 90, 90), 0.28);
      canvas.paint(Cell{r, c}, border ? cv::Vec3b(70, 70, 70) : col);
    }
}

std::string method_upper(partition::Method m) {
  std::string s = partition::method_name(m);
  for (auto& ch : s) ch = static_cast<char>(std::toupper(ch));
  return s;
}

}  // namespace

void write_plan_figures(const std::string& dir, const plan::PlanContext& ctx, const plan::ConfigurationPlan& cfg) {
  const OccupancyGrid& g = ctx.scenario.grid;
  const auto& labels = cfg.partition.labels;
  const auto& pal = fill_palette();
  const auto& lines = line_palette();
  const int dot = std::max(
      4, static_cast<int>(std::lround(0.3 / g.resolution() * std::min(1.0, 1600.0 / std::max(g.width(), g.height())))));
  const std::string what = method_upper(cfg.method) + ", " + std::to_string(cfg.workers) + " workers, " +
                           std::to_string(cfg.collectors) + " collectors";

  // (a) Worker graph.
  {
    const PerSegment<int> colour = colour_segments(labels, cfg.workers, static_cast<int>(pal.size()));
    MapCanvas canvas(g);
    paint_segments(canvas, labels, ctx.coverage, [&](SegmentId k) { return pal[static_cast<std::size_t>(colour[k])]; });
    int edges = 0;
    for (const auto& s : cfg.graph.segments)
      for (SegmentId m : s.neighbours)
        if (s.id < m) {
          canvas.polyline({s.centroid_m, cfg.graph.segment(m).centroid_m}, cv::Scalar(20, 20, 20), 2);
          ++edges;
        }
    for (const auto& s : cfg.graph.segments) {
      canvas.dot(s.centroid_m, cv::Scalar(255, 255, 255), dot);
      canvas.label(s.centroid_m, std::to_string(s.id.label()));
    }
    canvas.oc(ctx.scenario.oc);
    canvas.save(dir + "/fig2_graph.png",
                "(a) Worker graph: " + what + "; " + std::to_string(edges) + " edges = shared borders",
                {{LegendItem::kCircle, cv::Scalar(255, 255, 255), "segment centroid"},
                 {LegendItem::kLine, cv::Scalar(20, 20, 20), "adjacency"},
                 {LegendItem::kSquare, cv::Scalar(0, 0, 230), "OC"},
                 {LegendItem::kSquare, cv::Scalar(140, 140, 140), "OC coverage (darker)"}});
  }
  const cv::Vec3b direct_colour(205, 205, 205);
  auto group_fill = [&](SegmentId k) {
    const CollectorId c = cfg.collector_of_segment[k];
    return !c.valid() ? direct_colour : blend(to_vec(lines[c.index() % lines.size()]), cv::Vec3b(255, 255, 255), 0.55);
  };
  std::vector<LegendItem> group_legend;
  for (int c = 0; c < cfg.collectors; ++c) {
    const cv::Vec3b f =
        blend(to_vec(lines[static_cast<std::size_t>(c) % lines.size()]), cv::Vec3b(255, 255, 255), 0.55);
    group_legend.push_back({LegendItem::kSquare, cv::Scalar(f[0], f[1], f[2]), "collector " + std::to_string(c + 1)});
  }
  group_legend.push_back(
      {LegendItem::kSquare, cv::Scalar(direct_colour[0], direct_colour[1], direct_colour[2]), "to the OC"});
  group_legend.push_back({LegendItem::kSquare, cv::Scalar(0, 0, 230), "OC"});

  // (b) Collector segments.
  {
    MapCanvas canvas(g);
    paint_segments(canvas, labels, ctx.coverage, group_fill);
    for (const auto& s : cfg.graph.segments) canvas.label(s.centroid_m, std::to_string(s.id.label()), 0.35);
    canvas.oc(ctx.scenario.oc);
    canvas.save(dir + "/fig2_collector_segments.png", "(b) Collector segments S_col: " + what, group_legend);
  }
  // (c) Associations: routes, meeting areas, who delivers to whom.
  {
    MapCanvas canvas(g);
    paint_segments(canvas, labels, ctx.coverage,
                   [&](SegmentId k) { return blend(group_fill(k), cv::Vec3b(255, 255, 255), 0.5); });
    for (const auto& s : cfg.graph.segments) {
      const CollectorId c = cfg.collector_of_segment[s.id];
      if (!c.valid()) {
        canvas.polyline({s.centroid_m, ctx.scenario.oc}, cv::Scalar(0, 0, 200), 1, true);
        continue;
      }
      const auto& r = cfg.routes[c];
      for (const auto& m : r.meetings)
        if (m.segment == s.id) canvas.polyline({s.centroid_m, m.point}, lines[c.index() % lines.size()], 1, true);
    }
    for (const auto& r : cfg.routes) {
      const cv::Scalar& col = lines[r.collector.index() % lines.size()];
      canvas.polyline(r.waypoints, col, 3);
      for (const auto& m : r.meetings) canvas.dot(m.point, col, dot);
    }
    for (const auto& s : cfg.graph.segments) canvas.dot(s.centroid_m, cv::Scalar(255, 255, 255), std::max(3, dot - 1));
    canvas.oc(ctx.scenario.oc);
    std::vector<LegendItem> legend;
    for (const auto& r : cfg.routes)
      legend.push_back({LegendItem::kLine, lines[r.collector.index() % lines.size()],
                        "route " + std::to_string(r.collector.value() + 1) + fmt(" (%.0f s)", r.period)});
    legend.push_back({LegendItem::kCircle, cv::Scalar(120, 120, 120), "meeting area"});
    legend.push_back({LegendItem::kCircle, cv::Scalar(255, 255, 255), "worker (centroid)"});
    legend.push_back({LegendItem::kLine, cv::Scalar(0, 0, 200), "delivers to OC (dashed)"});
    legend.push_back({LegendItem::kSquare, cv::Scalar(0, 0, 230), "OC"});
    canvas.save(dir + "/fig2_associations.png",
                "(c) Associations P_cw: " + what + fmt(", request period %.0f s", ctx.cycle_period), legend);
  }
}

void write_estimates_figure(const std::string& path, const plan::SweepResult& sweep,
                            const std::vector<std::string>& methods) {
  const cv::Scalar colours[] = {cv::Scalar(180, 90, 20), cv::Scalar(40, 150, 40), cv::Scalar(20, 110, 230)};
  std::vector<Series> refresh, interval, goals, utility;
  for (std::size_t mi = 0; mi < methods.size(); ++mi) {
    const partition::Method m = partition::parse_method(methods[mi]);
    Series base;
    base.name = "E-" + std::string(1, static_cast<char>(std::toupper(methods[mi][0]))) + " (" + method_upper(m) + ")";
    base.colour = colours[static_cast<std::size_t>(m) % 3];
    base.marker = static_cast<int>(mi % 3);
    Series r = base, iv = base, n = base, u = base;
    for (const auto& c : sweep.configs) {
      if (c.method != m) continue;
      r.x.push_back(c.collectors), r.y.push_back(c.estimates.refresh_s);
      iv.x.push_back(c.collectors), iv.y.push_back(c.estimates.interval_s);
      n.x.push_back(c.collectors), n.y.push_back(c.estimates.goals);
      u.x.push_back(c.collectors), u.y.push_back(c.utility);
    }
    refresh.push_back(r), interval.push_back(iv), goals.push_back(n), utility.push_back(u);
  }
  const cv::Size size(460, 380);
  cv::Mat a = line_chart("(a) Refresh: latency (estimated)", "collectors N_c", "latency [s]", refresh, size);
  cv::Mat a2 = line_chart("(a') Refresh: interval (estimated)", "collectors N_c", "interval [s]", interval, size);
  cv::Mat b = line_chart("(b) Delivered goals per cycle (estimated)", "collectors N_c", "N_goals", goals, size);
  cv::Mat c = line_chart("(c) Utility U (estimated)", "collectors N_c", "U", utility, size);
  cv::Mat out;
  cv::hconcat(std::vector<cv::Mat>{a, a2, b, c}, out);
  write_png(path, out);
}

}  // namespace figures
}  // namespace gather
