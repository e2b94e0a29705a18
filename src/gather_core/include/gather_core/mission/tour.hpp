#pragma once
// A worker's tour through its goals: an open path from its position,
// nearest neighbour then 2-opt on geodesic distances.
#include <vector>

namespace gather {
namespace mission {

// Visiting order of the goals `subset` (indices into `from_start` and
// `between`): from_start[i] [m] is the distance from the start to goal i,
// between[i][j] [m] from goal i to goal j (rows may hold further columns).
// Open path (no return); 2-opt moves are judged on between[][] as given
// (FMM distances are nearly symmetric). Returns `subset` reordered.
std::vector<int> order_tour(const std::vector<double>& from_start, const std::vector<std::vector<double>>& between,
                            const std::vector<int>& subset);

// Length [m] of the open path start -> order[0] -> ... -> order.back().
double tour_length(const std::vector<double>& from_start, const std::vector<std::vector<double>>& between,
                   const std::vector<int>& order);

}  // namespace mission
}  // namespace gather
