// mission/tour: the open tour of a worker and the closed tour of a collector.
#include "gather_core/mission/tour.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

namespace gather {
namespace mission {
namespace {

// Points in the plane as tour distances: point 0 is the start, goals 1..n.
struct PlaneTour {
  std::vector<double> d;  // row-major (n + 1) x (n + 1)
  std::size_t stride = 0;
  explicit PlaneTour(const std::vector<std::pair<double, double>>& p) : stride(p.size()) {
    d.resize(stride * stride);
    for (std::size_t i = 0; i < stride; ++i)
      for (std::size_t j = 0; j < stride; ++j)
        d[i * stride + j] = std::hypot(p[i].first - p[j].first, p[i].second - p[j].second);
  }
  TourDistances distances() const { return TourDistances{d.data(), d.data(), stride}; }
  double closed_length(const std::vector<int>& order) const {
    double len = 0.0;
    int at = 0;
    for (int k : order) len += d[static_cast<std::size_t>(at) * stride + k], at = k;
    return len + d[static_cast<std::size_t>(at) * stride];
  }
};

std::vector<std::pair<double, double>> random_points(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 50.0);
  std::vector<std::pair<double, double>> p(static_cast<std::size_t>(n) + 1);
  for (auto& q : p) q = {u(rng), u(rng)};
  return p;
}

TEST(TourTest, OpenTourAlongALineIsInOrderWhateverTheSubsetsOrder) {
  // Start at x = 0, goals at x = 1..6 given shuffled: the open tour walks out once.
  std::vector<std::pair<double, double>> p;
  for (int x = 0; x <= 6; ++x) p.push_back({x, 0.0});
  const PlaneTour t(p);
  const int subset[6] = {4, 2, 6, 1, 5, 3};
  int order[6];
  char used[6];
  order_tour(t.distances(), subset, 6, order, used);
  EXPECT_EQ(std::vector<int>(order, order + 6), (std::vector<int>{1, 2, 3, 4, 5, 6}));
  EXPECT_DOUBLE_EQ(tour_length(t.distances(), order, 6), 6.0);
}

TEST(TourTest, TwoOptUndoesTheCrossingNearestNeighbourLeaves) {
  // Nearest neighbour alone leaves crossings on random points; after 2-opt no
  // reversal of a stretch of the tour shortens it.
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const auto p = random_points(15, seed);
    const PlaneTour t(p);
    std::vector<int> subset(15);
    std::iota(subset.begin(), subset.end(), 1);
    std::vector<int> order(15);
    std::vector<char> used(15);
    order_tour(t.distances(), subset.data(), 15, order.data(), used.data());
    std::vector<int> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, subset) << "every goal once, seed " << seed;
    const double len = tour_length(t.distances(), order.data(), 15);
    for (std::size_t i = 0; i + 1 < order.size(); ++i)
      for (std::size_t j = i + 1; j < order.size(); ++j) {
        std::vector<int> o = order;
        std::reverse(o.begin() + static_cast<long>(i), o.begin() + static_cast<long>(j) + 1);
        EXPECT_GE(tour_length(t.distances(), o.data(), 15), len - 1e-6) << "seed " << seed;
      }
  }
}

TEST(TourTest, TheSolversLimitsAreTheirParameters) {
  // No 2-opt pass leaves nearest neighbour's tour, longer on some of these
  // random sets; with passes it is never longer.
  int longer = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const PlaneTour t(random_points(15, seed));
    std::vector<int> subset(15);
    std::iota(subset.begin(), subset.end(), 1);
    std::vector<int> with(15), without(15);
    std::vector<char> used(15);
    order_tour(t.distances(), subset.data(), 15, with.data(), used.data());
    order_tour(t.distances(), subset.data(), 15, without.data(), used.data(), 0);
    const double a = tour_length(t.distances(), with.data(), 15), b = tour_length(t.distances(), without.data(), 15);
    EXPECT_LE(a, b + 1e-9) << "seed " << seed;
    longer += b > a + 1e-9;
  }
  EXPECT_GT(longer, 0) << "two_opt_rounds = 0 changed no tour";
  // A closed tour of 8 goals, exact or by the heuristic (exact_up_to = 0):
  // the heuristic is never shorter, and longer on some sets.
  int worse = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const PlaneTour t(random_points(8, 100u + seed));
    const double exact = t.closed_length(order_closed_tour(t.distances(), 8));
    const double heuristic = t.closed_length(order_closed_tour(t.distances(), 8, 0));
    EXPECT_LE(exact, heuristic + 1e-9) << "seed " << seed;
    worse += heuristic > exact + 1e-9;
  }
  EXPECT_GT(worse, 0) << "exact_up_to = 0 changed no closed tour";
}

TEST(TourTest, TourLengthByHand) {
  const PlaneTour t({{0, 0}, {3, 4}, {3, 0}});
  const int order[2] = {1, 2};
  EXPECT_DOUBLE_EQ(tour_length(t.distances(), order, 2), 5.0 + 4.0);
  EXPECT_DOUBLE_EQ(tour_length(t.distances(), order, 0), 0.0);
}

TEST(TourTest, ClosedTourIsExactUpToTwelveGoals) {
  for (int n : {1, 2, 5, 8}) {
    const auto p = random_points(n, 7u + static_cast<unsigned>(n));
    const PlaneTour t(p);
    const std::vector<int> order = order_closed_tour(t.distances(), n);
    ASSERT_EQ(order.size(), static_cast<std::size_t>(n));
    // Brute force over every permutation.
    std::vector<int> perm(static_cast<std::size_t>(n));
    std::iota(perm.begin(), perm.end(), 1);
    double best = 1e300;
    do best = std::min(best, t.closed_length(perm));
    while (std::next_permutation(perm.begin(), perm.end()));
    EXPECT_NEAR(t.closed_length(order), best, 1e-9) << n << " goals";
  }
  EXPECT_TRUE(order_closed_tour(PlaneTour({{0, 0}}).distances(), 0).empty());
}

TEST(TourTest, ClosedTourBeyondTwelveGoalsLeavesNoImprovingReversal) {
  for (int n : {13, 16, 20}) {
    const PlaneTour t(random_points(n, 40u + static_cast<unsigned>(n)));
    const std::vector<int> order = order_closed_tour(t.distances(), n);
    std::vector<int> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> goals(static_cast<std::size_t>(n));
    std::iota(goals.begin(), goals.end(), 1);
    ASSERT_EQ(sorted, goals) << n << " goals";
    const double len = t.closed_length(order);
    for (std::size_t i = 0; i + 1 < order.size(); ++i)
      for (std::size_t j = i + 1; j < order.size(); ++j) {
        std::vector<int> o = order;
        std::reverse(o.begin() + static_cast<long>(i), o.begin() + static_cast<long>(j) + 1);
        EXPECT_GE(t.closed_length(o), len - 1e-6) << n << " goals, reversal " << i << ".." << j;
      }
  }
}

TEST(TourTest, ClosedTourBeyondTwelveGoalsFindsTheCircle) {
  // 24 points on a circle, the start among them: the optimum is the circle,
  // and nearest neighbour + 2-opt finds it.
  const int n = 24;
  std::vector<std::pair<double, double>> p;
  const double kPi = 3.14159265358979323846;
  for (int k = 0; k <= n; ++k) {
    const int at = (k * 7) % (n + 1);  // the goals' ids do not follow the circle
    p.push_back({10.0 * std::cos(2 * kPi * at / (n + 1)), 10.0 * std::sin(2 * kPi * at / (n + 1))});
  }
  const PlaneTour t(p);
  const std::vector<int> order = order_closed_tour(t.distances(), n);
  const double circle = (n + 1) * 2 * 10.0 * std::sin(kPi / (n + 1));
  EXPECT_NEAR(t.closed_length(order), circle, 1e-6);
}

}  // namespace
}  // namespace mission
}  // namespace gather
