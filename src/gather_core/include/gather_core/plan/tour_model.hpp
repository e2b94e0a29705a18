#pragma once
// The expected length of a worker's tour through n random goals of its
// segment (docs/planner.md, "Estimate model"), read by the estimate, the
// collector groups' work balance and the association.
#include <algorithm>
#include <cmath>
#include <vector>

#include "gather_core/plan/worker_graph.hpp"

namespace gather {
namespace plan {

// The mean distance between two random points of an open square of side 1.
constexpr double kSquarePairDistance = 0.5214;

// Expected length [m] of a tour from a depot through n random goals of a
// region and back to where the data is delivered, whose cells lie at mean
// distance `out` [m] from the depot and `back` [m] from the delivery place:
// L(n) = out + back + c S (n - 1) / sqrt(n) for n >= 1. One goal costs the
// trip out and back; a second adds about the mean distance between two
// random points (0.5214 sqrt(A) in an open square of area A; the formula
// gives 0.50 sqrt(A)); for many goals it tends to the
// Beardwood-Halton-Hammersley law c sqrt(n A). S is the region's effective
// side: sqrt(A) for an open square, and in general its measured mean
// walking distance between two cells over 0.5214, so that walls and doors
// (rooms of one segment joined through a corridor) lengthen the walks
// between goals as they do on the map. (BHH alone, with the Euclidean side,
// assumes a central depot, open space and many goals: with 1-3 goals per
// segment and the depot at the segment's edge it came out ~40% short of the
// simulated tours; with the Euclidean side and one mean distance for both
// legs, ~10% short of the simulated latency.) Fractional n < 1 scales the
// trip out and back.
struct TourModel {
  double area = 0.0;  // [m^2]
  double side = 0.0;  // [m] effective side S
  double out = 0.0;   // [m] mean distance from the depot to the region's cells
  double back = 0.0;  // [m] mean distance from the region's cells to the delivery place
  double c = 0.7124;
  // Quantiles of the distance from the depot to the region's cells
  // (WorkerSegment::home_quantiles; empty: unknown).
  std::vector<double> out_quantiles;
  double trip() const { return out + back; }
  // The share F(d) of the region's cells within `d` [m] of the depot, from
  // the quantiles (linear between them); without quantiles, d / out up to 1.
  double within(double d) const {
    const std::size_t n = out_quantiles.size();
    if (n < 2) return out > 0 ? std::clamp(d / out, 0.0, 1.0) : 1.0;
    if (d < out_quantiles.front()) return 0.0;
    if (d >= out_quantiles.back()) return 1.0;
    const std::size_t i = static_cast<std::size_t>(std::upper_bound(out_quantiles.begin(), out_quantiles.end(), d) -
                                                   out_quantiles.begin() - 1);
    const double lo = out_quantiles[i], hi = out_quantiles[i + 1];
    return (static_cast<double>(i) + (hi > lo ? (d - lo) / (hi - lo) : 1.0)) / static_cast<double>(n - 1);
  }
  double length(double n) const {
    if (n <= 0) return 0.0;
    if (n < 1) return trip() * n;
    return trip() + c * side * (n - 1.0) / std::sqrt(n);
  }
  // Of a tour through k goals, the number it measures within `budget` [m]
  // of leaving the depot: the first, when any of the k lies within reach
  // (probability 1 - (1 - F)^k, F = within(budget)), then one every
  // c S / sqrt(k) of the budget left past the mean distance `out` (the
  // goals lie that far apart along the tour, so with many goals and little
  // time the first few are reached sooner than a tour through that few
  // random goals would reach them); never more than the k F goals within
  // reach. Continuous in the budget.
  double measured(double k, double budget) const {
    if (k <= 0 || budget <= 0) return 0.0;
    const double f = within(budget), first = 1.0 - std::pow(1.0 - f, k);
    if (side <= 0) return k * f;
    return std::min(k * f, first + std::max(0.0, budget - out) * std::sqrt(k) / (c * side));
  }
  // The trip [m] that measures the first n goals of an optimal tour through
  // k goals and comes back: length(k) when n = k.
  double partial_length(double n, double k) const {
    if (n <= 0) return 0.0;
    if (n < 1 || k <= 1) return trip() * std::min(n, 1.0);
    return trip() + c * side * (n - 1.0) / std::sqrt(k);
  }
  // Largest number of goals (<= want) whose tour fits in `budget` [m].
  double goals_within(double budget, double want) const {
    if (budget <= 0) return 0.0;
    if (budget <= trip()) return std::min(want, trip() > 0 ? budget / trip() : want);
    if (side <= 0) return want;
    const double q = (budget - trip()) / (c * side);
    const double u = 0.5 * (q + std::sqrt(q * q + 4.0));  // sqrt(n): u^2 - q u - 1 = 0
    return std::clamp(u * u, 0.0, want);
  }
};

// An OC worker's first trip: from the OC's cell, where it starts the
// mission, instead of its home.
TourModel first_trip(const WorkerSegment& seg, TourModel m);

// The tour model of a segment's goals, from where its worker starts them:
// its home in the OC's coverage, back to the coverage (OC workers), or the
// segment's entry and back to it (workers of collectors). `c`: the tour
// constant (PlannerOptions::tsp_constant, dimensionless).
TourModel tour_model(const WorkerSegment& seg, bool from_coverage, double c);

}  // namespace plan
}  // namespace gather
