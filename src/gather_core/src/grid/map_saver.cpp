#include "gather_core/grid/map_saver.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "gather_core/error.hpp"
#include "gather_core/yaml_fields.hpp"

namespace gather {

std::string save_map(const OccupancyGrid& grid, const std::string& base) {
  const std::string pgm = base + ".pgm";
  std::string yaml = base + ".yaml";
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::path(base).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  {
    std::ofstream out(pgm, std::ios::binary);
    out << "P5\n# gather map_saver: free 254, occupied 0, unknown 205\n"
        << grid.width() << " " << grid.height() << "\n255\n";
    std::string row(static_cast<std::size_t>(grid.width()), '\0');
    for (int r = grid.height() - 1; r >= 0; --r) {  // image row 0 = top of the map
      for (int c = 0; c < grid.width(); ++c) {
        const int8_t v = grid.value(Cell{r, c});
        row[static_cast<std::size_t>(c)] = static_cast<char>(v == 0 ? 254 : v >= 65 ? 0 : 205);
      }
      out.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
    if (!out) throw Error(pgm, "cannot write the map image");
  }
  YAML::Emitter y;
  y.SetDoublePrecision(17);
  y << YAML::BeginMap;
  y << YAML::Key << "image" << YAML::Value << std::filesystem::path(pgm).filename().string();
  y << YAML::Key << "resolution" << YAML::Value << grid.resolution();
  y << YAML::Key << "origin" << YAML::Value << YAML::Flow << YAML::BeginSeq << grid.origin().x << grid.origin().y << 0.0
    << YAML::EndSeq;
  y << YAML::Key << "negate" << YAML::Value << 0;
  y << YAML::Key << "occupied_thresh" << YAML::Value << 0.65;
  y << YAML::Key << "free_thresh" << YAML::Value << 0.196;
  y << YAML::Key << "mode" << YAML::Value << "trinary";
  y << YAML::EndMap;
  std::ofstream out(yaml);
  out << y.c_str() << "\n";
  if (!out) throw Error(yaml, "cannot write the map YAML");
  return yaml;
}

void write_scenario_with_map(const std::string& scenario, const std::string& map_yaml, const std::string& out) {
  YAML::Node root = yaml::load_file(scenario);
  root["map"] = map_yaml;
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::path(out).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  YAML::Emitter y;
  y.SetDoublePrecision(17);
  y << root;
  std::ofstream f(out);
  f << "# " << scenario << " with the map received from a ROS map topic\n" << y.c_str() << "\n";
  if (!f) throw Error(out, "cannot write the scenario");
}

}  // namespace gather
