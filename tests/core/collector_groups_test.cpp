// plan/collector_groups: which collector serves which segment, on hand-made
// worker graphs.
#include "gather_core/plan/collector_groups.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace gather {
namespace plan {
namespace {

WorkerSegment segment(int id, double x, double to_coverage, const std::vector<int>& neighbours) {
  WorkerSegment s;
  s.id = SegmentId(id);
  s.centroid_m = Point2{x, 0.0};
  s.coverage_distance = to_coverage;
  s.touches_coverage = to_coverage == 0.0;
  for (int m : neighbours) s.neighbours.push_back(SegmentId(m));
  return s;
}

// Two arms out of the OC's segment 1 (at x = 0): west 2 (x = -2), 3 (x = -5);
// east 4 (x = 2), 5 (x = 5).
WorkerGraph two_arms() {
  WorkerGraph g;
  g.segments =
      PerSegment<WorkerSegment>({segment(1, 0, 0.0, {2, 4}), segment(2, -2, 1.0, {1, 3}), segment(3, -5, 5.0, {2}),
                                 segment(4, 2, 1.5, {1, 5}), segment(5, 5, 6.0, {4})});
  return g;
}

// The collector of each segment as plain numbers (-1: the OC).
std::vector<int> groups(const WorkerGraph& graph, int collectors, const PerSegment<double>& work) {
  std::vector<int> out;
  for (CollectorId c : group_segments(graph, collectors, work)) out.push_back(c.value());
  return out;
}

TEST(CollectorGroupsTest, NoCollectorsSendsEverySegmentToTheOc) {
  EXPECT_EQ(groups(two_arms(), 0, PerSegment<double>(5, 1.0)), (std::vector<int>{-1, -1, -1, -1, -1}));
}

TEST(CollectorGroupsTest, OneCollectorPerArmAndTheOcKeepsWhatTouchesItsCoverage) {
  EXPECT_EQ(groups(two_arms(), 2, PerSegment<double>(5, 1.0)), (std::vector<int>{-1, 0, 0, 1, 1}));
}

TEST(CollectorGroupsTest, OneCollectorTakesBothArmsThroughTheOcArea) {
  // The east arm cannot be reached through segments from the west seed: it
  // joins the group of the nearest centroid.
  EXPECT_EQ(groups(two_arms(), 1, PerSegment<double>(5, 1.0)), (std::vector<int>{-1, 0, 0, 0, 0}));
}

TEST(CollectorGroupsTest, MoreCollectorsThanSegmentsToServe) {
  // Four segments to serve, eight collectors: one segment each, collectors 4-7 idle.
  const std::vector<int> g = groups(two_arms(), 8, PerSegment<double>(5, 1.0));
  EXPECT_EQ(g[0], -1);
  std::vector<int> served(g.begin() + 1, g.end());
  std::sort(served.begin(), served.end());
  EXPECT_EQ(served, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(g[1], 0) << "the first seed is the segment nearest the coverage";
}

TEST(CollectorGroupsTest, TheLeastLoadedGroupGrowsFirst) {
  // Segment 6 (far, x = 0 behind the OC) borders both seeds 2 and 4.
  WorkerGraph g;
  g.segments =
      PerSegment<WorkerSegment>({segment(1, 0, 0.0, {2, 4}), segment(2, -2, 1.0, {1, 6}), segment(3, -9, 9.0, {}),
                                 segment(4, 2, 1.5, {1, 6}), segment(5, 9, 9.0, {}), segment(6, 0, 8.0, {2, 4})});
  // Segments 3 and 5 border nothing: each joins the group of the nearest centroid.
  const std::vector<int> west_heavy = groups(g, 2, PerSegment<double>({1, 10, 1, 1, 1, 1}));
  EXPECT_EQ(west_heavy[5], 1) << "the east group (lighter) takes segment 6";
  const std::vector<int> east_heavy = groups(g, 2, PerSegment<double>({1, 1, 1, 10, 1, 1}));
  EXPECT_EQ(east_heavy[5], 0) << "the west group (lighter) takes segment 6";
  EXPECT_EQ(west_heavy[2], 0);
  EXPECT_EQ(west_heavy[4], 1);
}

}  // namespace
}  // namespace plan
}  // namespace gather
