// partition/rebalance: boundary cells move until the areas agree, and every
// segment stays connected.
#include "gather_core/partition/rebalance.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gather_core/partition/partition.hpp"
#include "label_checks.hpp"

namespace gather {
namespace partition {
namespace {

const int kCuts = PartitionParams{}.bap_cut_searches;

std::vector<int> areas(const LabelImage& labels, int workers) {
  std::vector<int> a(static_cast<std::size_t>(workers) + 1, 0);
  for (int32_t l : labels)
    if (l > 0) ++a[static_cast<std::size_t>(l)];
  return a;
}

// Every segment 1..workers is one 4-connected component.
bool connected(const LabelImage& labels, int workers) {
  for (int k = 1; k <= workers; ++k) {
    const auto first = std::find(labels.begin(), labels.end(), k);
    if (first == labels.end()) return false;
    const auto size = static_cast<std::size_t>(std::count(labels.begin(), labels.end(), k));
    if (testing_support::flood_size(labels, static_cast<std::size_t>(first - labels.begin())) != size) return false;
  }
  return true;
}

TEST(RebalanceTest, AStripOfTwoSegmentsEndsWithinTheTolerance) {
  // 40 x 4: segment 1 holds columns 0-29 (120 cells), segment 2 columns 30-39 (40).
  const int w = 40, h = 4;
  LabelImage labels(GridFrame{w, h});
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) labels.at(Cell{r, c}) = c < 30 ? 1 : 2;
  rebalance_areas(2, labels, 0.05, 20, kCuts);
  const std::vector<int> a = areas(labels, 2);
  EXPECT_NEAR(a[1], 80, 4);  // within 5% of the mean
  EXPECT_NEAR(a[2], 80, 4);
  EXPECT_EQ(a[1] + a[2], 160);
  EXPECT_TRUE(connected(labels, 2));
}

TEST(RebalanceTest, CellsOutsideEverySegmentStayOutAndTheResultIsDeterministic) {
  // 30 x 30 with a wall (label 0) down column 15 except a door at rows 14-15;
  // three uneven segments: 1 left of the wall, 2 and 3 split the right at row 5.
  const int w = 30, h = 30;
  LabelImage labels(GridFrame{w, h});
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      int32_t l = c < 15 ? 1 : (r < 5 ? 2 : 3);
      if (c == 15) l = (r == 14 || r == 15) ? 3 : 0;
      labels.at(Cell{r, c}) = l;
    }
  LabelImage again = labels;
  const LabelImage before = labels;
  rebalance_areas(3, labels, 0.05, 30, kCuts);
  rebalance_areas(3, again, 0.05, 30, kCuts);
  EXPECT_EQ(labels, again);
  for (std::size_t i = 0; i < labels.size(); ++i) EXPECT_EQ(labels[i] == 0, before[i] == 0) << "cell " << i;
  EXPECT_TRUE(connected(labels, 3));
  const std::vector<int> a = areas(labels, 3);
  const double mean = (a[1] + a[2] + a[3]) / 3.0;
  for (int k = 1; k <= 3; ++k) EXPECT_LE(std::abs(a[k] - mean), 0.05 * mean + 1) << "segment " << k;
  EXPECT_LT(areas(before, 3)[2], 0.5 * mean) << "the test starts unbalanced";
}

TEST(RebalanceTest, ZeroPassesChangeNothing) {
  LabelImage labels(GridFrame{4, 1}, {1, 1, 1, 2});
  rebalance_areas(2, labels, 0.0, 0, kCuts);
  EXPECT_EQ(labels.values(), (std::vector<int32_t>{1, 1, 1, 2}));
}

TEST(RebalanceTest, AFrontStuckAtACutMovesOnlyWhenCutsAreSearched) {
  // 25 x 2: segment 1 is row 0, one cell wide; segment 2 is the one cell
  // below column 4. The only cell of 1 next to 2 is a cut (taking it alone
  // would split 1), so the front is stuck there: searching it finds the
  // 4-cell pocket left of it, which moves with it, and the front goes on.
  const int w = 25, h = 2;
  LabelImage labels(GridFrame{w, h});
  for (int c = 0; c < w; ++c) labels.at(Cell{0, c}) = 1;
  labels.at(Cell{1, 4}) = 2;
  LabelImage unsearched = labels;
  rebalance_areas(2, labels, 0.05, 20, kCuts);
  rebalance_areas(2, unsearched, 0.05, 20, 0);
  EXPECT_EQ(areas(unsearched, 2)[2], 1) << "without cut searches nothing moves";
  EXPECT_NEAR(areas(labels, 2)[2], 13, 1);
  EXPECT_TRUE(connected(labels, 2));
  EXPECT_EQ(labels.at(Cell{0, 0}), 2) << "the pocket behind the cut went with it";
}

}  // namespace
}  // namespace partition
}  // namespace gather
