#include "gather_core/plan/plan_file.hpp"

#include <algorithm>

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

#include "gather_core/error.hpp"
#include "gather_core/input_file.hpp"
#include "gather_core/input_ranges.hpp"
#include "gather_core/yaml_fields.hpp"

namespace gather {
namespace plan {
namespace {

void point(YAML::Emitter& y, Point2 p) { y << YAML::Flow << YAML::BeginSeq << p.x << p.y << YAML::EndSeq; }

// The file names segments by their labels.
std::vector<int> labels_of(const std::vector<SegmentId>& segments) {
  std::vector<int> out;
  out.reserve(segments.size());
  for (SegmentId s : segments) out.push_back(s.label());
  return out;
}

Point2 read_point(const yaml::Fields& f, const std::string& key) {
  const std::vector<double> v = f.required<std::vector<double>>(key);
  if (v.size() != 2) throw Error(f.file(), "'" + f.name(key) + "' must be [x, y]");
  return Point2{v[0], v[1]};
}

// Each element of a YAML sequence as Fields, named "key[i]".
std::vector<yaml::Fields> items(const YAML::Node& root, const std::string& file, const std::string& key) {
  const YAML::Node seq = root[key];
  if (!seq.IsDefined() || !seq.IsSequence()) throw Error(file, "missing list '" + key + "'");
  std::vector<yaml::Fields> out;
  for (std::size_t i = 0; i < seq.size(); ++i) out.emplace_back(seq[i], file, key + "[" + std::to_string(i) + "]");
  return out;
}

}  // namespace

void write_plan_file(const std::string& path, const PlanFile& p) {
  YAML::Emitter y;
  y.SetDoublePrecision(9);
  y << YAML::BeginMap;
  y << YAML::Key << "format" << YAML::Value << PlanFile::kFormat;
  y << YAML::Key << "scenario" << YAML::Value << p.scenario;
  y << YAML::Key << "method" << YAML::Value << p.method;
  y << YAML::Key << "collectors" << YAML::Value << p.collectors;
  y << YAML::Key << "workers" << YAML::Value << p.workers;
  y << YAML::Key << "seed" << YAML::Value << p.seed;
  y << YAML::Key << "labels" << YAML::Value << p.labels_png;
  y << YAML::Key << "grid_factor" << YAML::Value << p.grid_factor;
  y << YAML::Key << "cycle_period_s" << YAML::Value << p.cycle_period_s;
  y << YAML::Key << "area_tile_m" << YAML::Value << p.area_tile_m;
  y << YAML::Key << "estimates" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "refresh_s"
    << YAML::Value << p.est_refresh_s << YAML::Key << "interval_s" << YAML::Value << p.est_interval_s << YAML::Key
    << "goals" << YAML::Value << p.est_goals << YAML::Key << "utility" << YAML::Value << p.utility << YAML::EndMap;
  y << YAML::Key << "agents" << YAML::Value << YAML::BeginSeq;
  for (const AgentAssignment& a : p.agents) {
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "id" << YAML::Value << a.id.value() << YAML::Key << "role"
      << YAML::Value << (a.collector ? "collector" : "worker") << YAML::Key << "segment" << YAML::Value
      << a.segment.label() << YAML::Key << "collector" << YAML::Value << a.delivers_to.value() << YAML::EndMap;
  }
  y << YAML::EndSeq;
  y << YAML::Key << "routes" << YAML::Value << YAML::BeginSeq;
  for (const CollectorRoute& r : p.routes) {
    y << YAML::BeginMap;
    y << YAML::Key << "collector" << YAML::Value << r.collector.value();
    y << YAML::Key << "segments" << YAML::Value << YAML::Flow << labels_of(r.segments);
    y << YAML::Key << "length_m" << YAML::Value << r.length;
    y << YAML::Key << "period_s" << YAML::Value << r.period;
    y << YAML::Key << "min_clearance_m" << YAML::Value << r.min_clearance;
    y << YAML::Key << "coverage_entries_m" << YAML::Value << YAML::Flow << r.coverage_entries;
    y << YAML::Key << "meetings" << YAML::Value << YAML::BeginSeq;
    for (const MeetingArea& m : r.meetings) {
      y << YAML::Flow << YAML::BeginMap << YAML::Key << "segment" << YAML::Value << m.segment.label() << YAML::Key
        << "point" << YAML::Value;
      point(y, m.point);
      y << YAML::Key << "at_m" << YAML::Value << m.arc_m << YAML::Key << "passes_m" << YAML::Value << YAML::Flow
        << m.passes << YAML::EndMap;
    }
    y << YAML::EndSeq;
    y << YAML::Key << "waypoints" << YAML::Value << YAML::BeginSeq;
    for (const Point2& w : r.waypoints) point(y, w);
    y << YAML::EndSeq << YAML::EndMap;
  }
  y << YAML::EndSeq;
  y << YAML::Key << "worker_estimates" << YAML::Value << YAML::BeginSeq;
  for (const WorkerEstimate& w : p.workers_est) {
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "segment" << YAML::Value << w.segment.label() << YAML::Key
      << "collector" << YAML::Value << w.collector.value() << YAML::Key << "expected_goals" << YAML::Value
      << w.expected_goals << YAML::Key << "delivered_goals" << YAML::Value << w.delivered_goals << YAML::Key << "tour_s"
      << YAML::Value << w.tour_s << YAML::Key << "refresh_s" << YAML::Value << w.refresh_s << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  std::error_code ec;
  const std::filesystem::path fp(path);
  if (fp.has_parent_path()) std::filesystem::create_directories(fp.parent_path(), ec);
  std::ofstream out(path);
  out << y.c_str() << "\n";
  if (!out) throw Error(path, "cannot write plan file");
}

PlanFile read_plan_file(const std::string& path) {
  const YAML::Node root = yaml::load_file(path);
  yaml::Fields f(root, path, "");
  f.allow({"format", "scenario", "method", "collectors", "workers", "seed", "labels", "grid_factor", "cycle_period_s",
           "area_tile_m", "estimates", "agents", "routes", "worker_estimates"});
  PlanFile p;
  const std::string format = f.required<std::string>("format");
  if (format != PlanFile::kFormat)
    throw Error(path, "format '" + quote_input(format) + "' is not " + PlanFile::kFormat);
  p.scenario = f.file_name("scenario");
  p.method = f.required<std::string>("method");
  if (p.method != "bap" && p.method != "pap" && p.method != "rap")
    throw Error(path, "'method' must be bap, pap or rap, got '" + quote_input(p.method, 40) + "'");
  p.collectors = f.required<int>("collectors");
  p.workers = f.required<int>("workers");
  p.seed = f.required<unsigned>("seed");
  p.labels_png = f.file_name("labels");
  p.grid_factor = f.optional<int>("grid_factor", 1);
  check_range(range::kGridFactor, p.grid_factor, path);
  p.cycle_period_s = f.required<double>("cycle_period_s");
  check_range(range::kCyclePeriod, p.cycle_period_s, path);
  p.area_tile_m = f.required<double>("area_tile_m");
  check_range(range::kAreaTile, p.area_tile_m, path);  // and at least a cell (mission::check_plan)
  const yaml::Fields est = f.section("estimates");
  est.allow({"refresh_s", "interval_s", "goals", "utility"});
  p.est_refresh_s = est.required<double>("refresh_s");
  p.est_interval_s = est.required<double>("interval_s");
  p.est_goals = est.required<double>("goals");
  p.utility = est.required<double>("utility");
  for (const yaml::Fields& a : items(root, path, "agents")) {
    a.allow({"id", "role", "segment", "collector"});
    AgentAssignment x;
    x.id = AgentId(a.required<int>("id"));
    const std::string role = a.required<std::string>("role");
    if (role != "collector" && role != "worker")
      throw Error(path, "'" + a.name("role") + "' must be collector or worker");
    x.collector = role == "collector";
    x.segment = SegmentId(a.required<int>("segment"));
    x.delivers_to = CollectorId(a.required<int>("collector"));
    p.agents.push_back(x);
  }
  const YAML::Node routes = root["routes"];
  for (const yaml::Fields& r : items(root, path, "routes")) {
    r.allow({"collector", "segments", "length_m", "period_s", "min_clearance_m", "coverage_entries_m", "meetings",
             "waypoints"});
    CollectorRoute x;
    x.collector = CollectorId(r.required<int>("collector"));
    for (int label : r.required<std::vector<int>>("segments")) x.segments.push_back(SegmentId(label));
    x.length = r.required<double>("length_m");
    x.period = r.required<double>("period_s");
    x.min_clearance = r.required<double>("min_clearance_m");
    x.coverage_entries = r.required<std::vector<double>>("coverage_entries_m");
    const YAML::Node node = routes[p.routes.size()];
    for (const yaml::Fields& m : items(node, path, "meetings")) {
      m.allow({"segment", "point", "at_m", "passes_m"});
      x.meetings.push_back(MeetingArea{SegmentId(m.required<int>("segment")), read_point(m, "point"),
                                       m.required<double>("at_m"), m.required<std::vector<double>>("passes_m")});
    }
    for (const auto& w : r.required<std::vector<std::vector<double>>>("waypoints")) {
      if (w.size() != 2) throw Error(path, "route waypoints must be [x, y]");
      x.waypoints.push_back(Point2{w[0], w[1]});
    }
    p.routes.push_back(x);
  }
  for (const yaml::Fields& w : items(root, path, "worker_estimates")) {
    w.allow({"segment", "collector", "expected_goals", "delivered_goals", "tour_s", "refresh_s"});
    WorkerEstimate x;
    x.segment = SegmentId(w.required<int>("segment"));
    x.collector = CollectorId(w.required<int>("collector"));
    x.expected_goals = w.required<double>("expected_goals");
    x.delivered_goals = w.required<double>("delivered_goals");
    x.tour_s = w.required<double>("tour_s");
    x.refresh_s = w.required<double>("refresh_s");
    p.workers_est.push_back(x);
  }
  if (static_cast<int>(p.agents.size()) != p.collectors + p.workers)
    throw Error(path, "lists " + std::to_string(p.agents.size()) +
                          " agents, expected collectors + workers = " + std::to_string(p.collectors + p.workers));
  if (static_cast<int>(p.routes.size()) != p.collectors)
    throw Error(path, "lists " + std::to_string(p.routes.size()) + " routes for " + std::to_string(p.collectors) +
                          " collectors");
  // By id, whatever order the file lists them in (check_plan then makes sure
  // the ids are 0..N-1: agents[k] is agent k).
  std::stable_sort(p.agents.begin(), p.agents.end(),
                   [](const AgentAssignment& a, const AgentAssignment& b) { return a.id < b.id; });
  return p;
}

}  // namespace plan
}  // namespace gather
