#include "gather_core/mission/tour.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "gather_core/numeric.hpp"

namespace gather {
namespace mission {
namespace {

// Nearest neighbour from the start through the n goals `subset` into order[0..n).
void nearest_neighbour(const TourDistances& d, const int* subset, std::size_t n, int* order, char* used) {
  std::fill(used, used + n, 0);
  for (std::size_t step = 0; step < n; ++step) {
    double best = kInf;
    std::size_t pick = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (used[i]) continue;
      const double dist = d.from(step == 0 ? -1 : order[step - 1], subset[i]);
      if (pick == n || dist < best) best = dist, pick = i;
    }
    used[pick] = 1;
    order[step] = subset[pick];
  }
}

// 2-opt: reverses order[i..j] while that shortens the path by more than 1 nm,
// at most `max_rounds` passes. The path starts at the start and, when
// `back` >= 0, ends at goal `back` (a closed tour); otherwise it is open.
void two_opt(const TourDistances& d, int* order, std::size_t n, int back, int max_rounds) {
  auto after_last = [&](int last) { return back >= 0 ? d.from(last, back) : 0.0; };
  for (int round = 0; round < max_rounds; ++round) {
    bool improved = false;
    for (std::size_t i = 0; i + 1 < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const int before = i == 0 ? -1 : order[i - 1];
        const double old_cost =
            d.from(before, order[i]) + (j + 1 < n ? d.from(order[j], order[j + 1]) : after_last(order[j]));
        const double new_cost =
            d.from(before, order[j]) + (j + 1 < n ? d.from(order[i], order[j + 1]) : after_last(order[i]));
        if (new_cost < old_cost - 1e-9) {
          std::reverse(order + i, order + j + 1);
          improved = true;
        }
      }
    if (!improved) break;
  }
}

// Held-Karp over goals 1..n (n <= kMaxExactGoals): the shortest closed
// tour from goal 0, the start.
std::vector<int> exact_closed_tour(const TourDistances& d, int n) {
  const int full = 1 << n;
  std::vector<double> best(static_cast<std::size_t>(full) * n, kInf);
  std::vector<int> prev(best.size(), -1);
  for (int j = 0; j < n; ++j) best[(1u << j) * n + j] = d.from(0, j + 1);
  for (int mask = 1; mask < full; ++mask)
    for (int j = 0; j < n; ++j) {
      const double b = best[static_cast<std::size_t>(mask) * n + j];
      if (!(mask & (1 << j)) || b == kInf) continue;
      for (int k = 0; k < n; ++k) {
        if (mask & (1 << k)) continue;
        const std::size_t to = static_cast<std::size_t>(mask | (1 << k)) * n + k;
        if (b + d.from(j + 1, k + 1) < best[to]) best[to] = b + d.from(j + 1, k + 1), prev[to] = j;
      }
    }
  int last = 0;
  double total = kInf;
  for (int j = 0; j < n; ++j) {
    const double t = best[static_cast<std::size_t>(full - 1) * n + j] + d.from(j + 1, 0);
    if (t < total) total = t, last = j;
  }
  std::vector<int> order;
  int mask = full - 1;
  while (last >= 0) {
    order.push_back(last + 1);
    const int p = prev[static_cast<std::size_t>(mask) * n + last];
    mask &= ~(1 << last);
    last = p;
  }
  std::reverse(order.begin(), order.end());
  return order;
}

}  // namespace

double tour_length(const TourDistances& d, const int* order, std::size_t n) {
  double len = 0.0;
  for (std::size_t i = 0; i < n; ++i) len += d.from(i == 0 ? -1 : order[i - 1], order[i]);
  return len;
}

void order_tour(const TourDistances& d, const int* subset, std::size_t n, int* order, char* used, int two_opt_rounds) {
  nearest_neighbour(d, subset, n, order, used);
  two_opt(d, order, n, -1, two_opt_rounds);
}

std::vector<int> order_closed_tour(const TourDistances& d, int n, int exact_up_to) {
  if (n <= 0) return {};
  if (n <= std::min(exact_up_to, kMaxExactGoals)) return exact_closed_tour(d, n);
  std::vector<int> goals(static_cast<std::size_t>(n)), order(goals.size());
  for (int k = 0; k < n; ++k) goals[static_cast<std::size_t>(k)] = k + 1;
  std::vector<char> used(goals.size());
  nearest_neighbour(d, goals.data(), goals.size(), order.data(), used.data());
  two_opt(d, order.data(), order.size(), 0, std::numeric_limits<int>::max());
  return order;
}

}  // namespace mission
}  // namespace gather
