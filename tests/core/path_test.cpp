#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "gather_core/fmm/path.hpp"
#include "gather_core/grid/clearance.hpp"
#include "gather_core/path/path_polisher.hpp"

namespace gather {
namespace {

OccupancyGrid random_grid(int w, int h, double fill, unsigned seed, double res = 0.1) {
  std::mt19937 rng(seed);
  std::vector<int8_t> v(static_cast<std::size_t>(w) * h, 0);
  std::vector<uint8_t> f(v.size(), 1);
  for (std::size_t i = 0; i < v.size(); ++i)
    if (std::uniform_real_distribution<>(0, 1)(rng) < fill) v[i] = 100, f[i] = 0;
  return OccupancyGrid(w, h, res, Point2{1.0, -1.0}, v, f);
}

// Distance [cells] from cell centre to the nearest blocked centre, the ring of
// cells around the map counting as blocked.
double brute_clearance(const OccupancyGrid& g, Cell c) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = -1; r <= g.height(); ++r)
    for (int k = -1; k <= g.width(); ++k) {
      const bool blocked = !g.contains(Cell{r, k}) || !g.is_free(Cell{r, k});
      if (blocked) best = std::min(best, std::hypot(r - c.row, k - c.col));
    }
  return best;
}

TEST(Clearance, ExactEuclideanDistanceTransform) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const OccupancyGrid g = random_grid(37, 23, seed == 3 ? 0.0 : 0.05, seed);
    const ClearanceMap cm(g);
    for (int r = 0; r < g.height(); ++r)
      for (int c = 0; c < g.width(); ++c) {
        const double want = g.is_free(Cell{r, c}) ? brute_clearance(g, Cell{r, c}) * g.resolution() : 0.0;
        ASSERT_NEAR(cm.at(Cell{r, c}), want, 1e-5) << "cell " << r << "," << c;
      }
  }
}

TEST(Clearance, FreeDistanceIsALowerBoundOfTheDistanceToBlockedSquares) {
  const OccupancyGrid g = random_grid(30, 30, 0.04, 9);
  const ClearanceMap cm(g);
  std::mt19937 rng(4);
  std::uniform_real_distribution<> ux(1.0, 4.0), uy(-1.0, 2.0);
  for (int t = 0; t < 2000; ++t) {
    const Point2 p{ux(rng), uy(rng)};
    double exact = std::numeric_limits<double>::infinity();
    for (int r = -1; r <= g.height(); ++r)
      for (int c = -1; c <= g.width(); ++c) {
        if (g.contains(Cell{r, c}) && g.is_free(Cell{r, c})) continue;
        const double x0 = 1.0 + c * 0.1, y0 = -1.0 + r * 0.1;  // square [x0, x0+0.1] x [y0, y0+0.1]
        const double dx = std::max({x0 - p.x, 0.0, p.x - x0 - 0.1}), dy = std::max({y0 - p.y, 0.0, p.y - y0 - 0.1});
        exact = std::min(exact, std::hypot(dx, dy));
      }
    ASSERT_LE(cm.free_distance(p), exact + 1e-9);
    ASSERT_GE(cm.free_distance(p), exact - 0.15 - 1e-9);  // not uselessly loose either
  }
}

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
