// BAP, Balanced Area Partition (seed paper: "BAP method uses FMM, extending
// N_w wavefront until cover all the free space").
//
// Reading built here, in three steps:
//  1. Wavefronts are extended one after the other. Each starts at the
//     uncovered cell farthest from the OC (geodesic, one FMM from the OC), so
//     the far ends of the building are served first and the last segment
//     holds the OC, and grows by FMM over uncovered cells until it holds its
//     share (uncovered area / wavefronts still to go). A front that starts in
//     a pocket smaller than half its share (closed off by earlier fronts)
//     gives the pocket to a segment next to it and starts again from the next
//     farthest cell. The last wavefront takes what is left.
//  2. What is left may be in pieces: its largest piece stays, the others go
//     to the segments next to them.
//  3. rebalance_areas() (rebalance.cpp) moves boundary cells between adjacent
//     segments until every area is within PartitionParams::bap_balance_tolerance of the mean,
//     keeping each segment 4-connected.
//
// Maps with more than PartitionParams::bap_coarse_cells reachable cells (the
// campus): the wavefronts run on a coarse copy (blocks of f x f cells at least
// half reachable, each weighted by its reachable cells, so shares are counted
// in real area); the full-resolution labels are the block labels, and cells
// of partial blocks, or cut off from their segment by a wall, go to the
// segment next to them; step 3 then runs at full resolution.
#include <algorithm>
#include <cmath>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/partition/front_growth.hpp"
#include "methods.hpp"

namespace gather {
namespace partition {
namespace {

// Rebalancing: stop when every area is within this fraction of the mean.

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
// all region cells. Writes labels 1..workers (the last label takes what is
// left, which may be in pieces) and the start cell of each.
void sequential_fronts(FrontGrowth& growth, const std::vector<uint32_t>& order, std::size_t total, int workers,
                       std::vector<int32_t>& labels, std::vector<std::size_t>& seeds) {
  const std::size_t n = static_cast<std::size_t>(growth.width()) * growth.height();
  growth.reset_available();
  labels.assign(n, 0);
  seeds.clear();
  std::size_t remaining = total;
  std::size_t next = 0;  // order[..next) are all covered
  const std::size_t w = static_cast<std::size_t>(growth.width());
  std::vector<uint32_t> taken;
  for (int k = 1; k <= workers; ++k) {
    while (next < order.size() && !growth.available(order[next])) ++next;
    if (k == workers || next >= order.size()) {
      seeds.push_back(order[std::min(next, order.size() - 1)]);
      growth.take_rest(k, labels);
      break;
    }
    // A front that starts in a pocket smaller than half its share (closed
    // off by earlier fronts) gives the pocket to a segment next to it and
    // starts again from the next farthest uncovered cell.
    std::size_t got = 0, seed = order[next];
    for (;;) {
      const int fronts = workers - k + 1;
      const std::size_t fronts_left = static_cast<std::size_t>(fronts);
      const std::size_t quota = std::max<std::size_t>(1, remaining / fronts_left);
      seed = order[next];
      got = growth.grow_quota(seed, quota, k, labels, &taken);
      if (got >= quota / 2) break;
      int32_t into = 0;
      for (std::size_t i = 0; i < taken.size() && into == 0; ++i) {
        const std::size_t c = taken[i], col = c % w;
        const std::size_t nb[4] = {col > 0 ? c - 1 : c, col + 1 < w ? c + 1 : c, c >= w ? c - w : c,
                                   c + w < n ? c + w : c};
        for (std::size_t j : nb)
          if (labels[j] > 0 && labels[j] != k) {
            into = labels[j];
            break;
          }
      }
      // Keep it when nothing is next to it, or when the fronts still to go
      // would run short of cells without it.
      if (into == 0 || remaining < got + fronts_left) break;
      std::size_t probe = next;
      while (probe < order.size() && !growth.available(order[probe])) ++probe;
      if (probe >= order.size()) break;
      for (uint32_t c : taken) labels[c] = into;
      remaining -= got;
      next = probe;
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
void reconnect(const OccupancyGrid& g, const std::vector<uint8_t>& reachable, int workers,
               std::vector<int32_t>& labels) {
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
      const std::size_t nb[4] = {col > 0 ? i - 1 : i, col + 1 < w ? i + 1 : i, i >= w ? i - w : i,
                                 i + w < n ? i + w : i};
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

// Keeps the largest 4-connected piece of `label` (the last, "the rest"
// segment: the only one that can be in pieces); its other pieces go to the
// segments next to them (breadth-first).
void reconnect_label(int width, int32_t label, std::vector<int32_t>& labels) {
  const std::size_t n = labels.size(), w = static_cast<std::size_t>(width);
  std::vector<uint32_t> piece(n, 0);
  std::vector<uint32_t> stack, cells;
  uint32_t id = 0, best = 0;
  std::size_t best_size = 0;
  for (std::size_t s = 0; s < n; ++s) {
    if (labels[s] != label || piece[s]) continue;
    piece[s] = ++id;
    stack.assign(1, static_cast<uint32_t>(s));
    std::size_t size = 0;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      ++size;
      cells.push_back(static_cast<uint32_t>(i));
      const std::size_t col = i % w;
      const std::size_t nb[4] = {col > 0 ? i - 1 : i, col + 1 < w ? i + 1 : i, i >= w ? i - w : i,
                                 i + w < n ? i + w : i};
      for (std::size_t j : nb)
        if (labels[j] == label && !piece[j]) piece[j] = id, stack.push_back(static_cast<uint32_t>(j));
    }
    if (size > best_size) best_size = size, best = id;
  }
  if (id <= 1) return;
  constexpr uint32_t kOrphan = 0xffffffffu;
  for (uint32_t c : cells)
    if (piece[c] != best) labels[c] = 0, piece[c] = kOrphan;
  std::vector<uint32_t> queue;
  for (uint32_t c : cells)
    if (piece[c] == kOrphan) queue.push_back(c);
  // Rounds: an orphan next to a labelled cell takes its label.
  std::vector<uint32_t> next_round;
  while (!queue.empty()) {
    next_round.clear();
    std::vector<std::pair<uint32_t, int32_t>> assign;
    for (uint32_t c : queue) {
      if (labels[c] != 0) continue;
      const std::size_t col = c % w;
      const std::size_t nb[4] = {col > 0 ? c - 1 : c, col + 1 < w ? c + 1 : c, c >= w ? c - w : c,
                                 c + w < n ? c + w : c};
      int32_t l = 0;
      for (std::size_t j : nb)
        if (labels[j] > 0) {
          l = labels[j];
          break;
        }
      if (l)
        assign.emplace_back(c, l);
      else
        next_round.push_back(c);
    }
    if (assign.empty()) break;  // cannot happen: the region is connected
    for (const auto& [c, l] : assign) labels[c] = l;
    queue.swap(next_round);
  }
}

}  // namespace

void run_bap(const MethodInput& in, PartitionResult& out) {
  const OccupancyGrid& grid = in.grid;
  const std::size_t nw = static_cast<std::size_t>(in.workers);

  // Geodesic distance from the OC orders the wavefront starts (the sweep's,
  // when it has one: the same march).
  Raster<double> marched;
  if (!in.oc_distance) {
    fmm::FastMarching fm(grid);
    fmm::SolveOptions opt;
    opt.labels = false;
    fm.solve({fmm::Source::at_cell(in.oc)}, opt);
    marched = fm.times();
  }
  const Raster<double>& dist = in.oc_distance ? *in.oc_distance : marched;

  int f = 1;
  while (in.reachable_cells / static_cast<std::size_t>(f * f) > in.params.bap_coarse_cells) ++f;
  while (f > 1 && in.reachable_cells / static_cast<std::size_t>(f * f) < 16 * nw) --f;

  out.seeds.clear();
  if (f == 1) {
    FrontGrowth growth(in.reachable);
    std::vector<std::size_t> seeds;
    const auto order = farthest_first(in.reachable.values(), dist.values(), grid.resolution() / 4.0);
    sequential_fronts(growth, order, in.reachable_cells, in.workers, out.labels.values(), seeds);
    reconnect_label(grid.width(), in.workers, out.labels.values());
    rebalance_areas(in.workers, out.labels, in.params.bap_balance_tolerance, in.params.bap_balance_passes,
                    in.params.bap_cut_searches);
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
  Mask region(GridFrame{cw, ch, grid.resolution() * f, grid.origin()});
  for (std::size_t b = 0; b < cn; ++b) region[b] = weight[b] >= need;
  keep_largest_component(cw, ch, region.values());
  std::size_t total = 0;
  for (std::size_t b = 0; b < cn; ++b) total += region[b] ? weight[b] : 0;
  FrontGrowth growth(region);
  growth.set_weights(weight);
  std::vector<int32_t> coarse_labels;
  std::vector<std::size_t> seeds;
  sequential_fronts(growth, farthest_first(region.values(), cdist, grid.resolution() * f / 4.0), total, in.workers,
                    coarse_labels, seeds);
  for (int r = 0; r < grid.height(); ++r)
    for (int c = 0; c < grid.width(); ++c) {
      const std::size_t i = grid.index(Cell{r, c});
      if (in.reachable[i]) out.labels[i] = coarse_labels[static_cast<std::size_t>(r / f) * cw + c / f];
    }
  reconnect(grid, in.reachable.values(), in.workers, out.labels.values());
  rebalance_areas(in.workers, out.labels, in.params.bap_balance_tolerance, in.params.bap_balance_passes,
                  in.params.bap_cut_searches);
  for (std::size_t s : seeds) out.seeds.push_back(grid.cell(far_cell[s]));
}

}  // namespace partition
}  // namespace gather
