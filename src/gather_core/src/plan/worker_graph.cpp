#include "gather_core/plan/worker_graph.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gather {
namespace plan {

WorkerGraph build_worker_graph(const OccupancyGrid& grid, const LabelImage& labels, int workers, const Mask& coverage,
                               const Raster<double>& coverage_distance, const Mask* roomy) {
  WorkerGraph g;
  g.segments.resize(static_cast<std::size_t>(workers));
  std::vector<double> sx(g.segments.size(), 0.0), sy(g.segments.size(), 0.0), sd(g.segments.size(), 0.0);
  std::vector<std::vector<uint8_t>> adjacent(g.segments.size(), std::vector<uint8_t>(g.segments.size(), 0));
  for (auto& s : g.segments) s.coverage_distance = std::numeric_limits<double>::infinity();
  std::vector<double> roomy_best(g.segments.size(), std::numeric_limits<double>::infinity());
  const int w = grid.width(), h = grid.height();
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      const int k = labels[i];
      if (k <= 0) continue;
      WorkerSegment& s = g.segments[static_cast<std::size_t>(k - 1)];
      ++s.cells;
      sx[static_cast<std::size_t>(k - 1)] += c;
      sy[static_cast<std::size_t>(k - 1)] += r;
      if (coverage[i]) s.touches_coverage = true;
      if (std::isfinite(coverage_distance[i])) sd[static_cast<std::size_t>(k - 1)] += coverage_distance[i];
      if (coverage_distance[i] < s.coverage_distance) {
        s.coverage_distance = coverage_distance[i];
        if (roomy_best[static_cast<std::size_t>(k - 1)] == std::numeric_limits<double>::infinity())
          s.entry = Cell{r, c};
      }
      if (roomy && (*roomy)[i] && coverage_distance[i] < roomy_best[static_cast<std::size_t>(k - 1)]) {
        roomy_best[static_cast<std::size_t>(k - 1)] = coverage_distance[i];
        s.entry = Cell{r, c};
      }
      // Right and up neighbours suffice to see every shared border once.
      const int right = c + 1 < w ? labels[i + 1] : 0;
      const int up = r + 1 < h ? labels[i + static_cast<std::size_t>(w)] : 0;
      for (int m : {right, up})
        if (m > 0 && m != k)
          adjacent[static_cast<std::size_t>(k - 1)][static_cast<std::size_t>(m - 1)] =
              adjacent[static_cast<std::size_t>(m - 1)][static_cast<std::size_t>(k - 1)] = 1;
    }
  }
  std::vector<double> best(g.segments.size(), std::numeric_limits<double>::infinity());
  std::vector<double> mx(g.segments.size()), my(g.segments.size());
  for (std::size_t k = 0; k < g.segments.size(); ++k) {
    WorkerSegment& s = g.segments[k];
    s.id = static_cast<int>(k) + 1;
    s.area = s.cells * grid.cell_area();
    mx[k] = s.cells ? sx[k] / s.cells : 0.0;
    my[k] = s.cells ? sy[k] / s.cells : 0.0;
    s.mean_coverage_distance = s.cells ? sd[k] / s.cells : 0.0;
    for (std::size_t m = 0; m < g.segments.size(); ++m)
      if (adjacent[k][m]) s.neighbours.push_back(static_cast<int>(m) + 1);
  }
  // Centroid: the segment's own cell nearest to its centre of mass (the
  // centre of an L-shaped segment may lie outside it).
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const int k = labels[static_cast<std::size_t>(r) * w + c];
      if (k <= 0) continue;
      const std::size_t j = static_cast<std::size_t>(k - 1);
      const double d = (c - mx[j]) * (c - mx[j]) + (r - my[j]) * (r - my[j]);
      if (d < best[j]) best[j] = d, g.segments[j].centroid = Cell{r, c};
    }
  for (auto& s : g.segments) s.centroid_m = grid.cell_center(s.centroid);
  return g;
}

}  // namespace plan
}  // namespace gather
