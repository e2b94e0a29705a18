#pragma once
// The partition methods behind partition_area() (private to gather_core).
#include <cstdint>
#include <memory>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/partition/partition.hpp"
#include "gather_core/partition/rebalance.hpp"

namespace gather {
namespace partition {

// What every method gets: the grid, the OC, the reachable cells and their
// clearance, already validated (1 <= workers <= reachable cells).
struct MethodInput {
  const OccupancyGrid& grid;
  Cell oc;
  const Mask& reachable;  // 1 = reachable from the OC
  std::size_t reachable_cells;
  const Field& clearance;  // [m]
  int workers;
  unsigned seed;
  const PartitionParams& params;
  const Raster<double>* oc_distance = nullptr;  // PreparedArea::oc_distance, or none (BAP marches it)
  CentroidCache* centroid_cache = nullptr;      // PreparedArea::centroid_cache, or none (PAP and RAP compute it)
};

void run_bap(const MethodInput& in, PartitionResult& out);
void run_pap(const MethodInput& in, PartitionResult& out);
void run_rap(const MethodInput& in, PartitionResult& out);

}  // namespace partition
}  // namespace gather
