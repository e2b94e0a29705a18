// plan/worker_graph: segments, borders, centroids and coverage distances of a
// hand-made partition.
#include "gather_core/plan/worker_graph.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <vector>

#include "gather_core/error.hpp"
#include "predicate_grid.hpp"

namespace gather {
namespace plan {
namespace {

std::vector<SegmentId> ids(std::initializer_list<int> labels) {
  std::vector<SegmentId> out;
  for (int l : labels) out.push_back(SegmentId(l));
  return out;
}

// A 27 x 3 strip at 0.1 m/cell cut into three segments of 9 columns
// (1: columns 0-8, 2: 9-17, 3: 18-26); the OC's coverage is columns 0-4 and
// the distance to it grows by 0.1 m a column beyond.
struct Strip {
  OccupancyGrid grid = testing_support::predicate_grid(
      27, 3, [](int, int) { return true; }, 0.1);
  LabelImage labels = LabelImage(grid.frame(), 0);
  Mask coverage = Mask(grid.frame(), 0);
  Raster<double> to_coverage = Raster<double>(grid.frame(), 0.0);
  Strip() {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 27; ++c) {
        const std::size_t i = grid.index(Cell{r, c});
        labels[i] = 1 + c / 9;
        coverage[i] = c <= 4;
        to_coverage[i] = c <= 4 ? 0.0 : 0.1 * (c - 4);
      }
  }
};

TEST(WorkerGraphTest, SegmentsOfAStripByHand) {
  const Strip s;
  const WorkerGraph g = build_worker_graph(s.grid, s.labels, 3, s.coverage, s.to_coverage);
  ASSERT_EQ(g.segments.size(), 3u);
  EXPECT_EQ(g.segment(SegmentId(1)).neighbours, ids({2}));
  EXPECT_EQ(g.segment(SegmentId(2)).neighbours, ids({1, 3}));
  EXPECT_EQ(g.segment(SegmentId(3)).neighbours, ids({2}));
  for (int k = 1; k <= 3; ++k) {
    const WorkerSegment& seg = g.segment(SegmentId(k));
    EXPECT_EQ(seg.id, SegmentId(k));
    EXPECT_EQ(seg.cells, 27u);
    EXPECT_NEAR(seg.area, 0.27, 1e-12);
    EXPECT_EQ(seg.centroid.row, 1);
    EXPECT_EQ(seg.centroid.col, 9 * (k - 1) + 4);
    EXPECT_NEAR(seg.centroid_m.x, 0.1 * (9 * (k - 1) + 4) + 0.05, 1e-12);
    EXPECT_NEAR(seg.centroid_m.y, 0.15, 1e-12);
  }
  EXPECT_TRUE(g.segment(SegmentId(1)).touches_coverage);
  EXPECT_FALSE(g.segment(SegmentId(2)).touches_coverage);
  EXPECT_FALSE(g.segment(SegmentId(3)).touches_coverage);
  EXPECT_NEAR(g.segment(SegmentId(1)).coverage_distance, 0.0, 1e-12);
  EXPECT_NEAR(g.segment(SegmentId(2)).coverage_distance, 0.5, 1e-12);  // column 9
  EXPECT_NEAR(g.segment(SegmentId(3)).coverage_distance, 1.4, 1e-12);  // column 18
  // Mean over the columns: segment 1 (0 x 5 + 0.1..0.4) / 9, segment 2 at column 13.
  EXPECT_NEAR(g.segment(SegmentId(1)).mean_coverage_distance, 1.0 / 9.0, 1e-12);
  EXPECT_NEAR(g.segment(SegmentId(2)).mean_coverage_distance, 0.9, 1e-12);
  EXPECT_NEAR(g.segment(SegmentId(3)).mean_coverage_distance, 1.8, 1e-12);
  // The entry is the first cell (row-major) nearest the coverage.
  EXPECT_EQ(g.segment(SegmentId(2)).entry.row, 0);
  EXPECT_EQ(g.segment(SegmentId(2)).entry.col, 9);
}

TEST(WorkerGraphTest, TheEntryIsARoomyCellWhenTheSegmentHasOne) {
  const Strip s;
  Mask roomy(s.grid.frame(), 0);
  for (int c = 11; c < 27; ++c) roomy[s.grid.index(Cell{1, c})] = 1;  // the robot fits on row 1 from column 11
  const WorkerGraph g = build_worker_graph(s.grid, s.labels, 3, s.coverage, s.to_coverage, &roomy);
  EXPECT_EQ(g.segment(SegmentId(2)).entry.row, 1);
  EXPECT_EQ(g.segment(SegmentId(2)).entry.col, 11);
  EXPECT_NEAR(g.segment(SegmentId(2)).coverage_distance, 0.5, 1e-12);  // the distance is still the segment's own
  EXPECT_EQ(g.segment(SegmentId(1)).entry.col, 0);                     // no roomy cell: the nearest cell
}

TEST(WorkerGraphTest, TheCentroidOfAnLShapedSegmentIsOneOfItsCells) {
  // 10 x 10 grid: segment 1 is an L (column 0 and row 0), segment 2 the rest.
  const OccupancyGrid grid = testing_support::predicate_grid(10, 10, [](int, int) { return true; });
  LabelImage labels(grid.frame(), 2);
  for (int k = 0; k < 10; ++k) labels[grid.index(Cell{0, k})] = labels[grid.index(Cell{k, 0})] = 1;
  const Mask coverage(grid.frame(), 0);
  const Raster<double> far(grid.frame(), std::numeric_limits<double>::infinity());
  const WorkerGraph g = build_worker_graph(grid, labels, 2, coverage, far);
  const Cell c = g.segment(SegmentId(1)).centroid;
  EXPECT_EQ(labels[grid.index(c)], 1);  // the centre of mass (2.4, 2.4) is not in the L
  EXPECT_TRUE(c.row == 0 || c.col == 0);
  EXPECT_EQ(g.segment(SegmentId(1)).neighbours, ids({2}));
  EXPECT_EQ(g.segment(SegmentId(1)).coverage_distance, std::numeric_limits<double>::infinity());
  EXPECT_EQ(g.segment(SegmentId(1)).mean_coverage_distance, 0.0);  // unreached cells add nothing to the sum
}

TEST(WorkerGraphTest, RastersOffTheGridAreRefusedNamingWhich) {
  const OccupancyGrid grid = testing_support::predicate_grid(10, 10, [](int, int) { return true; });
  const LabelImage labels(grid.frame(), 1);
  const Mask coverage(grid.frame(), 0);
  const Raster<double> far(grid.frame(), 1.0);
  EXPECT_NO_THROW(build_worker_graph(grid, labels, 1, coverage, far));
  auto message = [&](const LabelImage& l, const Mask& c, const Raster<double>& d) -> std::string {
    try {
      build_worker_graph(grid, l, 1, c, d);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(message(LabelImage(GridFrame{9, 10}, 1), coverage, far),
            "worker graph: the label image is 9x10 cells holding 90 values, the grid 10x10");
  EXPECT_NE(message(labels, Mask(GridFrame{10, 11}), far).find("the coverage mask"), std::string::npos);
  EXPECT_NE(message(labels, coverage, Raster<double>()).find("the coverage distance"), std::string::npos);
}

}  // namespace
}  // namespace plan
}  // namespace gather
