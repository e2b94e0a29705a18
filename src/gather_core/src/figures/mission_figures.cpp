#include "gather_core/figures/mission_figures.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>

#include "gather_core/error.hpp"
#include "gather_core/fmm/path.hpp"
#include "map_canvas.hpp"
#include "plot.hpp"
#include "video_sink.hpp"

namespace gather {
namespace figures {
namespace {

std::string upper(partition::Method m) {
  std::string s = partition::method_name(m);
  for (auto& ch : s) ch = static_cast<char>(std::toupper(ch));
  return s;
}

const cv::Scalar kMethodColours[] = {cv::Scalar(180, 90, 20), cv::Scalar(40, 150, 40), cv::Scalar(20, 110, 230)};

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

// The geodesic path of a leg, sampled: from -> to.
std::vector<Point2> leg_path(fmm::FastMarching& fm, const OccupancyGrid& grid, const mission::Leg& leg) {
  const Cell to = grid.world_to_cell(leg.to), from = grid.world_to_cell(leg.from);
  if (to == from) return {leg.from, leg.to};
  fmm::SolveOptions so;
  so.labels = false;
  so.targets = {from};
  fm.solve({fmm::Source::at_cell(to)}, so);
  if (!fm.reached(from)) return {leg.from, leg.to};
  return fmm::descend(fm, grid.cell_center(from));
}

// Route polyline of a collector between times t0 and t1, sampled every ~0.5 m;
// a span that holds a whole loop (its driving time and up to one request
// period `request_period` [s] of waiting at the OC) is the whole loop, so
// the points do not grow with the span (a fast team over the longest
// period drew gigabytes of points over the same loop).
std::vector<Point2> route_between(const mission::RouteTimetable& r, double t0, double t1, double speed,
                                  double request_period) {
  if (r.idle()) return {r.position(t0)};
  if (t1 - t0 >= r.period() + request_period) return r.waypoints();
  std::vector<Point2> pts;
  const double dt = 0.5 / speed;
  for (double t = t0; t < t1; t += dt) pts.push_back(r.position(t));
  pts.push_back(r.position(t1));
  return pts;
}

void paint_segments(MapCanvas& canvas, const plan::PlanContext& ctx, const mission::MissionPlan& plan) {
  const OccupancyGrid& g = ctx.scenario.grid;
  require_same_size(plan.labels, g.frame(), "mission figures", "the plan's label image");
  const auto& pal = fill_palette();
  for (std::size_t i = 0; i < plan.labels.size(); ++i) {
    const int k = plan.labels[i];
    if (k <= 0) continue;
    // Pale tints: the agents, goals and routes drawn on top must stand out.
    const cv::Vec3b& full = pal[static_cast<std::size_t>(k - 1) % pal.size()];
    cv::Vec3b c(static_cast<uchar>(full[0] * 0.4 + 255 * 0.6), static_cast<uchar>(full[1] * 0.4 + 255 * 0.6),
                static_cast<uchar>(full[2] * 0.4 + 255 * 0.6));
    if (ctx.coverage[i])
      c = cv::Vec3b(static_cast<uchar>(c[0] * 0.8), static_cast<uchar>(c[1] * 0.8), static_cast<uchar>(c[2] * 0.8));
    canvas.paint(g.cell(i), c);
  }
}

}  // namespace

std::vector<std::vector<double>> simulated_utilities(const std::vector<ConfigRuns>& runs, double alpha, double beta,
                                                     RefreshMetric m) {
  std::vector<std::vector<double>> u(runs.size());
  if (runs.empty()) return u;
  const double ab = alpha + beta > 0 ? alpha + beta : 1.0;
  std::size_t seeds = runs.front().refresh_s.size();
  for (const auto& r : runs) seeds = std::min(seeds, r.refresh_s.size());
  for (auto& x : u) x.assign(seeds, 0.0);
  for (std::size_t s = 0; s < seeds; ++s) {
    double tlo = 1e300, thi = -1e300, nlo = 1e300, nhi = -1e300;
    auto refresh = [&](const ConfigRuns& r) {
      return m == RefreshMetric::kInterval ? r.interval_s[s] : r.refresh_s[s];
    };
    for (const auto& r : runs) {
      tlo = std::min(tlo, refresh(r)), thi = std::max(thi, refresh(r));
      nlo = std::min(nlo, r.goals[s]), nhi = std::max(nhi, r.goals[s]);
    }
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const double tn = thi > tlo ? (refresh(runs[i]) - tlo) / (thi - tlo) : 0.0;
      const double nn = nhi > nlo ? (runs[i].goals[s] - nlo) / (nhi - nlo) : 0.0;
      u[i][s] = (alpha * (thi > tlo ? 1.0 - tn : 0.0) + beta * nn) / ab;
    }
  }
  return u;
}

void write_fig3(const std::string& dir, const std::vector<ConfigRuns>& runs, const std::vector<std::string>& methods,
                double alpha, double beta, RefreshMetric metric) {
  const auto util = simulated_utilities(runs, alpha, beta, metric);
  enum { kRefresh, kInterval, kGoals, kUtility };
  const char* files[] = {"fig3_refresh.png", "fig3_interval.png", "fig3_goals.png", "fig3_utility.png"};
  const std::string utility_title =
      std::string("(c) Utility U on the ") + refresh_metric_name(metric) + " refresh: E and R";
  const char* titles[] = {"(a) Refreshing time, latency: estimated E, real R (min-max over seeds)",
                          "(a') Refreshing time, interval between an area's deliveries: E and R",
                          "(b) Delivered goals per cycle: E and R", utility_title.c_str()};
  const char* ylabels[] = {"latency [s]", "interval [s]", "N_goals", "U"};
  for (int q = kRefresh; q <= kUtility; ++q) {
    std::vector<Series> series;
    for (std::size_t mi = 0; mi < methods.size(); ++mi) {
      const partition::Method m = partition::parse_method(methods[mi]);
      const std::string letter(1, static_cast<char>(std::toupper(methods[mi][0])));
      Series e, r;
      e.name = "E-" + letter + " (" + upper(m) + ")";
      r.name = "R-" + letter;
      e.colour = r.colour = kMethodColours[static_cast<std::size_t>(m) % 3];
      e.dashed = true;
      e.marker = r.marker = static_cast<int>(mi % 3);
      for (std::size_t i = 0; i < runs.size(); ++i) {
        const ConfigRuns& c = runs[i];
        if (c.method != m) continue;
        const std::vector<double>& v = q == kRefresh    ? c.refresh_s
                                       : q == kInterval ? c.interval_s
                                       : q == kGoals    ? c.goals
                                                        : util[i];
        if (v.empty()) continue;
        e.x.push_back(c.collectors), r.x.push_back(c.collectors);
        e.y.push_back(q == kRefresh    ? c.est_refresh_s
                      : q == kInterval ? c.est_interval_s
                      : q == kGoals    ? c.est_goals
                                       : c.est_utility);
        r.y.push_back(mean(v));
        r.band_lo.push_back(*std::min_element(v.begin(), v.end()));
        r.band_hi.push_back(*std::max_element(v.begin(), v.end()));
      }
      series.push_back(e), series.push_back(r);
    }
    write_png(dir + "/" + files[q], line_chart(titles[q], "collectors N_c", ylabels[q], series, cv::Size(640, 460)));
  }
}

void write_fig4_sync(const std::string& path, const plan::PlanContext& ctx, const mission::MissionSimulator& sim,
                     const mission::MissionResult& result, AgentId agent, double t0, double t1) {
  const OccupancyGrid& g = ctx.scenario.grid;
  const mission::MissionPlan& plan = sim.plan();
  CollectorId collector;
  SegmentId segment;
  for (const auto& a : plan.file.agents)
    if (a.id == agent && !a.collector) collector = a.delivers_to, segment = a.segment;
  MapCanvas canvas(g);
  for (std::size_t i = 0; i < plan.labels.size(); ++i)
    if (plan.labels[i] == segment.label()) canvas.paint(g.cell(i), cv::Vec3b(215, 235, 250));
  const cv::Scalar blue(200, 90, 20), red(30, 30, 210);
  fmm::FastMarching fm(g);
  const cv::Scalar window_colour(215, 205, 140), transfer_colour(60, 200, 60), rv_colour(120, 0, 120);
  const double v = ctx.scenario.team.speed;
  const mission::WorkerPolicy* policy = sim.worker(agent);
  if (collector.valid() && policy) {
    // Under the routes: where the collector is linked to each of the
    // worker's rendezvous points (the passes' link windows).
    const mission::RouteTimetable& route = sim.route(collector);
    for (std::size_t r = 0; r < policy->rendezvous().size(); ++r) {
      const auto [lo, hi] = policy->link_window(static_cast<int>(r));
      std::vector<Point2> stretch;
      for (double s = lo; s < hi; s += 0.25) stretch.push_back(route.position_at_arc(s));
      stretch.push_back(route.position_at_arc(hi));
      canvas.polyline(stretch, window_colour, 9);
    }
  }
  if (collector.valid()) canvas.polyline(route_between(sim.route(collector), t0, t1, v, ctx.cycle_period), red, 2);
  for (const mission::Leg& leg : result.legs) {
    if (leg.agent != agent || leg.t1 < t0 || leg.t0 > t1) continue;
    canvas.polyline(leg_path(fm, g, leg), blue, 2);
  }
  // Each hand-over: the collector's path while the link carried the batch
  // (transfer_s of its goals, ending at the pick-up), then its end.
  std::map<double, std::size_t> batches;  // picked_up_at -> goals
  for (const auto& goal : result.goals) {
    if (goal.measured_by != agent || goal.measured_at < t0 || goal.measured_at > t1) continue;
    canvas.dot(goal.point, cv::Scalar(0, 170, 255), 4);
    if (goal.picked_up_at >= 0) ++batches[goal.picked_up_at];
  }
  for (const auto& [at, n] : batches) {
    const double tau = transfer_s(ctx.scenario, n);
    if (tau > 0)
      canvas.polyline(route_between(sim.route(collector), at - tau, at, v, ctx.cycle_period), transfer_colour, 5);
    canvas.dot(sim.route(collector).position(at), transfer_colour, 5);
  }
  if (policy)
    for (std::size_t r = 0; r < policy->rendezvous().size(); ++r) {
      const cv::Point q = canvas.px(policy->rendezvous_point(static_cast<int>(r)));
      cv::drawMarker(canvas.image(), q, rv_colour, cv::MARKER_DIAMOND, 12, 2);
    }
  canvas.oc(ctx.scenario.oc);
  char caption[256];
  if (ctx.scenario.radio.bitrate_bps > 0)
    std::snprintf(caption, sizeof caption,
                  "Fig. 4a: worker %d (blue) and its collector %d (red), t = %.0f..%.0f s; a goal takes %.2f s of link",
                  agent.value(), collector.value(), t0, t1, transfer_s(ctx.scenario, 1));
  else
    std::snprintf(caption, sizeof caption,
                  "Fig. 4a: worker %d (blue) and its collector %d (red), t = %.0f..%.0f s; instant hand-over",
                  agent.value(), collector.value(), t0, t1);
  canvas.save(path, caption,
              {{LegendItem::kLine, blue, "worker"},
               {LegendItem::kLine, red, "collector"},
               {LegendItem::kLine, window_colour, "link window of a pass"},
               {LegendItem::kLine, transfer_colour, "transfer (collector's path)"},
               {LegendItem::kSquare, rv_colour, "rendezvous point"},
               {LegendItem::kCircle, cv::Scalar(0, 170, 255), "goal measured"},
               {LegendItem::kCircle, transfer_colour, "hand-over done"}});
}

namespace {

// Draws the mission at any time: the segments and routes are painted once,
// each frame copies them and adds goals, agents and the OC. Worker positions
// follow their legs' geodesic paths, each marched once and cached.
class MissionRenderer {
 public:
  MissionRenderer(const plan::PlanContext& ctx, const mission::MissionSimulator& sim,
                  const mission::MissionResult& result)
      : ctx_(ctx), sim_(sim), result_(result), base_(ctx.scenario.grid), fm_(ctx.scenario.grid) {
    const mission::MissionPlan& plan = sim.plan();
    paint_segments(base_, ctx, plan);
    for (const plan::CollectorRoute& r : plan.file.routes) base_.polyline(r.waypoints, colour(r.collector.value()), 2);
    for (std::size_t i = 0; i < result.legs.size(); ++i) legs_of_[result.legs[i].agent].push_back(i);
  }

  cv::Mat frame(double t) {
    MapCanvas canvas = base_;
    canvas.image() = base_.image().clone();
    const mission::MissionPlan& plan = sim_.plan();
    const int cycle =
        std::min(static_cast<int>(std::floor(t / result_.period_s)), static_cast<int>(result_.cycles.size()) - 1);
    for (const auto& goal : result_.goals) {
      if (goal.cycle != cycle) continue;
      cv::Scalar c = kPending;
      if (goal.measured_at >= 0 && goal.measured_at <= t) c = kCarried;
      if (goal.delivered_at >= 0 && goal.delivered_at <= t) c = kDelivered;
      if (goal.measured_at < 0 && goal.expired_at >= 0 && goal.expired_at <= t) continue;  // expired: gone
      canvas.dot(goal.point, c, 3);
    }
    for (const auto& a : plan.file.agents) {
      if (a.collector) {
        const cv::Point q = canvas.px(sim_.route(a.delivers_to).position(t));
        const int half = 6;
        cv::rectangle(canvas.image(), q - cv::Point(half, half), q + cv::Point(half, half),
                      colour(a.delivers_to.value()), cv::FILLED);
        cv::rectangle(canvas.image(), q - cv::Point(half, half), q + cv::Point(half, half), cv::Scalar(0, 0, 0), 1);
        continue;
      }
      canvas.dot(worker_at(a.id, t), a.delivers_to.valid() ? colour(a.delivers_to.value()) : cv::Scalar(0, 0, 0), 6);
    }
    canvas.oc(ctx_.scenario.oc);
    char caption[256];
    std::snprintf(caption, sizeof caption, "Fig. 4b: %s, %d collectors, %d workers at t = %.0f s (cycle %d)",
                  plan.file.method.c_str(), plan.file.collectors, plan.file.workers, t, cycle);
    return canvas.framed(caption, {{LegendItem::kSquare, colour(0), "collector"},
                                   {LegendItem::kCircle, colour(0), "its workers"},
                                   {LegendItem::kCircle, cv::Scalar(0, 0, 0), "OC worker"},
                                   {LegendItem::kCircle, kPending, "goal pending"},
                                   {LegendItem::kCircle, kCarried, "goal carried"},
                                   {LegendItem::kCircle, kDelivered, "goal delivered"},
                                   {LegendItem::kSquare, cv::Scalar(150, 150, 150), "OC radio coverage (shaded)"}});
  }

 private:
  static cv::Scalar colour(int collector) {
    const auto& lines = line_palette();
    return lines[static_cast<std::size_t>(collector) % lines.size()];
  }

  Point2 worker_at(AgentId agent, double t) {
    Point2 p = ctx_.scenario.grid.cell_center(ctx_.oc_cell);
    for (std::size_t i : legs_of_[agent]) {
      const mission::Leg& leg = result_.legs[i];
      if (leg.t0 > t) break;
      if (leg.t1 <= t) {
        p = leg.to;
        continue;
      }
      auto it = paths_.find(i);
      if (it == paths_.end()) {
        std::vector<Point2> path = leg_path(fm_, ctx_.scenario.grid, leg);
        std::vector<double> arcs = fmm::path_arcs(path);
        it = paths_.emplace(i, std::make_pair(std::move(path), std::move(arcs))).first;
      }
      const auto& [path, arcs] = it->second;
      const double f = leg.t1 > leg.t0 ? std::clamp((t - leg.t0) / (leg.t1 - leg.t0), 0.0, 1.0) : 1.0;
      p = fmm::point_at_arc(path, arcs, f * arcs.back());
    }
    return p;
  }

  const cv::Scalar kPending{150, 150, 150}, kCarried{0, 170, 255}, kDelivered{60, 190, 60};
  const plan::PlanContext& ctx_;
  const mission::MissionSimulator& sim_;
  const mission::MissionResult& result_;
  MapCanvas base_;
  fmm::FastMarching fm_;
  std::map<AgentId, std::vector<std::size_t>> legs_of_;                               // agent -> its legs in time order
  std::map<std::size_t, std::pair<std::vector<Point2>, std::vector<double>>> paths_;  // leg -> path, its arcs
};

}  // namespace

void write_fig4_snapshot(const std::string& path, const plan::PlanContext& ctx, const mission::MissionSimulator& sim,
                         const mission::MissionResult& result, double t) {
  MissionRenderer renderer(ctx, sim, result);
  write_png(path, renderer.frame(t));
}

void check_video_encoder(const std::string& path) { load_video_sink(path); }

void write_mission_video(const std::string& path, const plan::PlanContext& ctx, const mission::MissionSimulator& sim,
                         const mission::MissionResult& result, double fps, int frames) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  std::string codec;
  if (ext == ".mp4")
    codec = "mp4v";
  else if (ext == ".avi")
    codec = "MJPG";
  else
    throw Error(path, "video must be .mp4 or .avi, got '" + ext + "'");
  if (!(fps > 0) || frames < 2) throw Error(path, "video needs fps > 0 and at least 2 frames");
  const double end = std::max(result.end_s, result.mission_s);
  MissionRenderer renderer(ctx, sim, result);
  std::error_code ec;
  if (std::filesystem::path(path).has_parent_path())
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  const std::unique_ptr<VideoSink> writer = load_video_sink(path);
  cv::Size size;
  for (int i = 0; i < frames; ++i) {
    cv::Mat img = renderer.frame(end * i / (frames - 1));
    if (i == 0) {
      size = cv::Size(img.cols + img.cols % 2, img.rows + img.rows % 2);  // even sizes for the encoders
      if (!writer->open(path, codec, fps, size)) throw Error(path, "cannot write video (OpenCV/FFmpeg)");
    }
    cv::Mat even(size, img.type(), cv::Scalar(255, 255, 255));
    img(cv::Rect(0, 0, std::min(img.cols, size.width), std::min(img.rows, size.height)))
        .copyTo(even(cv::Rect(0, 0, std::min(img.cols, size.width), std::min(img.rows, size.height))));
    writer->write(even);
  }
  writer->release();
  if (!std::filesystem::exists(path) || std::filesystem::file_size(path) == 0) throw Error(path, "cannot write video");
}

}  // namespace figures
}  // namespace gather
