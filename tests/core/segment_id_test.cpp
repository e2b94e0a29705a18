// segment_id: a segment's label and its place in a per-segment table.
#include "gather_core/segment_id.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <vector>

namespace gather {
namespace {

TEST(SegmentIdTest, TheLabelAndTheTableIndexDifferByOne) {
  const SegmentId s(3);
  EXPECT_EQ(s.label(), 3);
  EXPECT_EQ(s.index(), 2u);
  EXPECT_EQ(SegmentId::at_index(2), s);
  EXPECT_TRUE(s.valid());
  EXPECT_FALSE(SegmentId().valid());  // label 0: no segment
  EXPECT_TRUE(s.within(3));
  EXPECT_FALSE(s.within(2));
  EXPECT_FALSE(SegmentId(0).within(3));
  EXPECT_FALSE(SegmentId(-1).within(3));
  EXPECT_LT(SegmentId(2), s);
  std::ostringstream text;
  text << s;
  EXPECT_EQ(text.str(), "segment 3");
}

TEST(SegmentIdTest, APerSegmentTableIsIndexedByIds) {
  PerSegment<int> collector(3, -1);
  EXPECT_EQ(collector.count(), 3);
  collector[SegmentId(1)] = 0;
  collector[SegmentId(3)] = 2;
  EXPECT_EQ(collector.values(), (std::vector<int>{0, -1, 2}));
  const PerSegment<int> from_values(std::vector<int>{0, -1, 2});
  EXPECT_EQ(from_values, collector);
  EXPECT_EQ(from_values[SegmentId(3)], 2);
  EXPECT_TRUE(PerSegment<int>(-4).empty());
}

TEST(SegmentIdTest, SegmentIdsRunFromOneToN) {
  std::vector<int> labels;
  for (SegmentId s : segment_ids(4)) labels.push_back(s.label());
  EXPECT_EQ(labels, (std::vector<int>{1, 2, 3, 4}));
  int none = 0;
  for (SegmentId s : segment_ids(0)) none += s.label();
  EXPECT_EQ(none, 0);
}

}  // namespace
}  // namespace gather
