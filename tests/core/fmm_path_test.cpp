// Tests of path extraction and geodesic distances (gather_core/fmm/path.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/fmm/path.hpp"
#include "gather_core/grid/map_loader.hpp"
#include "predicate_grid.hpp"

namespace gather {
namespace fmm {
namespace {

OccupancyGrid grid_from(int w, int h, const std::function<bool(int, int)>& free, double res) {
  return testing_support::predicate_grid(w, h, free, res, Point2{1.0, -2.0});
}

// Rooms 50 cells apart, walls 3 cells thick, one 8-cell door per wall segment.
OccupancyGrid office(int n, double res) {
  return grid_from(
      n, n,
      [=](int r, int c) {
        auto wall = [](int v) { return v % 50 < 3; };
        auto door = [](int v) { return v % 50 >= 21 && v % 50 < 29; };
        if (r >= n - 3 || c >= n - 3) return false;
        const bool wr = wall(r), wc = wall(c);
        if (!wr && !wc) return true;
        if (wr && wc) return false;
        if (r < 3 || c < 3) return false;
        return wr ? door(c) : door(r);
      },
      res);
}

// Checks the path's promises: starts at `from`, every point in a traversable
// cell, consecutive points in the same or adjacent cells without cutting an
// obstacle corner, interpolated time never rising, ends at a source.
void check_path(const FastMarching& fm, const OccupancyGrid& g, const std::vector<Point2>& path, Point2 from) {
  ASSERT_GE(path.size(), 2u);
  EXPECT_DOUBLE_EQ(path.front().x, from.x);
  EXPECT_DOUBLE_EQ(path.front().y, from.y);
  double prev_t = interpolated_time(fm, path.front());
  for (std::size_t i = 0; i < path.size(); ++i) {
    const Cell c = g.world_to_cell(path[i]);
    ASSERT_TRUE(g.is_free(c)) << "point " << i << " in a non-free cell";
    if (i > 0) {
      const Cell p = g.world_to_cell(path[i - 1]);
      const int dr = c.row - p.row, dc = c.col - p.col;
      if (i + 1 < path.size()) {  // the last segment joins a seed cell to its source: may span two cells
        ASSERT_LE(std::abs(dr), 1);
        ASSERT_LE(std::abs(dc), 1);
      }
      if (std::abs(dr) == 1 && std::abs(dc) == 1) {
        ASSERT_TRUE(g.is_free({p.row + dr, p.col}) && g.is_free({p.row, p.col + dc})) << "corner cut at " << i;
      }
      // Sample the segment: never in an obstacle.
      for (int k = 1; k < 20; ++k) {
        const double s = k / 20.0;
        const Point2 q{path[i - 1].x + s * (path[i].x - path[i - 1].x),
                       path[i - 1].y + s * (path[i].y - path[i - 1].y)};
        ASSERT_TRUE(g.is_free(g.world_to_cell(q))) << "segment " << i << " crosses an obstacle";
      }
      const double t = interpolated_time(fm, path[i]);
      EXPECT_LE(t, prev_t + 1e-6) << "time rises at point " << i;
      prev_t = t;
    }
  }
}

TEST(FmmPath, StraightOnFreeGrid) {
  const double res = 0.25;
  const OccupancyGrid g = grid_from(
      160, 120, [](int, int) { return true; }, res);
  FastMarching fm(g);
  const Point2 src{11.13, 12.87};
  for (Order order : {Order::kFirst, Order::kSecond}) {
    SolveOptions o;
    o.order = order;
    fm.solve({Source::at_point(src)}, o);
    for (const Point2 from : {Point2{35.3, 25.1}, Point2{2.2, 0.1}, Point2{38.9, -1.7}, Point2{11.5, 13.0}}) {
      const std::vector<Point2> path = descend(fm, from);
      check_path(fm, g, path, from);
      EXPECT_NEAR(path.back().x, src.x, 1e-12);
      EXPECT_NEAR(path.back().y, src.y, 1e-12);
      const double t = fm.time_at(from);
      const double straight = std::hypot(from.x - src.x, from.y - src.y);
      // time_at() near the source is an upper bound off by up to a cell.
      EXPECT_NEAR(path_length(path), straight, 0.02 * straight + 1e-9);
      if (order == Order::kSecond) {
        EXPECT_NEAR(path_length(path), t, 0.02 * t + res);
      }
    }
  }
}

TEST(FmmPath, AroundWallsNeverEntersObstacles) {
  const double res = 0.1;
  const OccupancyGrid g = office(200, res);
  FastMarching fm(g);
  const std::vector<Source> src{Source::at_point({1.0 + 2.53, -2.0 + 2.61}), Source::at_cell({170, 120})};
  for (Order order : {Order::kFirst, Order::kSecond}) {
    SolveOptions o;
    o.order = order;
    fm.solve(src, o);
    int checked = 0;
    for (int r = 5; r < 200; r += 23) {
      for (int c = 7; c < 200; c += 19) {
        if (!g.is_free({r, c}) || !fm.reached({r, c})) continue;
        Point2 from = g.cell_center({r, c});
        from.x += 0.031;
        from.y -= 0.027;
        const std::vector<Point2> path = descend(fm, from);
        check_path(fm, g, path, from);
        const int lab = fm.label({r, c});
        ASSERT_GE(lab, 0);
        const Source& s = src[static_cast<std::size_t>(lab)];
        const Point2 sp = s.is_point ? s.point : g.cell_center(s.cell);
        EXPECT_NEAR(path.back().x, sp.x, 1e-9);
        EXPECT_NEAR(path.back().y, sp.y, 1e-9);
        // Within 2% of T at second order; first-order T itself is up to ~4% long
        // on these short, cornered paths (the path is the shorter of the two).
        const double t = fm.time_at(from);
        const double len = path_length(path);
        if (order == Order::kSecond) {
          EXPECT_NEAR(len, t, 0.02 * t + 0.5 * res) << "from cell " << r << "," << c;
        } else {
          EXPECT_LE(len, t + 0.5 * res);
          EXPECT_GE(len, 0.95 * t - 0.5 * res);
        }
        ++checked;
      }
    }
    EXPECT_GT(checked, 50);
  }
}

TEST(FmmPath, ErrorsAndGeodesic) {
  const double res = 0.5;
  // A closed room on the right: unreachable from the left.
  const OccupancyGrid g = grid_from(
      60, 40,
      [](int r, int c) {
        if (c == 40) return false;
        return !(r == 20 && c > 10 && c < 30);
      },
      res);
  FastMarching fm(g);
  fm.solve({Source::at_cell({5, 5})});
  EXPECT_THROW(descend(fm, g.cell_center({5, 50})), Error);   // unreached
  EXPECT_THROW(descend(fm, g.cell_center({20, 20})), Error);  // obstacle
  EXPECT_THROW(descend(fm, Point2{-100.0, 0.0}), Error);      // off the map
  EXPECT_TRUE(std::isinf(geodesic_time(fm, g.cell_center({5, 5}), g.cell_center({5, 50}))));
  // In open space the geodesic is the straight line; around the wall it is longer.
  const Point2 a = g.cell_center({5, 5}), b{a.x + 6.2, a.y + 3.3};
  EXPECT_NEAR(geodesic_time(fm, a, b), std::hypot(6.2, 3.3), 0.02 * std::hypot(6.2, 3.3));
  EXPECT_NEAR(geodesic_time(fm, b, a), std::hypot(6.2, 3.3), 0.02 * std::hypot(6.2, 3.3));
  const Point2 below = g.cell_center({15, 20}), above = g.cell_center({25, 20});
  const double around = geodesic_time(fm, below, above);
  // Exact: via the wall's end at x = origin + 11 cells (wall spans cols 11..29 on row 20).
  const Point2 corner_lo{1.0 + 11 * res, -2.0 + 20 * res}, corner_hi{1.0 + 11 * res, -2.0 + 21 * res};
  const double exact = std::hypot(below.x - corner_lo.x, below.y - corner_lo.y) + res +
                       std::hypot(above.x - corner_hi.x, above.y - corner_hi.y);
  EXPECT_NEAR(around, exact, 0.02 * exact + 2 * res);
}

TEST(FmmPath, RandomPathsOnTheOfficeMap) {
  // maps/office.yaml: 1200 x 700 cells at 0.05 m, rooms and doors.
  const OccupancyGrid g = load_map(std::string(GATHER_REPO_DIR) + "/maps/office.yaml");
  FastMarching fm(g);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> row(0, g.height() - 1), col(0, g.width() - 1);
  Cell s;
  do s = Cell{row(rng), col(rng)};
  while (!g.is_free(s));
  SolveOptions o;
  o.order = Order::kSecond;
  fm.solve({Source::at_cell(s)}, o);
  int checked = 0;
  for (int k = 0; k < 400 && checked < 100; ++k) {
    const Cell c{row(rng), col(rng)};
    if (!fm.reached(c)) continue;
    const Point2 from = g.cell_center(c);
    const std::vector<Point2> path = descend(fm, from);
    check_path(fm, g, path, from);
    const double t = fm.time_at(from);
    EXPECT_NEAR(path_length(path), t, 0.02 * t + g.resolution()) << "from cell " << c.row << "," << c.col;
    ++checked;
  }
  EXPECT_EQ(checked, 100);
}

// An ArcWalker gives what point_at_arc gives, bit for bit, for positions
// that step a little, jump far ahead (past many waypoints: its binary
// search) and go back, with zero-length pieces on the path.
TEST(FmmPath, ArcWalkerAgreesWithPointAtArcOnStepsJumpsAndReturns) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Point2> path{{0.0, 0.0}};
  for (int i = 0; i < 500; ++i)
    path.push_back(i % 37 == 0 ? path.back() : Point2{path.back().x + u(rng), path.back().y + u(rng)});
  const std::vector<double> arcs = path_arcs(path);
  ArcWalker walk(path, arcs);
  std::vector<double> at{-1.0, 0.0};
  for (double s = 0.0; s < arcs.back() + 2.0; s += (at.size() % 5 == 0 ? 40.0 : 0.3)) at.push_back(s);
  at.push_back(arcs[37]);     // exactly on a zero-length piece
  at.push_back(5.0);          // back
  at.push_back(arcs.back());  // the end
  for (const double s : at) {
    const Point2 w = walk.at(s), p = point_at_arc(path, arcs, s);
    EXPECT_EQ(w.x, p.x) << "at s = " << s;
    EXPECT_EQ(w.y, p.y) << "at s = " << s;
  }
}

}  // namespace
}  // namespace fmm
}  // namespace gather
