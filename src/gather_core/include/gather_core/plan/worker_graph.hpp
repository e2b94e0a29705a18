#pragma once
// The worker graph of a partition (seed Fig. 2a): one node per working
// segment at its centroid, an edge between segments that share a border.
#include <cstdint>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/segment_id.hpp"

namespace gather {
namespace plan {

struct WorkerSegment {
  SegmentId id;
  std::size_t cells = 0;
  double area = 0.0;                  // [m^2]
  Cell centroid;                      // segment cell nearest to its centre of mass
  Point2 centroid_m;                  // [m]
  std::vector<SegmentId> neighbours;  // segments sharing a 4-neighbour border, ascending
  // Geodesic distance [m] from the OC's radio coverage to the segment's
  // nearest cell (0 when the segment overlaps the coverage), and that cell:
  // where the segment is cheapest to reach from the OC.
  double coverage_distance = 0.0;
  // Mean geodesic distance [m] from the coverage to the segment's cells: the
  // expected one-way trip to a goal of the segment from the OC's coverage.
  double mean_coverage_distance = 0.0;
  // Mean geodesic distance [m] from the home of the segment's worker when it
  // delivers to the OC (mission::World::oc_worker_home: where it waits for
  // requests) to the segment's cells: the outbound leg of its tours. Set by
  // the planner (plan_configuration); the way back is mean_coverage_distance.
  double mean_home_distance = 0.0;
  // The same distances' quantiles: home_quantiles[i] [m] is exceeded by a
  // fraction 1 - i / 16 of the cells (empty until the planner sets it).
  std::vector<double> home_quantiles;
  // The same from the OC's cell, where its worker starts the mission (the
  // first request's trip): mean [m] and quantiles.
  double mean_oc_distance = 0.0;
  std::vector<double> oc_quantiles;
  // Mean geodesic distance [m] between two cells of the segment (walls and
  // doors included; 0.52 sqrt(area) in an open square). Set by the planner.
  double mean_pair_distance = 0.0;
  Cell entry;                     // preferably a cell where the robot fits (see build_worker_graph)
  bool touches_coverage = false;  // some cell of the segment is linked to the OC
};

struct WorkerGraph {
  PerSegment<WorkerSegment> segments;
  const WorkerSegment& segment(SegmentId id) const { return segments[id]; }
};

// `labels`: partition labels (0 = none, 1..workers) in the grid's frame; `coverage`:
// 1 on cells linked to the OC; `coverage_distance`: geodesic distance [m]
// to the coverage (+inf unreached); all in the grid's frame. With `roomy` (1 where the
// robot fits), the entry is the nearest such cell of the segment when it has one.
WorkerGraph build_worker_graph(const OccupancyGrid& grid, const LabelImage& labels, int workers, const Mask& coverage,
                               const Raster<double>& coverage_distance, const Mask* roomy = nullptr);

}  // namespace plan
}  // namespace gather
