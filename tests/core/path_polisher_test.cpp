// path/path_polisher: OMPL shortcut and smoothing of a grid path that keeps
// the robot's clearance.
#include "gather_core/path/path_polisher.hpp"

#include <gtest/gtest.h>

#include <exception>
#include <vector>

#include "gather_core/fmm/path.hpp"
#include "gather_core/grid/clearance.hpp"

namespace gather {
namespace {

// L-shaped corridor 1.2 m wide, 0.1 m/cell.
OccupancyGrid l_corridor() {
  const int w = 100, h = 100;
  std::vector<int8_t> v(static_cast<std::size_t>(w) * h, 100);
  std::vector<uint8_t> f(v.size(), 0);
  auto open = [&](int r0, int r1, int c0, int c1) {
    for (int r = r0; r < r1; ++r)
      for (int c = c0; c < c1; ++c)
        v[static_cast<std::size_t>(r) * w + c] = 0, f[static_cast<std::size_t>(r) * w + c] = 1;
  };
  open(10, 22, 10, 90);  // horizontal leg
  open(10, 90, 78, 90);  // vertical leg
  return OccupancyGrid(w, h, 0.1, Point2{0, 0}, v, f);
}

TEST(PathPolisher, ShortensAStaircaseAndKeepsClearance) {
  const OccupancyGrid g = l_corridor();
  const ClearanceMap cm(g);
  // A 4-connected staircase hugging the inner corner, as a grid path would.
  std::vector<Point2> raw;
  for (int c = 20; c <= 84; ++c) raw.push_back(g.cell_center(Cell{16, c}));
  for (int r = 17; r <= 80; ++r) raw.push_back(g.cell_center(Cell{r, 84}));
  PolishOptions opt;
  opt.robot_radius = 0.3;
  const PolishedPath p = polish_path(raw, cm, opt);
  EXPECT_LT(p.points.size(), raw.size() / 5);
  EXPECT_LE(p.length, fmm::path_length(raw) + 1e-9);
  EXPECT_DOUBLE_EQ(p.points.front().x, raw.front().x);
  EXPECT_DOUBLE_EQ(p.points.back().y, raw.back().y);
  EXPECT_GE(p.min_clearance, 0.3);
  for (std::size_t i = 1; i < p.points.size(); ++i)
    for (double t = 0; t <= 1.0; t += 0.01) {
      const Point2 q{p.points[i - 1].x + t * (p.points[i].x - p.points[i - 1].x),
                     p.points[i - 1].y + t * (p.points[i].y - p.points[i - 1].y)};
      ASSERT_TRUE(cm.disc_free(q, 0.3 - 1e-9));
    }
  const PolishedPath again = polish_path(raw, cm, opt);
  ASSERT_EQ(again.points.size(), p.points.size());
  for (std::size_t i = 0; i < p.points.size(); ++i) EXPECT_EQ(again.points[i].x, p.points[i].x);
}

TEST(PathPolisher, KeepsAPathThatCannotHaveTheClearance) {
  const OccupancyGrid g = l_corridor();
  const ClearanceMap cm(g);
  const std::vector<Point2> raw{g.cell_center(Cell{11, 12}), g.cell_center(Cell{11, 40}), g.cell_center(Cell{11, 70})};
  PolishOptions opt;
  opt.robot_radius = 0.5;  // the path runs 0.1 m from the wall
  const PolishedPath p = polish_path(raw, cm, opt);
  EXPECT_LT(p.min_clearance, 0.5);
  EXPECT_DOUBLE_EQ(p.points.back().x, raw.back().x);
  EXPECT_THROW(polish_path({}, cm, opt), std::exception);
}

}  // namespace
}  // namespace gather
