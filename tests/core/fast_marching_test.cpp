// fmm/fast_marching: accuracy, labels, queues, early stops, speed maps and bad input of the Eikonal solver.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <random>
#include <string>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/fmm/path.hpp"
#include "gather_core/numeric.hpp"
#include "gather_core/radix_queue.hpp"
#include "predicate_grid.hpp"

namespace gather {
namespace fmm {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

OccupancyGrid make_grid(int w, int h, const std::function<bool(int, int)>& free, double res = 1.0,
                        Point2 origin = {0.0, 0.0}) {
  return testing_support::predicate_grid(w, h, free, res, origin);
}

OccupancyGrid free_grid(int w, int h, double res = 1.0) {
  return make_grid(
      w, h, [](int, int) { return true; }, res);
}

// Rooms on a pitch with walls `wall` cells thick and a door gap in each wall segment.
OccupancyGrid office_grid(int n, int pitch, int wall, int door) {
  return make_grid(n, n, [=](int r, int c) {
    auto in_wall = [&](int v) { return v % pitch < wall || v >= n - wall; };
    auto in_door = [&](int v) {
      const int m = v % pitch;
      return m >= pitch / 2 - door / 2 && m < pitch / 2 + door / 2;
    };
    const bool wr = in_wall(r), wc = in_wall(c);
    if (!wr && !wc) return true;
    if (wr && wc) return false;
    if (r >= n - wall || c >= n - wall || r < wall || c < wall) return false;  // outer walls
    return wr ? in_door(c) : in_door(r);
  });
}

struct Errors {
  double mean = 0.0, max = 0.0;
};

// Error [cells] against the exact Euclidean distance to the nearest of `points` (cell units).
Errors euclid_errors(const FastMarching& fm, const std::vector<Point2>& points_cells) {
  Errors e;
  std::size_t n = 0;
  for (int r = 0; r < fm.height(); ++r)
    for (int c = 0; c < fm.width(); ++c) {
      double exact = kInf;
      for (const Point2& p : points_cells) exact = std::min(exact, std::hypot(c + 0.5 - p.x, r + 0.5 - p.y));
      const double d = std::abs(fm.time(Cell{r, c}) / fm.resolution() - exact);
      e.mean += d;
      e.max = std::max(e.max, d);
      ++n;
    }
  e.mean /= static_cast<double>(n);
  return e;
}

TEST(FastMarching, AccuracyOnFreeGrid2000) {
  const OccupancyGrid g = free_grid(2000, 2000);
  FastMarching fm(g);
  SolveOptions o;
  o.labels = false;
  fm.solve({Source::at_cell({1000, 1000})}, o);
  const Errors e1 = euclid_errors(fm, {{1000.5, 1000.5}});
  EXPECT_LE(e1.mean, 1.4);
  EXPECT_LE(e1.max, 2.4);
  o.order = Order::kSecond;
  fm.solve({Source::at_cell({1000, 1000})}, o);
  const Errors e2 = euclid_errors(fm, {{1000.5, 1000.5}});
  EXPECT_LE(e2.mean, 0.2);
  EXPECT_LE(e2.max, 0.35);
  std::printf("order 1: mean %.4f max %.4f cells; order 2: mean %.4f max %.4f cells\n", e1.mean, e1.max, e2.mean,
              e2.max);
}

TEST(FastMarching, QueuesAgree) {
  // First order: the label-correcting buckets reach the exact-FMM fixed point;
  // second order: sorted buckets reproduce the heap exactly.
  const OccupancyGrid g = office_grid(240, 60, 3, 12);
  FastMarching a(g), b(g);
  const std::vector<Source> src{Source::at_cell({30, 30}), Source::at_point({200.3, 150.7})};
  for (Order order : {Order::kFirst, Order::kSecond}) {
    for (QueueKind q : {QueueKind::kBuckets, QueueKind::kSortedBuckets}) {
      if (order == Order::kSecond && q == QueueKind::kBuckets) continue;
      for (double width : {0.0, 0.3, 3.0}) {
        SolveOptions oa, ob;
        oa.order = ob.order = order;
        oa.queue = QueueKind::kHeap;
        ob.queue = q;
        ob.bucket_width = width;
        a.solve(src, oa);
        b.solve(src, ob);
        for (int r = 0; r < g.height(); ++r)
          for (int c = 0; c < g.width(); ++c) {
            const double ta = a.time({r, c}), tb = b.time({r, c});
            if (std::isinf(ta)) {
              ASSERT_TRUE(std::isinf(tb));
            } else {
              ASSERT_NEAR(ta, tb, 1e-3 + 1e-5 * ta) << "cell " << r << "," << c << " order " << int(order);
            }
          }
      }
    }
  }
}

TEST(FastMarching, ExactQueuesExpandEveryCellOnce) {
  // Fine resolution, point and cell sources: the seeds spread over more
  // buckets than one crossing; every reached cell must still be expanded.
  const OccupancyGrid g = make_grid(
      300, 200, [](int r, int c) { return !(c == 150 && r > 20); }, 0.05);
  FastMarching fm(g);
  const std::vector<Source> src{Source::at_point({2.013, 3.377}), Source::at_cell({150, 250})};
  for (QueueKind q : {QueueKind::kSortedBuckets, QueueKind::kHeap}) {
    for (Order order : {Order::kFirst, Order::kSecond}) {
      SolveOptions o;
      o.order = order;
      o.queue = q;
      const SolveStats& st = fm.solve(src, o);
      EXPECT_EQ(st.expanded, fm.count_reached()) << "queue " << int(q) << " order " << int(order);
    }
  }
  SolveOptions o;
  o.front_speed = {0.1, 3.0};  // slow and fast fronts widen the span of queued times
  for (QueueKind q : {QueueKind::kSortedBuckets, QueueKind::kBuckets}) {
    o.queue = q;
    const SolveStats& st = fm.solve(src, o);
    EXPECT_GE(st.expanded, fm.count_reached());
    Raster<double> a;
    fm.copy_times(a);
    o.queue = QueueKind::kHeap;
    fm.solve(src, o);
    const Raster<double> b = fm.times();
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (std::isinf(b[i])) {
        ASSERT_TRUE(std::isinf(a[i]));
      } else {
        ASSERT_NEAR(a[i], b[i], 1e-3 + 1e-5 * b[i]);
      }
    }
  }
}

// Shortest path length around axis-aligned rectangular obstacles: Dijkstra on
// the visibility graph of the obstacle corners (exact in the continuum).
double exact_shortest(Point2 a, Point2 b, const std::vector<std::array<double, 4>>& rects, double map_w, double map_h) {
  auto blocked = [&](Point2 p, Point2 q) {
    for (const auto& R : rects) {  // segment strictly through the open rectangle?
      const int steps = 400;
      for (int i = 1; i < steps; ++i) {
        const double s = static_cast<double>(i) / steps;
        const double x = p.x + s * (q.x - p.x), y = p.y + s * (q.y - p.y);
        if (x < 0.0 || y < 0.0 || x > map_w || y > map_h) return true;  // off the map
        if (x > R[0] + 1e-9 && x < R[2] - 1e-9 && y > R[1] + 1e-9 && y < R[3] - 1e-9) return true;
      }
    }
    return false;
  };
  std::vector<Point2> nodes{a, b};
  for (const auto& R : rects)
    for (int k = 0; k < 4; ++k) nodes.push_back(Point2{k & 1 ? R[2] : R[0], k & 2 ? R[3] : R[1]});
  std::vector<double> dist(nodes.size(), kInf);
  std::vector<bool> done(nodes.size(), false);
  dist[0] = 0.0;
  for (std::size_t it = 0; it < nodes.size(); ++it) {
    std::size_t u = nodes.size();
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (!done[i] && (u == nodes.size() || dist[i] < dist[u])) u = i;
    if (u == nodes.size() || std::isinf(dist[u])) break;
    done[u] = true;
    for (std::size_t v = 0; v < nodes.size(); ++v)
      if (!done[v] && !blocked(nodes[u], nodes[v]))
        dist[v] = std::min(dist[v], dist[u] + std::hypot(nodes[u].x - nodes[v].x, nodes[u].y - nodes[v].y));
  }
  return dist[1];
}

TEST(FastMarching, GeodesicAroundObstaclesMatchesExactShortestPath) {
  const double res = 0.1;
  // Obstacles in meters [x0, y0, x1, y1] on a 12 m x 8 m map.
  // Walls touching the map border extend past it, so no path slips around them.
  const std::vector<std::array<double, 4>> rects{{3.0, -1.0, 3.5, 6.0}, {7.0, 2.0, 7.5, 9.0}, {9.0, 3.0, 11.0, 4.0}};
  const OccupancyGrid g = make_grid(
      120, 80,
      [&](int r, int c) {
        const double x = (c + 0.5) * res, y = (r + 0.5) * res;
        for (const auto& R : rects)
          if (x > R[0] && x < R[2] && y > R[1] && y < R[3]) return false;
        return true;
      },
      res);
  FastMarching fm(g);
  const std::vector<std::pair<Point2, Point2>> pairs{
      {{1.02, 1.03}, {5.11, 1.27}}, {{1.02, 1.03}, {11.5, 1.0}}, {{5.0, 7.5}, {10.0, 5.5}}, {{0.5, 7.5}, {11.7, 0.3}}};
  for (Order order : {Order::kFirst, Order::kSecond}) {
    for (const auto& pr : pairs) {
      const double exact = exact_shortest(pr.first, pr.second, rects, 12.0, 8.0);
      const double got = geodesic_time(fm, pr.first, pr.second, order);
      // First-order FMM is O(h log) off near corners and diagonals; a few cells plus 2%.
      const double tol = (order == Order::kFirst ? 0.03 : 0.02) * exact + 3 * res;
      EXPECT_NEAR(got, exact, tol) << "order " << int(order) << " from " << pr.first.x << "," << pr.first.y;
    }
  }
}

TEST(FastMarching, LabelsAreArgminOfSingleSourceRuns) {
  const OccupancyGrid g = office_grid(180, 60, 3, 10);
  const std::vector<Source> src{Source::at_cell({20, 20}), Source::at_cell({100, 40}), Source::at_point({150.2, 30.9}),
                                Source::at_cell({160, 160}), Source::at_point({45.5, 110.25})};
  FastMarching fm(g);
  for (Order order : {Order::kFirst, Order::kSecond}) {
    for (int look_back : {6, 0}) {
      SolveOptions o;
      o.order = order;
      o.label_look_back = look_back;
      std::vector<Raster<double>> single(src.size());
      for (std::size_t i = 0; i < src.size(); ++i) {
        fm.solve({src[i]}, o);
        fm.copy_times(single[i]);
      }
      fm.solve(src, o);
      const Raster<double> multi = fm.times();
      const LabelImage labels = fm.labels();
      ASSERT_EQ(multi.frame(), g.frame());
      ASSERT_EQ(labels.frame(), g.frame());
      std::size_t checked = 0, wrong = 0;
      double worst_margin = 0.0;
      for (std::size_t p = 0; p < multi.size(); ++p) {
        double best = kInf, second = kInf;
        int arg = -1;
        for (std::size_t i = 0; i < src.size(); ++i) {
          if (single[i][p] < best) {
            second = best;
            best = single[i][p];
            arg = static_cast<int>(i);
          } else {
            second = std::min(second, single[i][p]);
          }
        }
        if (std::isinf(best)) {
          EXPECT_EQ(labels[p], -1);
          EXPECT_TRUE(std::isinf(multi[p]));
          continue;
        }
        EXPECT_LE(multi[p], best + 0.1);
        if (second - best > 1.0) {           // ties aside
          EXPECT_NEAR(multi[p], best, 0.1);  // fronts that merge upwind shift times slightly
          ++checked;
          if (labels[p] != arg) {
            ++wrong;
            worst_margin = std::max(worst_margin, second - best);
          }
        }
      }
      EXPECT_GT(checked, multi.size() / 2);
      // With look-back (the default) labels match; copying the earliest
      // neighbour's label alone drifts near collisions (see docs/fmm.md).
      std::printf("order %d look_back %d: %zu of %zu labels differ from the argmin (margin up to %.2f)\n", int(order),
                  look_back, wrong, checked, worst_margin);
      if (look_back > 0) {
        EXPECT_EQ(wrong, 0u);
      } else {
        EXPECT_LE(wrong, checked / 50);
      }
    }
  }
}

TEST(FastMarching, UnreachedCellsStayInfinite) {
  // A closed box in the middle: its inside is free but unreachable.
  const OccupancyGrid g = make_grid(50, 40, [](int r, int c) {
    const bool box = r >= 10 && r <= 30 && c >= 10 && c <= 30;
    const bool inside = r > 12 && r < 28 && c > 12 && c < 28;
    return !box || inside;
  });
  FastMarching fm(g);
  for (Order order : {Order::kFirst, Order::kSecond}) {
    SolveOptions o;
    o.order = order;
    fm.solve({Source::at_cell({2, 2})}, o);
    EXPECT_TRUE(std::isinf(fm.time({20, 20})));
    EXPECT_EQ(fm.label({20, 20}), -1);
    EXPECT_FALSE(fm.reached({20, 20}));
    EXPECT_TRUE(std::isinf(fm.time({11, 11})));  // wall
    EXPECT_TRUE(std::isinf(fm.time({-1, 0})));   // off the map
    EXPECT_TRUE(fm.reached({35, 45}));
    EXPECT_EQ(fm.label({35, 45}), 0);
    const std::size_t inside = 15 * 15;
    const std::size_t walls = 21 * 21 - inside;
    EXPECT_EQ(fm.count_reached(), 50u * 40u - walls - inside);
    // A source inside reaches only the inside.
    fm.solve({Source::at_cell({20, 20})}, o);
    EXPECT_EQ(fm.count_reached(), inside);
    EXPECT_TRUE(std::isinf(fm.time({2, 2})));
  }
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(FastMarching, BadInputGivesClearErrors) {
  const OccupancyGrid g = make_grid(10, 8, [](int r, int c) { return !(r == 3 && c == 4); });
  FastMarching fm(g);
  EXPECT_NE(error_of([&] { fm.solve({Source::at_cell({3, 4})}); }).find("obstacle"), std::string::npos);
  EXPECT_NE(error_of([&] { fm.solve({Source::at_cell({8, 0})}); }).find("off the map"), std::string::npos);
  EXPECT_NE(error_of([&] { fm.solve({Source::at_cell({0, -1})}); }).find("off the map"), std::string::npos);
  EXPECT_NE(error_of([&] { fm.solve({Source::at_point({10.5, 1.0})}); }).find("off the map"), std::string::npos);
  EXPECT_NE(error_of([&] { fm.solve({Source::at_point({4.5, 3.5})}); }).find("obstacle"), std::string::npos);
  EXPECT_NE(error_of([&] { fm.solve({Source::at_point({NAN, 1.0})}); }).find("not finite"), std::string::npos);
  EXPECT_NE(error_of([&] { fm.solve({}); }).find("no sources"), std::string::npos);
  Raster<double> speed(fm.frame(), 1.0);
  speed[17] = -0.5;
  EXPECT_NE(error_of([&] { fm.set_speed(speed); }).find("speed"), std::string::npos);
  speed[17] = NAN;
  EXPECT_NE(error_of([&] { fm.set_speed(speed); }).find("speed"), std::string::npos);
  EXPECT_NE(error_of([&] { fm.set_speed(Raster<double>(GridFrame{79, 1}, 1.0)); }).find("79x1"), std::string::npos);
  Raster<double> released(fm.frame(), 1.0);
  released.release();
  EXPECT_NE(error_of([&] { fm.set_speed(released); }).find("holding 0 values"), std::string::npos);
  SolveOptions o;
  o.targets = {Cell{100, 0}};
  EXPECT_NE(error_of([&] { fm.solve({Source::at_cell({0, 0})}, o); }).find("off the map"), std::string::npos);
  o.targets.clear();
  o.max_time = -1.0;
  EXPECT_NE(error_of([&] { fm.solve({Source::at_cell({0, 0})}, o); }).find("max_time"), std::string::npos);
  // Messages name the source; a failed solve leaves nothing reached.
  EXPECT_NE(error_of([&] {
              fm.solve({Source::at_cell({0, 0}), Source::at_cell({3, 4})});
            }).find("source 1"),
            std::string::npos);
  EXPECT_FALSE(fm.reached({0, 0}));
  EXPECT_EQ(fm.count_reached(), 0u);
}

TEST(FastMarching, WorkspaceReuseGivesSameResultWithoutGrowing) {
  const OccupancyGrid g = office_grid(300, 60, 3, 12);
  FastMarching fm(g);
  for (Order order : {Order::kFirst, Order::kSecond}) {
    SolveOptions o;
    o.order = order;
    const std::vector<Source> s1{Source::at_cell({30, 30}), Source::at_cell({200, 250})};
    fm.solve(s1, o);
    Raster<double> t1, t2;
    LabelImage l1, l2;
    fm.copy_times(t1);
    fm.copy_labels(l1);
    const std::size_t bytes = fm.working_bytes();
    fm.solve(s1, o);  // the same solve again allocates nothing
    EXPECT_EQ(fm.working_bytes(), bytes);
    // A different solve in between, including an early-stopped one (sparse reset path).
    fm.solve({Source::at_point({150.5, 150.5})}, o);
    SolveOptions stop = o;
    stop.max_time = 5.0;
    fm.solve({Source::at_cell({100, 100})}, stop);
    fm.solve(s1, o);
    fm.copy_times(t2);
    fm.copy_labels(l2);
    EXPECT_EQ(t1, t2);
    EXPECT_EQ(l1, l2);
    EXPECT_LE(static_cast<double>(fm.working_bytes()) / (300.0 * 300.0), 16.0);
  }
}

TEST(FastMarching, BindingAnotherGridGivesAFreshWorkspacesResult) {
  // A workspace that marched on a large grid, bound to a smaller one with
  // another origin and walls (and back), gives what a new workspace gives.
  const OccupancyGrid big = office_grid(300, 60, 3, 12);
  const OccupancyGrid small = make_grid(
      40, 25, [](int r, int c) { return !(c == 20 && r < 18); }, 0.1, Point2{3.0, -2.0});
  FastMarching fm(big);
  SolveOptions labelled;
  fm.solve({Source::at_cell({30, 30}), Source::at_cell({200, 250})}, labelled);
  fm.bind(small.frame(), small.free_mask());
  EXPECT_EQ(fm.width(), 40);
  EXPECT_EQ(fm.height(), 25);
  EXPECT_FALSE(fm.reached(Cell{2, 2}));  // nothing of the last solve is left
  SolveOptions plain;
  plain.labels = false;
  fm.solve({Source::at_cell({2, 2})}, plain);
  FastMarching fresh(small);
  fresh.solve({Source::at_cell({2, 2})}, plain);
  EXPECT_EQ(fm.times(), fresh.times());
  EXPECT_GT(fm.time(Cell{2, 30}), 1.5);  // around the wall's end
  EXPECT_DOUBLE_EQ(fm.time_at(Point2{3.0 + 0.35, -2.0 + 0.25}), fresh.time_at(Point2{3.0 + 0.35, -2.0 + 0.25}));
  fm.bind(big.frame(), big.free_mask());
  fm.solve({Source::at_cell({30, 30}), Source::at_cell({200, 250})}, labelled);
  FastMarching again(big);
  again.solve({Source::at_cell({30, 30}), Source::at_cell({200, 250})}, labelled);
  EXPECT_EQ(fm.times(), again.times());
  EXPECT_EQ(fm.labels(), again.labels());
  // Bound to a grid of the same size (so its arrays keep their layout and
  // the next solve resets only what the last one touched): nothing of the
  // last solve is left, and a march there is a fresh workspace's.
  const OccupancyGrid walls = office_grid(300, 50, 4, 9);
  SolveOptions stop = plain;
  stop.max_time = 8.0;  // an early stop touches few cells: the sparse reset
  fm.solve({Source::at_cell({30, 30})}, stop);
  ASSERT_TRUE(fm.reached(Cell{32, 33}));
  fm.bind(walls.frame(), walls.free_mask());
  EXPECT_FALSE(fm.reached(Cell{32, 33}));
  fm.solve({Source::at_cell({120, 140})}, stop);
  FastMarching other(walls);
  other.solve({Source::at_cell({120, 140})}, stop);
  EXPECT_EQ(fm.times(), other.times());
  EXPECT_FALSE(fm.reached(Cell{32, 33}));
  // A mask that is not the frame's size, or an empty frame, is refused.
  EXPECT_THROW(fm.bind(small.frame(), big.free_mask()), Error);
  EXPECT_THROW(fm.bind(GridFrame{0, 5, 0.1, Point2{}}, {}), Error);
  EXPECT_THROW(fm.bind(GridFrame{4, 4, 0.0, Point2{}}, std::vector<uint8_t>(16, 1)), Error);
}

TEST(FastMarching, EarlyStopAtTargetsAndMaxTime) {
  const OccupancyGrid g = office_grid(300, 60, 3, 12);
  FastMarching fm(g);
  for (QueueKind q : {QueueKind::kAuto, QueueKind::kHeap}) {
    for (Order order : {Order::kFirst, Order::kSecond}) {
      SolveOptions o;
      o.order = order;
      o.queue = q;
      const std::vector<Source> src{Source::at_cell({30, 30})};
      fm.solve(src, o);
      const Raster<double> full = fm.times();
      EXPECT_FALSE(fm.stats().stopped_early);

      SolveOptions ot = o;
      ot.targets = {Cell{90, 90}, Cell{40, 100}};
      fm.solve(src, ot);
      EXPECT_TRUE(fm.stats().stopped_early);
      EXPECT_DOUBLE_EQ(fm.time({90, 90}), full[90 * 300 + 90]);
      EXPECT_DOUBLE_EQ(fm.time({40, 100}), full[40 * 300 + 100]);
      EXPECT_TRUE(std::isinf(fm.time({290, 290})));
      EXPECT_LT(fm.count_reached(), g.free_cells() / 2);
      for (int r = 0; r < 300; ++r)
        for (int c = 0; c < 300; ++c) {
          const double t = fm.time({r, c});
          if (!std::isinf(t)) {
            ASSERT_DOUBLE_EQ(t, full[r * 300 + c]);  // what is reported is final
          }
        }

      SolveOptions om = o;
      om.max_time = 70.0;
      fm.solve(src, om);
      EXPECT_TRUE(fm.stats().stopped_early);
      for (int r = 0; r < 300; ++r)
        for (int c = 0; c < 300; ++c) {
          const double f = full[r * 300 + c];
          if (f <= 70.0)
            ASSERT_DOUBLE_EQ(fm.time({r, c}), f);
          else
            ASSERT_TRUE(std::isinf(fm.time({r, c})));
        }
    }
  }
}

TEST(FastMarching, SubCellPointSource) {
  const double res = 0.5;
  const OccupancyGrid g = make_grid(
      200, 160, [](int, int) { return true; }, res, Point2{-3.0, 2.0});
  FastMarching fm(g);
  const Point2 p{20.37, 41.81};  // [m]
  for (Order order : {Order::kFirst, Order::kSecond}) {
    SolveOptions o;
    o.order = order;
    fm.solve({Source::at_point(p)}, o);
    const Cell pc = g.world_to_cell(p);
    // The source cell and its 8 neighbours carry the exact distance [m].
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const Cell n{pc.row + dr, pc.col + dc};
        const Point2 cn = g.cell_center(n);
        EXPECT_NEAR(fm.time(n), std::hypot(cn.x - p.x, cn.y - p.y), 1e-5);
      }
    EXPECT_LE(fm.time_at(p), 0.75 * res);  // an upper bound: via the nearest cell centre
    const Point2 pcells{(p.x - g.origin().x) / res, (p.y - g.origin().y) / res};
    const Errors e = euclid_errors(fm, {pcells});
    EXPECT_LE(e.mean, order == Order::kFirst ? 1.0 : 0.2);
    EXPECT_LE(e.max, order == Order::kFirst ? 1.6 : 0.35);
  }
}

TEST(FastMarching, SpeedMapScalesTimes) {
  const OccupancyGrid g = office_grid(120, 60, 3, 10);
  FastMarching unit(g), fast(g);
  fast.set_speed(Raster<double>(g.frame(), 2.5));
  const std::vector<Source> src{Source::at_point({10.2, 12.7})};
  unit.solve(src);
  fast.solve(src);
  for (int r = 0; r < 120; r += 7)
    for (int c = 0; c < 120; c += 5) {
      const double u = unit.time({r, c});
      if (std::isinf(u)) {
        EXPECT_TRUE(std::isinf(fast.time({r, c})));
      } else {
        EXPECT_NEAR(fast.time({r, c}), u / 2.5, 1e-4 * u + 1e-5);
      }
    }
  fast.set_unit_speed();
  EXPECT_TRUE(fast.unit_speed());
  fast.solve(src);
  EXPECT_NEAR(fast.time({20, 20}), unit.time({20, 20}), 1e-9);
}

TEST(FastMarching, SlowAndBlockedCells) {
  // Left half 1 m/s, right half 0.5 m/s, column 30 at zero speed (a wall).
  const OccupancyGrid g = make_grid(120, 40, [](int, int) { return true; });
  Raster<double> speed(g.frame(), 1.0);
  for (int r = 0; r < 40; ++r) {
    for (int c = 60; c < 120; ++c) speed[static_cast<std::size_t>(r) * 120 + c] = 0.5;
    speed[static_cast<std::size_t>(r) * 120 + 30] = 0.0;
  }
  FastMarching fm(g);
  fm.set_speed(speed);
  EXPECT_DOUBLE_EQ(fm.speed({5, 70}), 0.5);
  EXPECT_DOUBLE_EQ(fm.speed({5, 30}), 0.0);
  EXPECT_FALSE(fm.traversable({10, 30}));
  for (Order order : {Order::kFirst, Order::kSecond}) {
    SolveOptions o;
    o.order = order;
    fm.solve({Source::at_cell({20, 50})}, o);
    EXPECT_TRUE(std::isinf(fm.time({20, 20})));  // behind the zero-speed column
    EXPECT_TRUE(std::isinf(fm.time({20, 30})));
    EXPECT_NEAR(fm.time({20, 40}), 10.0, 0.05);
    // 10 slow cells cost 2 s each.
    EXPECT_NEAR(fm.time({20, 69}) - fm.time({20, 59}), 20.0, order == Order::kFirst ? 0.01 : 0.6);
  }
  EXPECT_NE(error_of([&] { fm.solve({Source::at_cell({3, 30})}); }).find("zero speed"), std::string::npos);
}

TEST(FastMarching, FrontSpeedFactorsMoveTheBoundary) {
  const OccupancyGrid g = make_grid(200, 50, [](int, int) { return true; });
  FastMarching fm(g);
  const std::vector<Source> src{Source::at_cell({25, 50}), Source::at_cell({25, 150})};
  for (Order order : {Order::kFirst, Order::kSecond}) {
    SolveOptions o;
    o.order = order;
    o.front_speed = {2.0, 1.0};
    fm.solve(src, o);
    // Along the row: front 0 covers d0 at 2 m/s, front 1 at 1 m/s; they meet where
    // d0 / 2 = 100 - d0, d0 = 66.7 (col 116.7).
    EXPECT_NEAR(fm.time({25, 100}), 25.0, 0.01);
    EXPECT_NEAR(fm.time({25, 30}), 10.0, 0.01);
    EXPECT_NEAR(fm.time({25, 170}), 20.0, 0.01);
    EXPECT_EQ(fm.label({25, 115}), 0);
    EXPECT_EQ(fm.label({25, 119}), 1);
    EXPECT_EQ(fm.label({5, 60}), 0);
    EXPECT_EQ(fm.label({45, 190}), 1);
  }
  SolveOptions bad;
  bad.front_speed = {1.0};
  EXPECT_NE(error_of([&] { fm.solve(src, bad); }).find("front_speed"), std::string::npos);
  bad.front_speed = {1.0, 0.0};
  EXPECT_NE(error_of([&] { fm.solve(src, bad); }).find("source 1"), std::string::npos);
  bad.front_speed = {1.0, 2.0};
  bad.labels = false;
  EXPECT_NE(error_of([&] { fm.solve(src, bad); }).find("labels"), std::string::npos);
}

// The queue of FrontGrowth::lower and the routes' A*: as a march uses it
// (each key taken queues a few above it, now and then a few a rounding
// puts at or just below it, and equal keys twice), it gives the keys in the
// order a binary heap of them does.
TEST(RadixQueue, GivesTheSmallestKeyQueuedAsABinaryHeapDoes) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> step(0.0f, 3.0f);
  std::uniform_int_distribution<uint32_t> cell(0, 1000), pick(0, 19);
  RadixQueue queue;
  std::priority_queue<uint64_t, std::vector<uint64_t>, std::greater<>> heap;
  auto push = [&](uint64_t key) { queue.push(key), heap.push(key); };
  push(order_key(0.0f, 5));
  std::size_t popped = 0, below = 0;
  while (!heap.empty() && popped < 20000) {
    ASSERT_FALSE(queue.empty());
    ASSERT_EQ(queue.size(), heap.size());
    const uint64_t key = queue.pop();
    ASSERT_EQ(key, heap.top()) << "pop " << popped;
    heap.pop();
    ++popped;
    const float t = order_key_time(key);
    if (heap.size() > 5000) continue;  // let the queue drain now and then
    for (int n = 0; n < 3; ++n) push(order_key(t + step(rng), cell(rng)));
    const uint32_t what = pick(rng);
    if (what == 0 && t > 0.0f) {  // rounding: at or just below the key taken, two neighbours at once
      push(order_key(std::nextafter(t, 0.0f), cell(rng)));
      push(order_key(std::nextafter(std::nextafter(t, 0.0f), 0.0f), cell(rng)));
      push(order_key(t, cell(rng)));
      ++below;
    } else if (what == 1) {
      push(key);  // the same key again
    }
  }
  EXPECT_GT(below, 100u);
  while (!heap.empty()) {
    ASSERT_EQ(queue.pop(), heap.top());
    heap.pop();
  }
  EXPECT_TRUE(queue.empty());
  // Cleared with keys queued (a march stopped early): none left, and a new
  // march's keys, below the last one taken, come out in order.
  for (uint32_t c = 0; c < 50; ++c) queue.push(order_key(1000.0f + static_cast<float>(c), c));
  EXPECT_EQ(queue.pop(), order_key(1000.0f, 0));
  queue.clear();
  EXPECT_TRUE(queue.empty());
  EXPECT_EQ(queue.size(), 0u);
  queue.push(order_key(2.0f, 1));
  queue.push(order_key(1.0f, 9));
  queue.push(order_key(3.0f, 4));
  EXPECT_EQ(queue.size(), 3u);
  EXPECT_EQ(queue.pop(), order_key(1.0f, 9));
  EXPECT_EQ(queue.pop(), order_key(2.0f, 1));
  EXPECT_EQ(queue.pop(), order_key(3.0f, 4));
  EXPECT_TRUE(queue.empty());
}

}  // namespace
}  // namespace fmm
}  // namespace gather
