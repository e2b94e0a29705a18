#pragma once
// Quality of a partition: area balance, compactness, and agreement with
// ground-truth rooms (the ipa_room_segmentation evaluation).
#include <cstdint>
#include <string>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/partition/partition.hpp"

namespace gather {
namespace partition {

struct PartitionMetrics {
  int segments = 0;
  std::vector<double> areas;  // [m^2] per segment 1..N_w
  double area_mean = 0.0;     // [m^2]
  double area_ratio = 0.0;    // max / min area
  double area_cv = 0.0;       // coefficient of variation (population std / mean)
  // Compactness of a segment: radius of the disc of its area / its geodesic
  // radius (largest FMM distance, inside the segment, from its cell nearest
  // the centre of mass). 1 for a disc; lower for long or twisted segments.
  std::vector<double> compactness;
  double compactness_mean = 0.0;
  double compactness_min = 0.0;
  double runtime_ms = 0.0;  // of the partition
};

PartitionMetrics compute_metrics(const OccupancyGrid& grid, const PartitionResult& part);

// Ground-truth rooms: a room = 4-connected component of white pixels (all
// colour channels >= 250, alpha ignored) of `gt_png`, a gray, gray+alpha,
// RGB or RGBA PNG (or a PGM) of the map's size, image row 0 = top;
// components under `min_cells` ignored. Returns room ids in the grid's frame
// (0 = no room, 1..rooms). Throws gather::Error on a missing or
// unreadable file, a palette PNG that is not a gray ramp, or a size mismatch.
LabelImage load_gt_rooms(const std::string& gt_png, const OccupancyGrid& grid, int* rooms = nullptr,
                         int min_cells = 50);

// Agreement with ground-truth rooms, counted over cells that are both in a
// segment and in a room. Recall: per room, the share of it covered by its
// best-matching segment; precision: per segment, the share of it inside its
// best-matching room. Both averages are area-weighted (by room area for
// recall, by segment area for precision); F1 = 2PR / (P + R).
struct RoomAgreement {
  int rooms = 0;
  double recall = 0.0;
  double precision = 0.0;
  double f1 = 0.0;
};

// Throws gather::Error when the two images are not the same size.
RoomAgreement room_agreement(const LabelImage& labels, const LabelImage& rooms);

}  // namespace partition
}  // namespace gather
