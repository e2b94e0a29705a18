#include "gather_core/plan/walking_distances.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "gather_core/error.hpp"
#include "gather_core/grid/planning_grid.hpp"
#include "gather_core/grid/reachability.hpp"
#include "gather_core/mission/segment_window.hpp"
#include "gather_core/numeric.hpp"
#include "gather_core/plan/tour_model.hpp"

namespace gather {
namespace plan {
namespace {

// One LSD radix pass over the digits of kBits bits from `from_bit` up,
// skipping the digits that are the same in every key (`varying`: the bits
// that differ between keys).
template <int kBits>
void radix_passes(std::vector<uint64_t>& keys, std::vector<uint64_t>& spare, int from_bit, uint64_t varying) {
  constexpr uint64_t kMask = (uint64_t{1} << kBits) - 1;
  std::array<std::size_t, std::size_t{1} << kBits> at;
  for (int shift = from_bit; shift < 64; shift += kBits) {
    if (((varying >> shift) & kMask) == 0) continue;
    at.fill(0);
    for (const uint64_t k : keys) ++at[(k >> shift) & kMask];
    std::size_t sum = 0;
    for (std::size_t& a : at) {
      const std::size_t n = a;
      a = sum, sum += n;
    }
    for (const uint64_t k : keys) spare[at[(k >> shift) & kMask]++] = k;
    keys.swap(spare);
  }
}

// Sorts `keys` ascending by their bits from `from_bit` up (the bits below
// must already ascend with the position, as an index does, or be equal):
// an LSD radix sort, stable, that skips the passes whose digit is the same
// in every key; 8-bit digits for a few thousand keys (the counts stay in
// L1), 11-bit ones above. A segment's cells number thousands, and this is
// several times quicker than std::sort on them; all give the same order.
void sort_keys(std::vector<uint64_t>& keys, std::vector<uint64_t>& spare, int from_bit) {
  if (keys.size() < 256) {
    std::sort(keys.begin(), keys.end());
    return;
  }
  uint64_t any = 0, every = ~uint64_t{0};
  for (const uint64_t k : keys) any |= k, every &= k;
  spare.resize(keys.size());
  if (keys.size() < 8192)
    radix_passes<8>(keys, spare, from_bit, any ^ every);
  else
    radix_passes<11>(keys, spare, from_bit, any ^ every);
}

// Sorts distances (>= 0, or +inf) ascending: their bits sort like them.
void sort_distances(std::vector<double>& d, std::vector<uint64_t>& keys, std::vector<uint64_t>& spare) {
  keys.resize(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (!(d[i] >= 0.0) || std::signbit(d[i])) {  // not a distance: the general sort
      std::sort(d.begin(), d.end());
      return;
    }
    std::memcpy(&keys[i], &d[i], sizeof(double));
  }
  sort_keys(keys, spare, 0);
  for (std::size_t i = 0; i < d.size(); ++i) std::memcpy(&d[i], &keys[i], sizeof(double));
}

}  // namespace

float HomeWalks::Kept::at(Cell c) const {
  const int r = c.row - origin.row, q = c.col - origin.col;
  if (!times || r < 0 || q < 0 || r >= rows || q >= cols) return std::numeric_limits<float>::infinity();
  return (*times)[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(q)];
}

void HomeWalks::distances(Cell home, const std::vector<Cell>& cells, fmm::FastMarching& walk,
                          std::vector<double>& out) {
  out.resize(cells.size());
  const uint64_t key = static_cast<uint64_t>(static_cast<uint32_t>(home.row)) << 32 | static_cast<uint32_t>(home.col);
  Kept kept;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it = fields_.find(key);
    if (it != fields_.end()) kept = it->second;
  }
  // From the kept march, when it reached every cell (its finite times are
  // final), or when it reached all it could.
  if (kept.times) {
    bool all = true;
    for (std::size_t i = 0; i < cells.size() && all; ++i) {
      const float t = kept.at(cells[i]);
      out[i] = t < kInf ? static_cast<double>(t) : kInf;
      all = t < kInf || kept.whole;
    }
    if (all) return;
  }
  // Else marched until every cell is reached (on the whole map if one is
  // never reached), and kept if it reaches farther than the kept one: the
  // box of the cells it reached.
  fmm::SolveOptions so;
  so.labels = false;
  so.targets = cells;
  walk.solve({fmm::Source::at_cell(home)}, so);
  Kept now;
  // Not stopped at its cells (some was never reached): it reached all it could.
  now.whole = !walk.stats().stopped_early;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    out[i] = walk.time(cells[i]);
    if (out[i] < kInf) now.reach = std::max(now.reach, out[i]);
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    ++marched_;
    const auto it = fields_.find(key);
    if (it != fields_.end() && !now.whole && it->second.reach >= now.reach) return;  // as far kept meanwhile
    if (it == fields_.end() && budget_->full()) return;                              // no room for another
  }
  // The box of the reached cells: each row's first and last reached cell,
  // looked for from either end (not every cell's time compared), then the
  // box copied row by row.
  const float* t = walk.padded_times();
  auto row_of = [&](int r) { return t + walk.padded(Cell{r, 0}); };
  int r0 = -1, r1 = -1, c0 = walk.width(), c1 = -1;
  for (int r = 0; r < walk.height(); ++r) {
    const float* row = row_of(r);
    int first = 0, last = walk.width() - 1;
    while (first <= last && !(row[first] < kInf)) ++first;
    if (first > last) continue;
    while (!(row[last] < kInf)) --last;
    if (r0 < 0) r0 = r;
    r1 = r, c0 = std::min(c0, first), c1 = std::max(c1, last);
  }
  if (r1 < 0) return;  // nothing reached, not even the home
  now.origin = Cell{r0, c0}, now.rows = r1 - r0 + 1, now.cols = c1 - c0 + 1;
  auto times = std::make_shared<Times>(static_cast<std::size_t>(now.rows) * static_cast<std::size_t>(now.cols));
  for (int r = 0; r < now.rows; ++r)
    std::copy_n(row_of(r0 + r) + c0, now.cols,
                times->data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(now.cols));
  now.times = std::move(times);
  const std::size_t bytes = now.times->size() * sizeof(float);
  const std::lock_guard<std::mutex> lock(mutex_);
  Kept& slot = fields_[key];
  const std::size_t before = slot.times ? slot.times->size() * sizeof(float) : 0;
  if (slot.times && !now.whole && slot.reach >= now.reach) return;  // another thread kept one as far meanwhile
  if (!budget_->exchange(before, bytes)) {
    if (!slot.times) fields_.erase(key);
    return;
  }
  slot = std::move(now);
}

bool WalkBudget::exchange(std::size_t less, std::size_t more) {
  std::size_t used = used_.load();
  for (;;) {
    const std::size_t next = used - less + more;
    if (more > less && next > cap_) return false;
    if (used_.compare_exchange_weak(used, next)) return true;
  }
}

std::size_t HomeWalks::kept() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return fields_.size();
}

std::size_t HomeWalks::marched() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return marched_;
}

// The share of the reachable space a pair grid keeps at least (a cell of it
// is kept when a reachable block stands for it). Less than the planning
// grid's 98%: a cell of no block only leaves the mean pair distance, which
// its segment's other cells still sample, and a segment whose blocks the
// coarse window does not connect is marched on the planning grid.
constexpr double kPairGridKept = 0.95;

namespace {

// The j-th of `count` items spread over `n` (the middles of `count` equal
// runs): how pair sources and scale samples are picked, deterministically.
std::size_t spread(std::size_t j, std::size_t count, std::size_t n) { return (2 * j + 1) * n / (2 * count); }

// Where a march on the pair grid from planning cell `from` (standing on
// block `b` >= 0) starts: the cell's centre in its own block, else (its
// block not free) the centre of the block standing for it.
Point2 pair_start(const PairGrid& pg, const OccupancyGrid& grid, Cell from, int32_t b) {
  const Cell block = pg.grid.cell(static_cast<std::size_t>(b));
  const bool own = block.row == from.row / pg.factor && block.col == from.col / pg.factor;
  return own ? grid.cell_center(from) : pg.grid.cell_center(block);
}

// Whether planning cell `c` (in block `b`, not free) walks into block `n`
// (reachable, one of the 8 around b) within the box of the two blocks:
// through reachable cells, so never across a wall. The box holds at most
// 2f x 2f cells (f <= kMaxPairGridFactor): fixed arrays, nothing allocated
// for each of the many cells this is asked for.
constexpr int kMaxPairGridFactor = 4;  // PlannerOptions::pair_grid_factor's range
bool walks_into(const OccupancyGrid& grid, const Mask& reachable, Cell c, Cell b, Cell n, int f) {
  constexpr std::size_t kBox = 4 * kMaxPairGridFactor * kMaxPairGridFactor;
  const int r0 = std::min(b.row, n.row) * f, c0 = std::min(b.col, n.col) * f;
  const int rows = (std::abs(b.row - n.row) + 1) * f, cols = (std::abs(b.col - n.col) + 1) * f;
  if (f > kMaxPairGridFactor) throw Error("pair grid", "factor " + std::to_string(f) + " over 4");
  std::array<uint8_t, kBox> seen{};
  std::array<Cell, kBox> stack;  // each cell is pushed once: when first seen
  std::size_t top = 0;
  auto at = [&](Cell q) {
    return static_cast<std::size_t>(q.row - r0) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(q.col - c0);
  };
  seen[at(c)] = 1, stack[top++] = c;
  while (top > 0) {
    const Cell q = stack[--top];
    if (q.row / f == n.row && q.col / f == n.col) return true;
    const Cell next[4] = {{q.row - 1, q.col}, {q.row + 1, q.col}, {q.row, q.col - 1}, {q.row, q.col + 1}};
    for (Cell m : next) {
      if (m.row < r0 || m.col < c0 || m.row >= r0 + rows || m.col >= c0 + cols || !grid.contains(m)) continue;
      if (seen[at(m)] || !reachable[grid.index(m)]) continue;
      seen[at(m)] = 1, stack[top++] = m;
    }
  }
  return false;
}

}  // namespace

PairGrid make_pair_grid(const OccupancyGrid& grid, Point2 oc, const Mask& reachable, const fmm::FastMarching& walk,
                        const Field& from_oc, double reach_m, int factor) {
  PairGrid out;
  if (factor <= 1) return out;
  // The planning grid's rule: the factor lowered while the coarse grid
  // keeps under kPairGridKept of the reachable space, or loses the OC's block.
  CoarseGrid coarse_grid = coarsest_kept(grid, oc, reachable, factor, kPairGridKept);
  if (coarse_grid.factor <= 1) return out;
  const int f = out.factor = coarse_grid.factor;
  out.grid = std::move(coarse_grid.grid);
  const Mask& coarse_reachable = coarse_grid.reachable;
  out.block_of.assign(grid.size(), -1);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!reachable[i]) continue;
    const Cell c = grid.cell(i);
    const Cell b{c.row / f, c.col / f};
    if (coarse_reachable[out.grid.index(b)]) {
      out.block_of[i] = static_cast<int32_t>(out.grid.index(b));
      continue;
    }
    // [planning cells^2] from the cell's centre to a block's, doubled.
    double best = std::numeric_limits<double>::infinity();
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const Cell n{b.row + dr, b.col + dc};
        if (!out.grid.contains(n) || !coarse_reachable[out.grid.index(n)]) continue;
        const double y = 2.0 * c.row + 1.0 - f * (2.0 * n.row + 1.0), x = 2.0 * c.col + 1.0 - f * (2.0 * n.col + 1.0);
        if (x * x + y * y < best && walks_into(grid, reachable, c, b, n, f))
          best = x * x + y * y, out.block_of[i] = static_cast<int32_t>(out.grid.index(n));
      }
  }
  // The scale: both grids marched from the same cells (from the cell's
  // centre on the coarse grid, as a segment's pair sources), the sums of the
  // times of the planning cells within reach_m and of their blocks'.
  std::vector<std::size_t> mapped;
  for (std::size_t i = 0; i < grid.size(); ++i)
    if (out.block_of[i] >= 0) mapped.push_back(i);
  if (mapped.empty()) return out;
  fmm::FastMarching fine = walk, coarse(out.grid);
  fmm::SolveOptions so;
  so.labels = false;
  double fine_sum = 0.0, coarse_sum = 0.0;
  const int cells_reach = static_cast<int>(std::ceil(reach_m / grid.resolution())) + 1;
  for (std::size_t j = 0; j < kPairGridSamples; ++j) {
    const std::size_t i = mapped[spread(j, kPairGridSamples, mapped.size())];
    const Cell from = grid.cell(i);
    so.max_time = reach_m;
    fine.solve({fmm::Source::at_cell(from)}, so);
    so.max_time = 2.0 * reach_m + 2.0 * f * grid.resolution();  // beyond every block of a cell within reach_m
    coarse.solve({fmm::Source::at_point(pair_start(out, grid, from, out.block_of[i]))}, so);
    // The times read in place (+inf unreached or not free).
    const float* tf = fine.padded_times();
    const float* tc = coarse.padded_times();
    for (int r = std::max(0, from.row - cells_reach); r <= std::min(grid.height() - 1, from.row + cells_reach); ++r)
      for (int c = std::max(0, from.col - cells_reach); c <= std::min(grid.width() - 1, from.col + cells_reach); ++c) {
        const int32_t b = out.block_of[grid.index(Cell{r, c})];
        const double t = tf[fine.padded(Cell{r, c})];
        if (b < 0 || !(t <= reach_m)) continue;
        const double t_block = tc[coarse.padded(out.grid.cell(static_cast<std::size_t>(b)))];
        if (t_block < kInf) fine_sum += t, coarse_sum += t_block;
      }
  }
  if (fine_sum > 0.0 && coarse_sum > 0.0) out.scale = fine_sum / coarse_sum;
  // The walk scale: the OC's march on both grids (on the coarse one from the
  // block standing for the OC's cell, as a home's walk starts), over every
  // cell standing on a block.
  const Cell oc_cell = grid.world_to_cell(oc);
  const int32_t oc_block = grid.contains(oc_cell) ? out.block_of[grid.index(oc_cell)] : -1;
  if (oc_block < 0) return out;
  so.max_time = fmm::kUnreached;
  coarse.solve({fmm::Source::at_cell(out.grid.cell(static_cast<std::size_t>(oc_block)))}, so);
  const float* tc = coarse.padded_times();
  fine_sum = 0.0, coarse_sum = 0.0;
  for (std::size_t i : mapped) {
    const double t = from_oc[i], t_block = tc[coarse.padded(out.grid.cell(static_cast<std::size_t>(out.block_of[i])))];
    if (t < kInf && t_block < kInf) fine_sum += t, coarse_sum += t_block;
  }
  if (fine_sum > 0.0 && coarse_sum > 0.0) out.walk_scale = fine_sum / coarse_sum;
  return out;
}

// Each segment's walking distances, marched at unit speed on the reachable
// space (as the workers walk), each march stopped once the segment's cells
// are reached:
//  - mean_home_distance and home_quantiles: from the home of its worker as
//    a worker of the OC, on the whole map (ctx.home_walks);
//  - mean_oc_distance and oc_quantiles: from the OC's cell (ctx.oc_walk,
//    no march), where that worker starts the mission;
//  - mean_pair_distance: between two of its cells, the mean over the cells
//    of the distances from opt.pair_sources cells spread over the segment (in
//    row-major order, so the estimate is deterministic), marched in the
//    segment's window as the worker marches between its goals; on the pair
//    grid (ctx.pair_grid) when it is coarser, between the blocks that stand
//    for the cells, each counted as many times as it stands for one (on the
//    planning grid when a block of the segment is not reached in the
//    coarse window).
// Returns each cell's rank in its segment by distance from that home, in
// [0, 1) (row-major; -1 off the segments).
Field segment_distances(const PlanContext& ctx, const LabelImage& labels, WorkerGraph& graph,
                        const PlannerOptions& opt) {
  constexpr std::size_t kQuantiles = 16;  // WorkerSegment::home_quantiles holds 17
  const auto pair_sources = static_cast<std::size_t>(opt.pair_sources);
  const OccupancyGrid& grid = ctx.scenario.grid;
  require_same_size(labels, grid.frame(), "walking distances", "the label image");
  PerSegment<std::vector<Cell>> cells(graph.segments.count());
  {
    PerSegment<std::size_t> count(graph.segments.count(), 0);  // each list allocated once
    for (std::size_t i = 0; i < grid.size(); ++i) {
      const SegmentId k(labels[i]);
      if (k.within(count.count()) && ctx.reachable[i]) ++count[k];
    }
    for (SegmentId k : segment_ids(cells.count())) cells[k].reserve(count[k]);
  }
  std::size_t at = 0;  // row-major, without a division per cell
  for (int r = 0; r < grid.height(); ++r)
    for (int c = 0; c < grid.width(); ++c, ++at) {
      const SegmentId k(labels[at]);
      if (k.within(cells.count()) && ctx.reachable[at]) cells[k].push_back(Cell{r, c});
    }
  Field rank(labels.frame(), -1.0f);
  std::vector<uint64_t> order, keys, spare;
  std::vector<double> sorted;     // distances of one segment's cells, ascending
  std::vector<double> pair;       // from one cell of a segment to its cells
  std::vector<double> walk_time;  // from the home to the segment's cells
  // The kQuantiles + 1 quantiles of ascending distances (the i-th: the
  // value at rank i / kQuantiles).
  auto quantiles = [](const std::vector<double>& ascending) {
    std::vector<double> q(kQuantiles + 1);
    for (std::size_t i = 0; i <= kQuantiles; ++i)
      q[i] = ascending[std::min(ascending.size() - 1, i * ascending.size() / kQuantiles)];
    return q;
  };
  fmm::FastMarching walk = ctx.coverage_field;  // unit speed on the reachable space
  mission::SegmentWindow segment_window;        // bound to each segment in turn
  fmm::SolveOptions so;
  so.labels = false;
  // Adds the reached distances of `out` to `sum`, counted in `n`.
  auto add = [](const std::vector<double>& out, double& sum, std::size_t& n) {
    for (double t : out)
      if (t < kInf) sum += t, ++n;
  };
  // Distances [m] from `from` to the segment's cells `to` into `out` (+inf
  // where not reached): in the segment's window, else on the whole map.
  auto distances = [&](Cell from, const std::vector<Cell>& to, mission::SegmentWindow& window, std::vector<double>& out,
                       double& sum, std::size_t& n) {
    out.resize(to.size());
    if (!window.march_over(from, to, out.data())) {
      so.targets = to;
      walk.solve({fmm::Source::at_cell(from)}, so);
      for (std::size_t i = 0; i < to.size(); ++i) out[i] = walk.time(to[i]);
    }
    add(out, sum, n);
  };
  // On the coarser pair grid: the blocks standing for a segment's cells (in
  // the order of their first cell), each weighted by the cells it stands
  // for, and each cell's place among them (-1: it stands on none).
  const PairGrid& pg = *ctx.pair_grid;
  mission::SegmentWindow block_window;                                // on pg.grid, bound to each segment in turn
  std::vector<int32_t> slot(pg.factor > 1 ? pg.grid.size() : 0, -1);  // a block's place in `blocks`, -1 none
  std::vector<Cell> blocks;
  std::vector<double> weight, block_time;
  std::vector<int32_t> cell_block;
  std::vector<Point2> source_point;  // the sources' cell centres
  fmm::FastMarching block_walk;      // unit speed on pg.grid (the homes' walks)
  if (pg.factor > 1) block_walk = fmm::FastMarching(pg.grid);
  // Returns the number of the segment's cells that stand on a block.
  auto segment_blocks = [&](const std::vector<Cell>& seg_cells) {
    blocks.clear(), weight.clear(), cell_block.assign(seg_cells.size(), -1);
    std::size_t mapped = 0;
    for (std::size_t i = 0; i < seg_cells.size(); ++i) {
      const int32_t b = pg.block_of[grid.index(seg_cells[i])];
      if (b < 0) continue;  // no reachable block next to it
      if (slot[static_cast<std::size_t>(b)] < 0) {
        slot[static_cast<std::size_t>(b)] = static_cast<int32_t>(blocks.size());
        blocks.push_back(pg.grid.cell(static_cast<std::size_t>(b)));
        weight.push_back(0.0);
      }
      cell_block[i] = slot[static_cast<std::size_t>(b)];
      weight[static_cast<std::size_t>(cell_block[i])] += 1.0;
      ++mapped;
    }
    for (Cell c : blocks) slot[pg.grid.index(c)] = -1;
    return mapped;
  };
  // The walks from the home to the segment's cells on the pair grid, from
  // the block standing for the home, scaled: false (walk_time then not
  // set) when a cell or the home stands on no block, or a block is not
  // reached.
  auto coarse_home = [&](Cell home, const std::vector<Cell>& seg_cells, std::size_t mapped) {
    const int32_t h = pg.block_of[grid.index(home)];
    if (h < 0 || mapped < seg_cells.size()) return false;
    ctx.pair_home_walks->distances(pg.grid.cell(static_cast<std::size_t>(h)), blocks, block_walk, block_time);
    for (double t : block_time)
      if (!(t < kInf)) return false;
    walk_time.resize(seg_cells.size());
    for (std::size_t i = 0; i < seg_cells.size(); ++i)
      walk_time[i] = pg.walk_scale * block_time[static_cast<std::size_t>(cell_block[i])];
    return true;
  };
  // The pair distances between the blocks (cells standing on none are left
  // out of the mean); false when a source's or a cell's block is not
  // reached in the blocks' window (then marched on the planning grid).
  auto coarse_pairs = [&](const std::vector<Cell>& seg_cells, std::size_t mapped, std::size_t sources, double& sum,
                          std::size_t& n) {
    source_point.clear();
    // The sources: the centres of the cells the planning grid's marches
    // start from (a block's centre lies half a cell from each of its cells,
    // on a segment's edge often inwards of it: a bias of a few percent).
    for (std::size_t j = 0; j < sources; ++j) {
      const Cell from = seg_cells[spread(j, sources, seg_cells.size())];
      const int32_t b = pg.block_of[grid.index(from)];
      if (b < 0) return false;
      source_point.push_back(pair_start(pg, grid, from, b));
    }
    // Most of the segment is to stand on blocks (as of the map), else its
    // narrow parts would be left out of the mean.
    if (blocks.empty() || static_cast<double>(mapped) < kPairGridKept * static_cast<double>(seg_cells.size()))
      return false;
    block_window.bind(pg.grid, blocks, opt.protocol.window_margin_m);
    double s = 0.0, w = 0.0;
    for (Point2 from : source_point) {
      pair.resize(blocks.size());
      if (!block_window.march_over(from, blocks, pair.data())) return false;
      for (std::size_t i = 0; i < blocks.size(); ++i) s += weight[i] * pair[i], w += weight[i];
    }
    sum = s * pg.scale, n = static_cast<std::size_t>(w);
    return true;
  };
  for (SegmentId k : segment_ids(cells.count())) {
    WorkerSegment& seg = graph.segments[k];
    seg.mean_home_distance = seg.mean_coverage_distance;
    seg.mean_pair_distance = kSquarePairDistance * std::sqrt(seg.area);  // an open square's, until measured
    if (cells[k].empty()) continue;
    double sum = 0.0;
    std::size_t n = 0;
    const Cell home = ctx.oc_worker_home(cells[k]);
    const std::size_t mapped = pg.factor > 1 ? segment_blocks(cells[k]) : 0;
    // From the home, on the whole map as its worker walks from there.
    if (home.row >= 0) {
      if (pg.factor <= 1 || !coarse_home(home, cells[k], mapped))
        ctx.home_walks->distances(home, cells[k], walk, walk_time);
      add(walk_time, sum, n);
    }
    if (n > 0) seg.mean_home_distance = sum / static_cast<double>(n);
    // Ascending by distance, ties by row-major order: keys (the distance's
    // float bits, which sort like distances >= 0) << 32 | index in cells[k].
    // The marches' times are floats, so nothing is lost.
    order.clear();
    for (std::size_t i = 0; i < cells[k].size(); ++i)
      order.push_back(order_key(static_cast<float>(home.row >= 0 ? walk_time[i] : 0.0), static_cast<uint32_t>(i)));
    sort_keys(order, spare, 32);
    for (std::size_t i = 0; i < order.size(); ++i)
      rank[grid.index(cells[k][order[i] & 0xffffffffu])] =
          static_cast<float>(static_cast<double>(i) / static_cast<double>(order.size()));
    if (home.row >= 0 && n == order.size()) {
      sorted.clear();
      for (uint64_t key : order) sorted.push_back(walk_time[key & 0xffffffffu]);
      seg.home_quantiles = quantiles(sorted);
    }
    // From the OC's cell (the first request's trip).
    std::vector<double>& from_oc = sorted;
    from_oc.clear();
    for (Cell c : cells[k]) {
      const double d = ctx.oc_walk[grid.index(c)];
      if (d < kInf) from_oc.push_back(d);
    }
    if (from_oc.size() == cells[k].size()) {
      sort_distances(from_oc, keys, spare);
      double total = 0.0;
      for (double d : from_oc) total += d;
      seg.mean_oc_distance = total / static_cast<double>(from_oc.size());
      seg.oc_quantiles = quantiles(from_oc);
    } else {
      seg.mean_oc_distance = seg.mean_home_distance, seg.oc_quantiles = seg.home_quantiles;
    }
    // Between its cells, in its window as the worker walks between goals
    // (on the whole map when the window does not connect them).
    sum = 0.0, n = 0;
    const std::size_t sources = std::min(pair_sources, cells[k].size());
    if (pg.factor <= 1 || !coarse_pairs(cells[k], mapped, sources, sum, n)) {
      sum = 0.0, n = 0;
      segment_window.bind(grid, cells[k], opt.protocol.window_margin_m);
      for (std::size_t j = 0; j < sources; ++j)
        distances(cells[k][spread(j, sources, cells[k].size())], cells[k], segment_window, pair, sum, n);
    }
    if (n > 0) seg.mean_pair_distance = sum / static_cast<double>(n);
  }
  return rank;
}

}  // namespace plan
}  // namespace gather
