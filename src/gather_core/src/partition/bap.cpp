// BAP, Balanced Area Partition (seed paper: "BAP method uses FMM, extending
// N_w wavefront until cover all the free space").
//
// Reading built here: wavefronts are extended one after the other. Each starts
// at the uncovered cell farthest from the OC (geodesic, one FMM from the OC),
// so the far ends of the building are served first and the last segment
// holds the OC, and grows by FMM over uncovered cells until it holds its
// share (uncovered area / wavefronts still to go). A front never takes a cell
// that would cut the uncovered space in two (a local test on the cell's
// 8-neighbourhood), so no pocket is ever left behind: the uncovered space
// stays one 4-connected piece and the last wavefront takes all of it. Areas
// come out equal to the cell, except where a front is boxed in early.
#include <algorithm>
#include <cmath>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/partition/front_growth.hpp"
#include "methods.hpp"

namespace gather {
namespace partition {

namespace {
constexpr int kMaxRestarts = 6;
}  // namespace

void run_bap(const MethodInput& in, PartitionResult& out) {
  const OccupancyGrid& grid = in.grid;
  const std::size_t n = grid.size();

  // Geodesic distance from the OC orders the wavefront starts.
  fmm::FastMarching fm(grid);
  fmm::SolveOptions opt;
  opt.labels = false;
  fm.solve({fmm::Source::at_cell(in.oc)}, opt);
  std::vector<double> dist;
  fm.copy_times(dist);

  // Reachable cells, farthest first (counting sort on 1/4-cell steps; ties by index).
  const double step = grid.resolution() / 4.0;
  std::size_t max_key = 0;
  std::vector<uint32_t> key(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!in.reachable[i]) continue;
    key[i] = static_cast<uint32_t>(dist[i] / step);
    max_key = std::max<std::size_t>(max_key, key[i]);
  }
  std::vector<uint32_t> start(max_key + 2, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (in.reachable[i]) ++start[max_key - key[i] + 1];
  for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  std::vector<uint32_t> order(in.reachable_cells);
  for (std::size_t i = 0; i < n; ++i)
    if (in.reachable[i]) order[start[max_key - key[i]]++] = static_cast<uint32_t>(i);

  FrontGrowth growth(grid.width(), grid.height(), grid.resolution(), in.reachable);
  growth.reset_available();
  out.labels.assign(n, 0);
  out.seeds.clear();
  std::size_t remaining = in.reachable_cells;
  std::size_t next = 0;  // order[..next) are all covered
  std::vector<uint8_t> no_seed(n, 0);  // cells of undone segments: not a start again
  for (int k = 1; k <= in.workers; ++k) {
    while (next < order.size() && !growth.available(order[next])) ++next;
    if (k == in.workers) {
      out.seeds.push_back(grid.cell(order[std::min(next, order.size() - 1)]));
      growth.take_rest(k, out.labels);
      break;
    }
    const std::size_t fronts_left = static_cast<std::size_t>(in.workers - k + 1);
    const std::size_t quota = std::max<std::size_t>(1, remaining / fronts_left);
    // A front boxed in by earlier ones (it ends in a pocket reached through a
    // one-cell gap) is undone and started again from the next farthest cell;
    // the pocket is left for a front that reaches it from outside and takes
    // it whole. After kMaxRestarts the small segment is kept.
    std::size_t got = 0, seed = 0;
    for (int attempt = 0;; ++attempt) {
      std::size_t pick = next;
      while (pick < order.size() &&
             !(growth.available(order[pick]) && !no_seed[order[pick]] && growth.removable(order[pick])))
        ++pick;
      if (pick >= order.size()) {
        pick = next;
        while (pick < order.size() && !(growth.available(order[pick]) && growth.removable(order[pick]))) ++pick;
        if (pick >= order.size()) pick = next;
      }
      seed = order[pick];
      got = growth.grow_quota(seed, quota, k, out.labels);
      if (got >= quota - quota / 50 || attempt >= kMaxRestarts) break;
      for (std::size_t i = 0; i < n; ++i)
        if (out.labels[i] == k) no_seed[i] = 1;
      growth.release(k, out.labels);
    }
    out.seeds.push_back(grid.cell(seed));
    remaining -= got;
  }
}

}  // namespace partition
}  // namespace gather
