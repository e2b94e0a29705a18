// figures/mission_figures: the mission video has every frame, reads back
// and shows the map; an unknown container is refused.
#include "gather_core/figures/mission_figures.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/plan/planner.hpp"
#include "small_office.hpp"

namespace gather {
namespace {

using mission::MissionOptions;
using mission::MissionResult;
using mission::MissionSimulator;

class MissionFiguresTest : public testing_support::SmallOfficeTest {};

TEST_F(MissionFiguresTest, VideoHasEveryFrameAndReadsBack) {
  const auto cfg = plan::plan_configuration(*ctx_, partition::Method::kPap, 2);
  MissionSimulator sim(*ctx_, mission::mission_plan(*ctx_, cfg));
  MissionOptions opt;
  opt.cycles = 2;
  const MissionResult r = sim.run(opt);
  const auto dir = std::filesystem::temp_directory_path() / ("gather_video_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "mission.avi").string();
  figures::write_mission_video(path, *ctx_, sim, r, 5.0, 12);
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);
  ASSERT_TRUE(cap.isOpened());
  int frames = 0;
  cv::Mat f, first;
  while (cap.read(f)) {
    if (frames == 0) first = f.clone();
    ++frames;
  }
  EXPECT_EQ(frames, 12);
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first.cols % 2, 0);
  EXPECT_EQ(first.rows % 2, 0);
  EXPECT_GT(first.cols, 600);
  // A real picture, not a blank frame: dark walls and light free space.
  double lo = 0, hi = 0;
  cv::minMaxLoc(first.reshape(1), &lo, &hi);
  EXPECT_LT(lo, 60);
  EXPECT_GT(hi, 200);
  EXPECT_THROW(figures::write_mission_video((dir / "mission.gif").string(), *ctx_, sim, r), Error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gather
