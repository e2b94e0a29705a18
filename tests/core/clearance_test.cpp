// grid/clearance: the exact Euclidean distance transform and the free
// distance of a point, against brute force on random grids.
#include "gather_core/grid/clearance.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

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

TEST(Clearance, DiscFreeIsFreeDistanceAgainstTheRadius) {
  // disc_free decides from the cell's clearance where it can: it must say
  // what free_distance(p) >= radius says, also for radii that fall on the
  // edges of its shortcuts (a cell's clearance less one and two half
  // diagonals) and points at cell centres and at cell corners.
  const OccupancyGrid g = random_grid(40, 30, 0.05, 11);
  const ClearanceMap cm(g);
  const double half = 0.5 * std::sqrt(2.0) * g.resolution();
  std::mt19937 rng(5);
  std::uniform_real_distribution<> ux(0.9, 5.1), uy(-1.1, 2.1), ur(0.0, 0.6);
  std::size_t agreed = 0, free_discs = 0;
  for (int t = 0; t < 20000; ++t) {
    Point2 p{ux(rng), uy(rng)};
    if (t % 3 == 1) p = g.cell_center(g.world_to_cell(p));
    if (t % 3 == 2) {  // a cell's corner (as far from its centre as a point of it gets)
      const Point2 q = g.cell_center(g.world_to_cell(p));
      p = Point2{q.x - 0.5 * g.resolution(), q.y - 0.5 * g.resolution()};
    }
    const Cell c = g.world_to_cell(p);
    const double clr = cm.at(c);
    for (const double r : {ur(rng), clr - half, clr - 2.0 * half, cm.free_distance(p), 0.0}) {
      ASSERT_EQ(cm.disc_free(p, r), cm.free_distance(p) >= r) << p.x << ", " << p.y << " radius " << r;
      ++agreed;
      free_discs += cm.disc_free(p, r) ? 1 : 0;
    }
  }
  EXPECT_EQ(agreed, 100000u);
  EXPECT_GT(free_discs, 20000u);  // both answers are common
  EXPECT_LT(free_discs, 90000u);
}

}  // namespace
}  // namespace gather
