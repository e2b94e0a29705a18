// BAP, Balanced Area Partition (seed paper: "BAP method uses FMM, extending
// N_w wavefront until cover all the free space").
//
// Reading built here: wavefronts are extended one after the other. Each starts
// at the uncovered cell farthest from the OC (geodesic, one FMM from the OC),
// so the far ends of the building are served first and the last segment
// holds the OC, and grows by FMM over uncovered cells until it holds its
// share (uncovered area / wavefronts still to go). A front never takes a cell
// that would cut the uncovered space in two (a local test on the cell's
// 8-neighbourhood, then a bounded search that either finds both sides joined
// or takes a small closed pocket whole), so no pocket is left behind: the
// uncovered space stays one 4-connected piece and the last wavefront takes all
// of it. A front boxed into a pocket is undone and started again from the next
// farthest cell away from narrow spots (up to kMaxRestarts times; then the
// best attempt is kept, which is where the area CV rises above 0).
//
// Maps with more than PartitionParams::bap_coarse_cells reachable cells (the
// campus): the wavefronts run on a coarse copy (blocks of f x f cells at least
// half reachable, each weighted by its reachable cells, so shares are counted
// in real area); the full-resolution labels are the block labels, and cells
// of partial blocks, or cut off from their segment by a wall, go to the
// segment next to them.
#include <algorithm>
#include <cmath>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/partition/front_growth.hpp"
#include "methods.hpp"

namespace gather {
namespace partition {
namespace {

constexpr int kMaxRestarts = 8;
// A wavefront starts where clearance >= this many cells: not in the one-cell
// nooks and threads of scanned maps, where it would be boxed in at once.
constexpr double kSeedClearance = 3.0;

// Region cells, farthest first (counting sort on `dist` in steps; ties by index).
std::vector<uint32_t> farthest_first(const std::vector<uint8_t>& region, const std::vector<double>& dist, double step) {
  const std::size_t n = region.size();
  std::size_t max_key = 0, count = 0;
  std::vector<uint32_t> key(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!region[i]) continue;
    ++count;
    key[i] = std::isfinite(dist[i]) ? static_cast<uint32_t>(dist[i] / step) : 0;
    max_key = std::max<std::size_t>(max_key, key[i]);
  }
  std::vector<uint32_t> start(max_key + 2, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (region[i]) ++start[max_key - key[i] + 1];
  for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  std::vector<uint32_t> order(count);
  for (std::size_t i = 0; i < n; ++i)
    if (region[i]) order[start[max_key - key[i]]++] = static_cast<uint32_t>(i);
  return order;
}

// The sequential wavefronts on one grid (fine or coarse). `total` = weight of
// all region cells. Writes labels 1..workers and the start cell of each.
void sequential_fronts(FrontGrowth& growth, const std::vector<uint32_t>& order, const std::vector<uint8_t>& seed_ok,
                       std::size_t total, int workers, std::vector<int32_t>& labels, std::vector<std::size_t>& seeds) {
  const std::size_t n = static_cast<std::size_t>(growth.width()) * growth.height();
  growth.reset_available();
  labels.assign(n, 0);
  seeds.clear();
  std::size_t remaining = total;
  std::size_t next = 0;                // order[..next) are all covered
  std::vector<uint8_t> no_seed(n, 0);  // cells of undone segments: not a start again
  for (int k = 1; k <= workers; ++k) {
    while (next < order.size() && !growth.available(order[next])) ++next;
    if (k == workers) {
      seeds.push_back(order[std::min(next, order.size() - 1)]);
      growth.take_rest(k, labels);
      break;
    }
    const std::size_t fronts_left = static_cast<std::size_t>(workers - k + 1);
    const std::size_t quota = std::max<std::size_t>(1, remaining / fronts_left);
    // A front boxed in by earlier ones (it ends in a pocket reached through a
    // one-cell gap) is undone and started again from the next farthest cell;
    // the pocket is left for a front that reaches it from outside and takes
    // it whole. After kMaxRestarts the small segment is kept.
    std::size_t got = 0, seed = 0, best_got = 0, best_seed = order[next];
    for (int attempt = 0;; ++attempt) {
      std::size_t pick = next;
      // The first start is the farthest cell; restarts also avoid narrow spots.
      while (pick < order.size() && !(growth.available(order[pick]) && (attempt == 0 || seed_ok[order[pick]]) &&
                                      !no_seed[order[pick]] && growth.removable(order[pick])))
        ++pick;
      if (pick >= order.size()) {
        pick = next;
        while (pick < order.size() &&
               !(growth.available(order[pick]) && !no_seed[order[pick]] && growth.removable(order[pick])))
          ++pick;
      }
      if (pick >= order.size()) {  // no fresh start left: regrow the best attempt
        if (attempt == 0) best_seed = order[next];
        got = growth.grow_quota(best_seed, quota, k, labels);
        seed = best_seed;
        break;
      }
      seed = order[pick];
      got = growth.grow_quota(seed, quota, k, labels);
      if (got > best_got) best_got = got, best_seed = seed;
      if (got >= quota - quota / 50) break;
      for (std::size_t i = 0; i < n; ++i)
        if (labels[i] == k) no_seed[i] = 1;
      growth.release(k, labels);
      if (attempt >= kMaxRestarts) {  // keep the best of the attempts
        got = growth.grow_quota(best_seed, quota, k, labels);
        seed = best_seed;
        break;
      }
    }
    seeds.push_back(seed);
    remaining -= std::min(remaining, got);
  }
}

// Clears every region cell outside the largest 4-connected component.
void keep_largest_component(int w, int h, std::vector<uint8_t>& region) {
  const std::size_t n = region.size();
  std::vector<uint32_t> comp(n, 0);
  std::vector<std::size_t> stack;
  uint32_t id = 0, best = 0;
  std::size_t best_size = 0;
  for (std::size_t s = 0; s < n; ++s) {
    if (!region[s] || comp[s]) continue;
    comp[s] = ++id;
    stack.assign(1, s);
    std::size_t size = 0;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      ++size;
      const std::size_t col = i % static_cast<std::size_t>(w);
      const std::size_t nb[4] = {col > 0 ? i - 1 : i, col + 1 < static_cast<std::size_t>(w) ? i + 1 : i,
                                 i >= static_cast<std::size_t>(w) ? i - w : i, i + w < n ? i + w : i};
      for (std::size_t j : nb)
        if (region[j] && !comp[j]) comp[j] = id, stack.push_back(j);
    }
    if (size > best_size) best_size = size, best = id;
  }
  (void)h;
  for (std::size_t i = 0; i < n; ++i) region[i] = comp[i] == best && best ? 1 : 0;
}

// Keeps, per label, its largest 4-connected piece; the other pieces are given
// to the neighbouring segment they touch (breadth-first from labelled cells).
void reconnect(const OccupancyGrid& g, const std::vector<uint8_t>& reachable, int workers, std::vector<int32_t>& labels) {
  const std::size_t n = g.size(), w = static_cast<std::size_t>(g.width());
  std::vector<uint32_t> piece(n, 0);
  std::vector<std::size_t> piece_size;
  piece_size.reserve(4 * static_cast<std::size_t>(workers) + 1);
  piece_size.push_back(0);
  std::vector<std::size_t> stack;
  for (std::size_t s = 0; s < n; ++s) {
    if (labels[s] <= 0 || piece[s]) continue;
    const uint32_t id = static_cast<uint32_t>(piece_size.size());
    piece_size.push_back(0);
    piece[s] = id;
    stack.assign(1, s);
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      ++piece_size[id];
      const std::size_t col = i % w;
      const std::size_t nb[4] = {col > 0 ? i - 1 : i, col + 1 < w ? i + 1 : i, i >= w ? i - w : i, i + w < n ? i + w : i};
      for (std::size_t j : nb)
        if (!piece[j] && labels[j] == labels[i]) piece[j] = id, stack.push_back(j);
    }
  }
  std::vector<uint32_t> best(static_cast<std::size_t>(workers) + 1, 0);
  std::vector<std::size_t> best_size(best.size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (labels[i] <= 0) continue;
    const uint32_t id = piece[i];
    if (piece_size[id] > best_size[labels[i]]) best_size[labels[i]] = piece_size[id], best[labels[i]] = id;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (labels[i] > 0 && piece[i] != best[labels[i]]) labels[i] = 0;
  std::vector<uint32_t> queue;
  for (std::size_t i = 0; i < n; ++i)
    if (labels[i] > 0) queue.push_back(static_cast<uint32_t>(i));
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::size_t i = queue[head];
    const std::size_t col = i % w;
    const std::size_t nb[4] = {col > 0 ? i - 1 : i, col + 1 < w ? i + 1 : i, i >= w ? i - w : i, i + w < n ? i + w : i};
    for (std::size_t j : nb)
      if (reachable[j] && labels[j] == 0) labels[j] = labels[i], queue.push_back(static_cast<uint32_t>(j));
  }
}

}  // namespace

void run_bap(const MethodInput& in, PartitionResult& out) {
  const OccupancyGrid& grid = in.grid;
  const std::size_t n = grid.size();
  const std::size_t nw = static_cast<std::size_t>(in.workers);

  // Geodesic distance from the OC orders the wavefront starts.
  fmm::FastMarching fm(grid);
  fmm::SolveOptions opt;
  opt.labels = false;
  fm.solve({fmm::Source::at_cell(in.oc)}, opt);
  std::vector<double> dist;
  fm.copy_times(dist);

  int f = 1;
  while (in.reachable_cells / static_cast<std::size_t>(f * f) > in.params.bap_coarse_cells) ++f;
  while (f > 1 && in.reachable_cells / static_cast<std::size_t>(f * f) < 16 * nw) --f;

  out.seeds.clear();
  if (f == 1) {
    FrontGrowth growth(grid.width(), grid.height(), grid.resolution(), in.reachable);
    std::vector<std::size_t> seeds;
    std::vector<uint8_t> seed_ok(n, 0);
    for (std::size_t i = 0; i < n; ++i) seed_ok[i] = in.clearance[i] >= kSeedClearance * grid.resolution();
    sequential_fronts(growth, farthest_first(in.reachable, dist, grid.resolution() / 4.0), seed_ok,
                      in.reachable_cells, in.workers, out.labels, seeds);
    for (std::size_t s : seeds) out.seeds.push_back(grid.cell(s));
    return;
  }

  // Coarse copy: a block is a region cell when it holds a reachable cell; its
  // weight is the number it holds, its distance the smallest among them.
  const int cw = (grid.width() + f - 1) / f, ch = (grid.height() + f - 1) / f;
  const std::size_t cn = static_cast<std::size_t>(cw) * ch;
  std::vector<uint32_t> weight(cn, 0);
  std::vector<double> cdist(cn, fmm::kUnreached);
  std::vector<uint32_t> far_cell(cn, 0);
  std::vector<double> far_dist(cn, -1.0);
  for (int r = 0; r < grid.height(); ++r)
    for (int c = 0; c < grid.width(); ++c) {
      const std::size_t i = grid.index(Cell{r, c});
      if (!in.reachable[i]) continue;
      const std::size_t b = static_cast<std::size_t>(r / f) * cw + c / f;
      ++weight[b];
      cdist[b] = std::min(cdist[b], dist[i]);
      if (dist[i] > far_dist[b]) far_dist[b] = dist[i], far_cell[b] = static_cast<uint32_t>(i);
    }
  // Region: blocks at least half reachable (a block that straddles a thin
  // wall would join both sides), their largest 4-connected component.
  const uint32_t need = static_cast<uint32_t>((f * f + 1) / 2);
  std::vector<uint8_t> region(cn, 0);
  for (std::size_t b = 0; b < cn; ++b) region[b] = weight[b] >= need;
  keep_largest_component(cw, ch, region);
  std::size_t total = 0;
  for (std::size_t b = 0; b < cn; ++b) total += region[b] ? weight[b] : 0;
  FrontGrowth growth(cw, ch, grid.resolution() * f, region);
  growth.set_weights(weight);
  std::vector<int32_t> coarse_labels;
  std::vector<std::size_t> seeds;
  std::vector<uint8_t> seed_ok(cn, 0);
  for (std::size_t b = 0; b < cn; ++b) seed_ok[b] = far_dist[b] >= 0.0;
  sequential_fronts(growth, farthest_first(region, cdist, grid.resolution() * f / 4.0), seed_ok, total, in.workers,
                    coarse_labels, seeds);
  out.labels.assign(n, 0);
  for (int r = 0; r < grid.height(); ++r)
    for (int c = 0; c < grid.width(); ++c) {
      const std::size_t i = grid.index(Cell{r, c});
      if (in.reachable[i]) out.labels[i] = coarse_labels[static_cast<std::size_t>(r / f) * cw + c / f];
    }
  reconnect(grid, in.reachable, in.workers, out.labels);
  for (std::size_t s : seeds) out.seeds.push_back(grid.cell(far_cell[s]));
}

}  // namespace partition
}  // namespace gather
