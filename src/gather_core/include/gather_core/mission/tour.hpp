#pragma once
// A worker's tour through its goals: an open path from its position,
// nearest neighbour then 2-opt on geodesic distances. Allocation-free: the
// caller owns every buffer (the worker policy decides in its control step).
#include <cstddef>

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

// Writes into order[0..n) the visiting order of the n goals `subset`:
// nearest neighbour (ties: the first in `subset`), then 2-opt moves judged
// on the distances as given (FMM distances are nearly symmetric), at most
// 100 rounds. `used` is scratch of n bytes.
void order_tour(const TourDistances& d, const int* subset, std::size_t n, int* order, char* used);

// Length [m] of the open path start -> order[0] -> ... -> order[n - 1].
double tour_length(const TourDistances& d, const int* order, std::size_t n);

}  // namespace mission
}  // namespace gather
