#pragma once
// The partition methods behind partition_area() (private to gather_core).
#include <cstdint>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/partition/partition.hpp"

namespace gather {
namespace partition {

// What every method gets: the grid, the OC, the reachable cells and their
// clearance, already validated (1 <= workers <= reachable cells).
struct MethodInput {
  const OccupancyGrid& grid;
  Cell oc;
  const std::vector<uint8_t>& reachable;  // row-major, 1 = reachable from the OC
  std::size_t reachable_cells;
  const std::vector<float>& clearance;    // row-major [m]
  int workers;
  unsigned seed;
  const PartitionParams& params;
};

void run_bap(const MethodInput& in, PartitionResult& out);
void run_pap(const MethodInput& in, PartitionResult& out);
void run_rap(const MethodInput& in, PartitionResult& out);

// Moves boundary cells between adjacent segments of `labels` (row-major
// width*height, 0 = no segment, segments 1..workers each 4-connected) until
// every segment's area is within tolerance * mean of the mean, or after
// max_passes passes. Every segment stays 4-connected and non-empty; the
// cells labelled 0 stay 0. Deterministic. In rebalance.cpp.
void rebalance_areas(int width, int height, int workers, std::vector<int32_t>& labels, double tolerance,
                     int max_passes);

}  // namespace partition
}  // namespace gather
