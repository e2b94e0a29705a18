#include "gather_core/mission/mission_plan.hpp"

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

}  // namespace mission
}  // namespace gather
