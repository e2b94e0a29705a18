// roles/custody: one copy per key, room for data and notices apart, resends
// only after their interval.
#include "gather_agent/roles/custody.hpp"

#include <gtest/gtest.h>

#include "corridor_team.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::measured;

TEST(Custody, KeepsOneCopyPerKeyRefusesWhenFullAndForgetsWhatIsAcked) {
  Custody c(2, 1);
  EXPECT_EQ(c.put(measured(5, 1, 1.0)), Custody::Put::kStored);
  EXPECT_EQ(c.put(measured(5, 1, 1.0)), Custody::Put::kDuplicate);
  EXPECT_EQ(c.put(measured(6, 1, 2.0)), Custody::Put::kStored);
  EXPECT_EQ(c.put(measured(7, 1, 3.0)), Custody::Put::kFull);  // data full; the sender keeps it
  DataItem n;
  n.key = 9, n.kind = ItemKind::kExpired;
  EXPECT_EQ(c.put(n), Custody::Put::kStored);  // notices have their own room
  EXPECT_EQ(c.data(), 2u);
  EXPECT_EQ(c.notices(), 1u);
  const int32_t keys[] = {5, 42};
  EXPECT_EQ(c.acked(keys, 2), 1u);
  EXPECT_FALSE(c.holds(5));
  EXPECT_TRUE(c.holds(6));
  EXPECT_EQ(c.put(measured(7, 1, 3.0)), Custody::Put::kStored);
}

TEST(Custody, SendsWhatIsDueAndResendsOnlyAfterTheInterval) {
  Custody c(8, 8);
  c.put(measured(1, 1, 0.0));
  c.put(measured(2, 1, 0.0));
  DataBatch b;
  EXPECT_EQ(c.due(10.0, 1.0, false, b), 2u);
  EXPECT_EQ(c.due(10.5, 1.0, false, b), 0u);  // sent 0.5 s ago, no ack yet: wait
  c.put(measured(3, 1, 0.0));
  EXPECT_EQ(c.due(10.6, 1.0, false, b), 1u);  // only the new one
  EXPECT_EQ(b.items[0].key, 3);
  EXPECT_EQ(c.due(11.0, 1.0, false, b), 2u);  // 1 and 2 again: the ack was lost
  EXPECT_EQ(c.due(11.1, 1.0, true, b), 3u);   // a new contact: everything
}
}  // namespace
}  // namespace agent
}  // namespace gather
