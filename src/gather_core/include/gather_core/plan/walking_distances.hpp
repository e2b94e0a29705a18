#pragma once
// Each segment's walking distances for the estimate: from its OC worker's
// home, from the OC's cell, and between its cells (docs/planner.md,
// "Estimate model").
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/plan/planner.hpp"

namespace gather {
namespace plan {

// Bytes that homes' walks may keep, shared by the HomeWalks of a context
// (on the planning grid and on the pair grid). Thread-safe.
class WalkBudget {
 public:
  explicit WalkBudget(std::size_t bytes) : cap_(bytes) {}
  bool full() const { return used_.load() >= cap_; }
  // Gives back `less` bytes and takes `more` when the total stays within
  // the budget (or shrinks); false, and nothing changed, else.
  bool exchange(std::size_t less, std::size_t more);

 private:
  const std::size_t cap_;
  std::atomic<std::size_t> used_{0};
};

// The walks from the OC workers' homes, shared by a sweep's configurations.
// A worker of the OC walks from its home to its goals on the whole map
// (mission::WorkerPolicy::march), so its distances are marched there too.
// Homes are cells of the coverage's border, and a few of them serve most
// segments of every configuration: a home's march, stopped once it reached
// the asked cells, is kept (over the box of the cells it reached, while the
// kept marches fit in `budget_bytes`) and answers every later ask whose
// cells it reached; an ask it did not
// reach marches again, farther, and that march is kept instead. A march
// reaches its cells with the same times whether it stops there or runs
// over the whole map, so what is kept changes only the time, never a
// result. Thread-safe.
class HomeWalks {
 public:
  explicit HomeWalks(std::size_t budget_bytes) : budget_(std::make_shared<WalkBudget>(budget_bytes)) {}
  explicit HomeWalks(std::shared_ptr<WalkBudget> budget) : budget_(std::move(budget)) {}
  // Distances [m] from `home` to `cells` into `out` (+inf where not
  // reached), on `walk`: unit speed on the reachable space (a copy of
  // PlanContext::coverage_field, owned by the calling thread; or a march on
  // the pair grid, cells and home its blocks, for PlanContext::pair_home_walks).
  // One HomeWalks serves one grid.
  void distances(Cell home, const std::vector<Cell>& cells, fmm::FastMarching& walk, std::vector<double>& out);
  // Homes whose march is kept, and marches run.
  std::size_t kept() const;
  std::size_t marched() const;

 private:
  using Times = std::vector<float>;  // a march's times: finite where final, +inf elsewhere
  struct Kept {
    std::shared_ptr<const Times> times;  // over the box of the cells it reached, row-major
    Cell origin{0, 0};                   // the box's first cell on the map
    int rows = 0, cols = 0;
    double reach = 0.0;      // [m] the farthest asked cell it reached
    bool whole = false;      // it ran over all it could reach (it did not stop at its cells)
    float at(Cell c) const;  // +inf off the box
  };
  std::shared_ptr<WalkBudget> budget_;
  mutable std::mutex mutex_;
  std::unordered_map<uint64_t, Kept> fields_;  // by home (row << 32 | col)
  std::size_t marched_ = 0;
};

// The HomeWalks budget a PlanContext gets: 32 MiB (32 whole marches on a
// 250,000-cell planning grid, planner.max_cells' default; a march stopped
// near its home keeps less), shared by the walks on the planning grid and
// on a coarser pair grid (WalkBudget).
constexpr std::size_t kHomeWalkBytes = std::size_t{32} << 20;

// The grid a segment's pair distances and its home's walk are marched on:
// the planning grid, or (PlannerOptions::pair_grid_factor f > 1) that grid
// coarsened by f (grid/planning_grid.hpp: a block is free only when all its
// cells are), f lowered until the coarse grid keeps 95% of the reachable
// space, as the planning grid itself is chosen (with 98%). A march there
// costs about 1 / f^2 of one on the planning grid; its times are those of
// the blocks standing for the cells, from the source cell's centre (or the
// centre of the block standing for it), scaled (docs/planner.md, "Coarser
// walks").
struct PairGrid {
  int factor = 1;
  OccupancyGrid grid;  // the planning grid coarsened by `factor` (unset at 1)
  // Per planning cell (at factor > 1): the coarse cell that stands for it,
  // its own block when that is reachable from the OC's block, else the
  // reachable one of the 8 blocks around it whose centre is nearest (the
  // first in row-major order of equal ones) among those it walks into
  // within the box of the two blocks (never across a wall); -1 when none
  // is, or off the reachable space.
  std::vector<int32_t> block_of;
  // The planning grid's distances over the coarse grid's: a first-order
  // march overestimates a straight distance by a share that grows with the
  // cell size (1-3% more at twice the cell), so the coarse distances are
  // scaled by the ratio of the two grids' marches from kPairGridSamples
  // cells spread over the map, over the cells within `reach_m` of them.
  double scale = 1.0;
  // The same for the homes' walks, longer: the ratio of the OC's marches on
  // both grids over the whole map.
  double walk_scale = 1.0;
};
constexpr std::size_t kPairGridSamples = 8;
// `reachable`: the planning grid's reachable space (4-connected to `oc`);
// `walk`: unit speed on it (PlanContext::coverage_field); `from_oc`: its
// march from the OC's cell (PlanContext::oc_walk); `reach_m` [m]:
// about a segment's size (PlanContext::area_tile).
PairGrid make_pair_grid(const OccupancyGrid& grid, Point2 oc, const Mask& reachable, const fmm::FastMarching& walk,
                        const Field& from_oc, double reach_m, int factor);

// Fills graph.segments' mean_home_distance, home_quantiles,
// mean_oc_distance, oc_quantiles and mean_pair_distance (see
// walking_distances.cpp); returns each cell's rank in its segment by
// walking distance from that home, in [0, 1) (-1 off the segments), in the
// labels' frame.
// `opt`: pair_sources. The homes' walks come from ctx.home_walks (or
// ctx.pair_home_walks on the pair grid), the pair grid from ctx.pair_grid.
// On the pair grid the cells of one block get the same home distance: their
// rank among themselves is their row-major order.
Field segment_distances(const PlanContext& ctx, const LabelImage& labels, WorkerGraph& graph,
                        const PlannerOptions& opt);

}  // namespace plan
}  // namespace gather
