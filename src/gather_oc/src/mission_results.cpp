#include "gather_oc/mission_results.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

#include "gather_core/error.hpp"

namespace gather {

MissionSummary summarize(const FleetMonitor& fleet, double duration_s) {
  MissionSummary s;
  s.duration_s = duration_s;
  s.agents_expected = static_cast<int>(fleet.agents().size());
  s.agents_heard = fleet.heard();
  s.rejected = fleet.rejected();
  for (const AgentRecord& a : fleet.agents()) {
    s.heartbeats += a.heartbeats;
    s.missed += a.missed;
  }
  return s;
}

void write_mission_results(const std::string& path, const Scenario& scenario, const FleetMonitor& fleet,
                           const MissionSummary& summary) {
  YAML::Emitter y;
  y.SetDoublePrecision(6);
  y << YAML::BeginMap;
  y << YAML::Key << "status" << YAML::Value << (summary.ok() ? "ok" : "incomplete");
  y << YAML::Key << "scenario" << YAML::Value << std::filesystem::weakly_canonical(scenario.path).string();
  y << YAML::Key << "duration_s" << YAML::Value << summary.duration_s;
  y << YAML::Key << "map" << YAML::Value << YAML::Flow << YAML::BeginMap;
  y << YAML::Key << "width" << YAML::Value << scenario.grid.width();
  y << YAML::Key << "height" << YAML::Value << scenario.grid.height();
  y << YAML::Key << "resolution" << YAML::Value << scenario.grid.resolution();
  y << YAML::EndMap;
  y << YAML::Key << "oc" << YAML::Value << YAML::Flow << YAML::BeginSeq << scenario.oc.x << scenario.oc.y << YAML::EndSeq;
  y << YAML::Key << "agents_expected" << YAML::Value << summary.agents_expected;
  y << YAML::Key << "agents_heard" << YAML::Value << summary.agents_heard;
  y << YAML::Key << "heartbeats" << YAML::Value << summary.heartbeats;
  y << YAML::Key << "missed" << YAML::Value << summary.missed;
  y << YAML::Key << "rejected" << YAML::Value << summary.rejected;
  y << YAML::Key << "agents" << YAML::Value << YAML::BeginSeq;
  for (std::size_t i = 0; i < fleet.agents().size(); ++i) {
    const AgentRecord& a = fleet.agents()[i];
    y << YAML::Flow << YAML::BeginMap;
    y << YAML::Key << "id" << YAML::Value << i;
    y << YAML::Key << "heard" << YAML::Value << a.heard;
    y << YAML::Key << "heartbeats" << YAML::Value << a.heartbeats;
    y << YAML::Key << "first_seq" << YAML::Value << a.first_seq;
    y << YAML::Key << "last_seq" << YAML::Value << a.last_seq;
    y << YAML::Key << "missed" << YAML::Value << a.missed;
    y << YAML::Key << "out_of_order" << YAML::Value << a.out_of_order;
    y << YAML::Key << "first_heard_s" << YAML::Value << a.first_heard_s;
    y << YAML::Key << "last_heard_s" << YAML::Value << a.last_heard_s;
    y << YAML::Key << "role" << YAML::Value << role_name(a.role);
    y << YAML::Key << "pose" << YAML::Value << YAML::Flow << YAML::BeginSeq << a.pose.x << a.pose.y << YAML::EndSeq;
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;

  const std::filesystem::path p(path);
  std::error_code ec;
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path(), ec);
  if (ec) throw Error(path, "cannot create directory: " + ec.message());
  std::ofstream out(path);
  out << y.c_str() << "\n";
  if (!out) throw Error(path, "cannot write results file");
}

}  // namespace gather
