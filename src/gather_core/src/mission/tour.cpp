#include "gather_core/mission/tour.hpp"

#include <algorithm>
#include <limits>

namespace gather {
namespace mission {

double tour_length(const TourDistances& d, const int* order, std::size_t n) {
  double len = 0.0;
  for (std::size_t i = 0; i < n; ++i) len += d.from(i == 0 ? -1 : order[i - 1], order[i]);
  return len;
}

void order_tour(const TourDistances& d, const int* subset, std::size_t n, int* order, char* used) {
  std::fill(used, used + n, 0);
  for (std::size_t step = 0; step < n; ++step) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t pick = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (used[i]) continue;
      const double dist = d.from(step == 0 ? -1 : order[step - 1], subset[i]);
      if (pick == n || dist < best) best = dist, pick = i;
    }
    used[pick] = 1;
    order[step] = subset[pick];
  }
  // 2-opt on the open path: reverse order[i..j] when that shortens it.
  for (int round = 0; round < 100; ++round) {
    bool improved = false;
    for (std::size_t i = 0; i + 1 < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const int before = i == 0 ? -1 : order[i - 1];
        const double old_cost = d.from(before, order[i]) + (j + 1 < n ? d.from(order[j], order[j + 1]) : 0.0);
        const double new_cost = d.from(before, order[j]) + (j + 1 < n ? d.from(order[i], order[j + 1]) : 0.0);
        if (new_cost < old_cost - 1e-9) {
          std::reverse(order + i, order + j + 1);
          improved = true;
        }
      }
    if (!improved) break;
  }
}

}  // namespace mission
}  // namespace gather
