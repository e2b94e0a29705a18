#pragma once
// Segmentation of the scenario into N_w working areas, one per worker (seed
// paper, Sec. 3.1 "Scenario Segmentation", Fig. 1). Three methods share one
// signature and one table (kMethods in partition.cpp):
//   BAP  Balanced Area Partition: "uses FMM, extending N_w wavefront until
//        cover all the free space" - areas balanced.
//   PAP  Polygonal Area Partition: "initialization of N_w centroids in areas
//        distant from obstacles, Fig. 1(b), and then moving these centroids,
//        balancing the distances between them" - convex-ish cells.
//   RAP  Room-like Area Partition: the same two phases, but "the wavefront is
//        expanded in such a way that the resulting segments fit better the
//        shape of the rooms" - fronts slow down near obstacles, stall in doors.
//
// Contract (all methods): every free cell 4-connected to the OC gets exactly
// one label in 1..N_w, every other cell 0; each label's region is 4-connected
// and non-empty; the same inputs and seed give the same labels.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace partition {

enum class Method { kBap, kPap, kRap };

// "bap" | "pap" | "rap" -> Method; throws gather::Error naming the bad name.
Method parse_method(const std::string& name);
const char* method_name(Method m);  // "bap", "pap", "rap"
// Every method, in table order.
std::vector<Method> all_methods();

// The partition methods' tuning. Every field changes results; the defaults
// are the ones the reports (docs/partitions.md, docs/scenarios.md) were
// measured with. partition_area() refuses a value outside its range with a
// gather::Error naming the field.
struct PartitionParams {
  // PAP/RAP work on a coarse copy of the grid for the seed phase (Lloyd
  // iterations) and label the full grid once at the end; coarse cells per
  // side = the smallest factor that leaves <= this many coarse free cells.
  // Range [100, 1e9].
  std::size_t coarse_cells = 20000;
  // BAP runs its wavefronts on blocks of f x f cells, f the smallest factor
  // that leaves <= this many coarse cells (1 = full resolution). Range [100, 1e9].
  std::size_t bap_coarse_cells = 1000000;
  // BAP: boundary cells move between segments until every area is within
  // this fraction of the mean (range (0, 1)), in at most this many passes
  // (range [0, 1000]; partition/rebalance).
  double bap_balance_tolerance = 0.002;
  int bap_balance_passes = 12;
  // BAP: when a segment's moving front is stuck at local cuts (cells whose
  // removal would split it), at most this many of them are searched for a
  // small pocket to move with the cut, per move. Range [0, 4096].
  int bap_cut_searches = 64;
  // PAP/RAP: Lloyd iterations of the seed phase. Range [0, 1000].
  int lloyd_iterations = 12;
  // PAP: additive front weights follow area imbalance; gain per iteration
  // [fraction of the mean segment radius per unit of relative area error].
  // Range [0, 10].
  double pap_balance_gain = 0.5;
  // PAP: start delays stay within this many mean segment radii of each other
  // (a larger spread lets the neighbours surround a seed before its front
  // starts). Range [0, 10].
  double pap_max_delay_radii = 1.0;
  // PAP: a segment under this share of the mean area after the Lloyd
  // iterations gets its delay halved until it is not. Range [0, 1].
  double pap_min_area_share = 0.5;
  // RAP: front speed = clamp((clearance / rap_room_clearance)^rap_exponent,
  // rap_min_speed, 1) [relative]; doors (clearance ~0.45 m) are slow.
  double rap_room_clearance = 1.2;  // [m], range (0, 100]
  double rap_exponent = 2.0;        // range [0, 10]
  double rap_min_speed = 0.02;      // range (0, 1]
};

// Throws gather::Error("partition params", "<field> = <value> must be in
// <range>") for the first field outside its documented range.
void check_params(const PartitionParams& params);

struct PartitionResult {
  Method method = Method::kBap;
  int workers = 0;                  // N_w
  LabelImage labels;                // in the grid's frame: 0 = no segment, k = segment k (1..N_w)
  std::vector<Cell> seeds;          // per segment k-1: its final seed / wavefront start
  std::vector<Cell> initial_seeds;  // PAP/RAP: the centroid initialisation (Fig. 1b); BAP: empty
  Field clearance;                  // [m] clearance_map(): distance to the nearest non-free cell (map edge = wall)
  double runtime_ms = 0.0;          // wall time of partition_area()
};

// Splits the free space reachable from `oc` [cell] into `workers` segments.
// `seed` drives the random choices (PAP/RAP: the first centroid among the
// cells of near-maximal clearance); BAP uses none.
// Throws gather::Error when the OC is off the map or not free, workers < 1,
// or workers exceeds the number of reachable cells.
PartitionResult partition_area(const OccupancyGrid& grid, Cell oc, Method method, int workers, unsigned seed = 1,
                               const PartitionParams& params = {});

// What every method needs from the map besides N_w: the cells reachable from
// the OC and the clearance. A sweep over methods and N_w on one map (the
// planner) prepares it once instead of once per partition (about a quarter
// of a BAP on office_a).
class CentroidCache;  // partition/centroid_partition.cpp
struct PreparedArea {
  Cell oc{};
  Mask reachable;  // in the grid's frame: 1 = free and 4-connected to the OC
  std::size_t reachable_cells = 0;
  Field clearance;  // [m] clearance_map(grid)
  // [m] optional (empty: BAP marches it for each partition): the unit-speed
  // march from the OC's cell on the grid, FastMarching(grid).times() (BAP
  // orders its wavefronts by it). A sweep that has it computes it once.
  Raster<double> oc_distance;
  // What PAP and RAP compute alike for every partition of this area (the
  // coarse grids, the first centroid and its distances, RAP's slowness of
  // the full grid: about 4 B a cell), kept by the first partition that
  // needs it; thread-safe. Results are the same without it (prepare_area()
  // makes one; make_centroid_cache() for an area filled in otherwise). It
  // belongs to this area: a copy whose reachable space, clearance or OC is
  // changed needs a new one.
  std::shared_ptr<CentroidCache> centroid_cache;
};
std::shared_ptr<CentroidCache> make_centroid_cache();
// Throws gather::Error when the OC is off the map or not free.
PreparedArea prepare_area(const OccupancyGrid& grid, Cell oc);
// partition_area() on a prepared map (same result); `area` must come from
// prepare_area() on this grid (a size mismatch throws gather::Error).
// runtime_ms then counts the method only.
PartitionResult partition_area(const OccupancyGrid& grid, const PreparedArea& area, Method method, int workers,
                               unsigned seed = 1, const PartitionParams& params = {});

// Distance [m] from each cell centre to the nearest non-free cell centre
// (0 on non-free cells), in the grid's frame: ClearanceMap(grid).values(), the
// exact Euclidean distance transform, where the map's edge counts as a wall.
Field clearance_map(const OccupancyGrid& grid);

// The label image as a 16-bit gray PNG of the map size (image row 0 = top):
// 0 = no segment, k = segment k; what a plan's labels.png holds. Throws
// gather::Error naming `path` when it cannot be written or N_w > 65535.
void write_label_png(const std::string& path, const PartitionResult& part);

}  // namespace partition
}  // namespace gather
