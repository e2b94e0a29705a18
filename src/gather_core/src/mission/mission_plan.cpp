#include "gather_core/mission/mission_plan.hpp"

#include <opencv2/imgcodecs.hpp>

#include <filesystem>

#include "gather_core/error.hpp"

namespace gather {
namespace mission {

MissionPlan mission_plan(const plan::PlanContext& ctx, const plan::ConfigurationPlan& cfg, unsigned seed) {
  MissionPlan m;
  m.file = plan::make_plan_file(ctx, cfg, "", seed);
  m.width = cfg.partition.width;
  m.height = cfg.partition.height;
  m.labels = cfg.partition.labels;
  return m;
}

MissionPlan load_mission_plan(const std::string& plan_path) {
  namespace fs = std::filesystem;
  const fs::path yaml = fs::is_directory(plan_path) ? fs::path(plan_path) / "plan.yaml" : fs::path(plan_path);
  if (!fs::exists(yaml)) throw Error(yaml.string(), "no such plan file");
  MissionPlan m;
  m.file = plan::read_plan_file(yaml.string());
  const fs::path png = yaml.parent_path() / m.file.labels_png;
  if (!fs::is_regular_file(png)) throw Error(png.string(), "no such label image (named by " + yaml.string() + ")");
  const cv::Mat img = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
  if (img.empty()) throw Error(png.string(), "cannot read the label image");
  if (img.type() != CV_16UC1) throw Error(png.string(), "the label image must be a 16-bit single-channel PNG");
  m.width = img.cols;
  m.height = img.rows;
  m.labels.assign(static_cast<std::size_t>(m.width) * m.height, 0);
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c) {
      const int label = img.at<uint16_t>(m.height - 1 - r, c);
      if (label > m.file.workers)
        throw Error(png.string(), "label " + std::to_string(label) + " exceeds the plan's " +
                                      std::to_string(m.file.workers) + " workers");
      m.labels[static_cast<std::size_t>(r) * m.width + c] = label;
    }
  return m;
}

}  // namespace mission
}  // namespace gather
