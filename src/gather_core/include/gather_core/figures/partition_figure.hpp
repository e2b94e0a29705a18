#pragma once
// PNG figures of the partitions in the style of the seed paper's Fig. 1: one
// colour per segment (neighbours always differ), obstacles dark, the OC a red
// square, seeds/centroids small black-edged dots, a scale bar in metres.
// Image row 0 = top of the map (grid row 0 = bottom). All writers throw
// gather::Error naming the file when it cannot be written.
#include <string>
#include <vector>

#include "gather_core/figures/palette.hpp"
#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/partition/partition.hpp"

namespace gather {
namespace figures {

// One panel: the partition with its seeds, the OC and `caption` above it.
void write_partition_png(const std::string& path, const OccupancyGrid& grid, const partition::PartitionResult& part,
                         Point2 oc, const std::string& caption);

// The centroid initialisation (Fig. 1b): clearance shading of the reachable
// space and the initial centroids of a PAP/RAP result.
void write_seeds_png(const std::string& path, const OccupancyGrid& grid, const partition::PartitionResult& part,
                     Point2 oc, const std::string& caption);

// Fig. 1 side by side: (a) BAP, (b) centroids, (c) PAP, (d) RAP. `parts` holds
// one result per method in any order; the centroid panel uses PAP's (or RAP's)
// initial seeds. Panels go in a 2 x 2 grid for wide maps, in a row otherwise.
void write_compare_png(const std::string& path, const OccupancyGrid& grid,
                       const std::vector<partition::PartitionResult>& parts, const std::vector<std::string>& captions,
                       Point2 oc);

}  // namespace figures
}  // namespace gather
