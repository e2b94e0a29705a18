// mission/accounting: the replay of every goal's history catches what
// breaks conservation or the order of its events.
#include <gtest/gtest.h>

#include "gather_core/error.hpp"
#include "gather_core/mission/simulator.hpp"

namespace gather {
namespace {

using mission::GoalRecord;

TEST(AccountingTest, BrokenHistoriesAreCaught) {
  GoalRecord g;
  g.id = GoalId(0);  // goal 0 of the run
  g.deadline = 10.0;
  g.measured_at = 2.0;
  g.delivered_at = 1.0;  // before it was measured
  EXPECT_THROW(mission::account({g}, 1, 10.0), Error);
  g.delivered_at = 3.0;
  EXPECT_NO_THROW(mission::account({g}, 1, 10.0));
  g.delivered_at = -1.0;  // measured, never delivered: data dropped
  EXPECT_THROW(mission::account({g}, 1, 10.0), Error);
  GoalRecord e;
  e.id = GoalId(0);
  e.deadline = 10.0;
  e.expired_at = 10.0;
  EXPECT_NO_THROW(mission::account({e}, 1, 10.0));
  e.measured_at = 5.0;  // measured and expired
  EXPECT_THROW(mission::account({e}, 1, 10.0), Error);
}

}  // namespace
}  // namespace gather
