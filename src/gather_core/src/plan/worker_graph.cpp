#include "gather_core/plan/worker_graph.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gather_core/numeric.hpp"

namespace gather {
namespace plan {

WorkerGraph build_worker_graph(const OccupancyGrid& grid, const LabelImage& labels, int workers, const Mask& coverage,
                               const Raster<double>& coverage_distance, const Mask* roomy) {
  const std::string where = "worker graph";
  require_same_size(labels, grid.frame(), where, "the label image");
  require_same_size(coverage, grid.frame(), where, "the coverage mask");
  require_same_size(coverage_distance, grid.frame(), where, "the coverage distance");
  if (roomy) require_same_size(*roomy, grid.frame(), where, "the roomy mask");
  WorkerGraph g;
  g.segments = PerSegment<WorkerSegment>(workers);
  PerSegment<double> sx(workers, 0.0), sy(workers, 0.0), sd(workers, 0.0);
  PerSegment<std::vector<uint8_t>> adjacent(workers, std::vector<uint8_t>(g.segments.size(), 0));
  for (auto& s : g.segments) s.coverage_distance = kInf;
  PerSegment<double> roomy_best(workers, kInf);
  const int w = grid.width(), h = grid.height();
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      const SegmentId k(labels[i]);
      if (!k.valid()) continue;
      WorkerSegment& s = g.segments[k];
      ++s.cells;
      sx[k] += c;
      sy[k] += r;
      if (coverage[i]) s.touches_coverage = true;
      if (std::isfinite(coverage_distance[i])) sd[k] += coverage_distance[i];
      if (coverage_distance[i] < s.coverage_distance) {
        s.coverage_distance = coverage_distance[i];
        if (roomy_best[k] == kInf) s.entry = Cell{r, c};
      }
      if (roomy && (*roomy)[i] && coverage_distance[i] < roomy_best[k]) {
        roomy_best[k] = coverage_distance[i];
        s.entry = Cell{r, c};
      }
      // Right and up neighbours suffice to see every shared border once.
      const SegmentId right(c + 1 < w ? labels[i + 1] : 0);
      const SegmentId up(r + 1 < h ? labels[i + static_cast<std::size_t>(w)] : 0);
      for (SegmentId m : {right, up})
        if (m.valid() && m != k) adjacent[k][m.index()] = adjacent[m][k.index()] = 1;
    }
  }
  PerSegment<double> best(workers, kInf), mx(workers), my(workers);
  for (SegmentId k : segment_ids(workers)) {
    WorkerSegment& s = g.segments[k];
    s.id = k;
    s.area = s.cells * grid.cell_area();
    mx[k] = s.cells ? sx[k] / s.cells : 0.0;
    my[k] = s.cells ? sy[k] / s.cells : 0.0;
    s.mean_coverage_distance = s.cells ? sd[k] / s.cells : 0.0;
    for (SegmentId m : segment_ids(workers))
      if (adjacent[k][m.index()]) s.neighbours.push_back(m);
  }
  // Centroid: the segment's own cell nearest to its centre of mass (the
  // centre of an L-shaped segment may lie outside it).
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const SegmentId k(labels.at(Cell{r, c}));
      if (!k.valid()) continue;
      const double d = (c - mx[k]) * (c - mx[k]) + (r - my[k]) * (r - my[k]);
      if (d < best[k]) best[k] = d, g.segments[k].centroid = Cell{r, c};
    }
  for (auto& s : g.segments) s.centroid_m = grid.cell_center(s.centroid);
  return g;
}

}  // namespace plan
}  // namespace gather
