#pragma once
// Tours through points, the one solver of the project:
// - a worker's tour through its goals: an open path from its position, nearest
//   neighbour then 2-opt on geodesic distances; allocation-free, the caller
//   owns every buffer (the worker policy decides in its control step);
// - a collector's closed route through its meeting areas (the planner's
//   route_builder): exact up to kExactClosedTourGoals, else nearest neighbour
//   then 2-opt.
#include <cstddef>
#include <vector>

namespace gather {
namespace mission {

// from_start[i] [m]: from the start to goal i; between[i * stride + j] [m]:
// from goal i to goal j (a row may hold further columns after the goals).
struct TourDistances {
  const double* from_start = nullptr;
  const double* between = nullptr;
  std::size_t stride = 0;
  double from(int a, int b) const {  // a < 0: the start
    return a < 0 ? from_start[b] : between[static_cast<std::size_t>(a) * stride + static_cast<std::size_t>(b)];
  }
};

// The defaults of the solver's limits (ProtocolParams::two_opt_rounds,
// PlannerOptions::exact_route_stops): 2-opt passes over an open tour at most
// (a worker's tour: bounded work per control step; tours of tens of goals
// settle in a few passes), and closed tours of up to this many goals solved
// exactly (Held-Karp: 2^n * n^2 steps, 0.6 M at 12; at most kMaxExactGoals).
constexpr int kOpenTourTwoOptRounds = 100;
constexpr int kExactClosedTourGoals = 12;
constexpr int kMaxExactGoals = 16;

// Writes into order[0..n) the visiting order of the n goals `subset`:
// nearest neighbour (ties: the first in `subset`), then 2-opt moves judged
// on the distances as given (FMM distances are nearly symmetric), at most
// `two_opt_rounds` passes. `used` is scratch of n bytes.
void order_tour(const TourDistances& d, const int* subset, std::size_t n, int* order, char* used,
                int two_opt_rounds = kOpenTourTwoOptRounds);

// The visiting order of goals 1..n of the closed tour start -> ... -> start,
// where point 0 of `d` is the start (d.from(-1, k) must equal d.from(0, k)):
// exact by dynamic programming up to `exact_up_to` goals (at most
// kMaxExactGoals), else nearest neighbour then 2-opt until no move shortens
// it. Allocates (a planning step, not a control step).
std::vector<int> order_closed_tour(const TourDistances& d, int n, int exact_up_to = kExactClosedTourGoals);

// Length [m] of the open path start -> order[0] -> ... -> order[n - 1].
double tour_length(const TourDistances& d, const int* order, std::size_t n);

}  // namespace mission
}  // namespace gather
