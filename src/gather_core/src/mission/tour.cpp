#include "gather_core/mission/tour.hpp"

#include <algorithm>
#include <limits>

namespace gather {
namespace mission {

double tour_length(const std::vector<double>& from_start, const std::vector<std::vector<double>>& between,
                   const std::vector<int>& order) {
  double len = 0.0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t o = static_cast<std::size_t>(order[i]);
    len += i == 0 ? from_start[o] : between[static_cast<std::size_t>(order[i - 1])][o];
  }
  return len;
}

std::vector<int> order_tour(const std::vector<double>& from_start, const std::vector<std::vector<double>>& between,
                            const std::vector<int>& subset) {
  const std::size_t n = subset.size();
  std::vector<int> order;
  order.reserve(n);
  std::vector<char> used(n, 0);
  for (std::size_t step = 0; step < n; ++step) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t pick = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (used[i]) continue;
      const std::size_t g = static_cast<std::size_t>(subset[i]);
      const double dist = order.empty() ? from_start[g] : between[static_cast<std::size_t>(order.back())][g];
      if (pick == n || dist < best) best = dist, pick = i;
    }
    used[pick] = 1;
    order.push_back(subset[pick]);
  }
  // 2-opt on the open path: reverse order[i..j] when that shortens it.
  auto d = [&](int a, int b) { return a < 0 ? from_start[static_cast<std::size_t>(b)]
                                            : between[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)]; };
  for (int round = 0; round < 100; ++round) {
    bool improved = false;
    for (std::size_t i = 0; i + 1 < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const int before = i == 0 ? -1 : order[i - 1];
        const double old_cost = d(before, order[i]) + (j + 1 < n ? d(order[j], order[j + 1]) : 0.0);
        const double new_cost = d(before, order[j]) + (j + 1 < n ? d(order[i], order[j + 1]) : 0.0);
        if (new_cost < old_cost - 1e-9) {
          std::reverse(order.begin() + static_cast<long>(i), order.begin() + static_cast<long>(j) + 1);
          improved = true;
        }
      }
    if (!improved) break;
  }
  return order;
}

}  // namespace mission
}  // namespace gather
