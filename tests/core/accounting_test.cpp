// mission/accounting: the replay of every goal's history catches what
// breaks conservation or the order of its events.
#include <gtest/gtest.h>

#include <string>
#include <vector>

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

// A goal its worker's robot could not reach (agent runtime): pending ->
// unreachable is a final state of its own, counted apart from expiries.
GoalRecord unreachable_goal(int id, double at) {
  GoalRecord g;
  g.id = GoalId(id);
  g.requested_at = 0.0;
  g.deadline = 10.0;
  g.unreachable_at = at;
  g.state = mission::GoalState::kUnreachable;
  return g;
}

TEST(AccountingTest, APendingGoalGivenUpAsUnreachableIsCountedAsSuch) {
  GoalRecord delivered;
  delivered.id = GoalId(1);
  delivered.deadline = 10.0;
  delivered.measured_at = 2.0, delivered.delivered_at = 3.0;
  delivered.state = mission::GoalState::kDelivered;
  GoalRecord expired;
  expired.id = GoalId(2);
  expired.deadline = 10.0;
  expired.expired_at = 10.0;
  expired.state = mission::GoalState::kExpired;
  GoalRecord later = unreachable_goal(3, 14.0);  // of the second request, given up in it
  later.cycle = 1, later.requested_at = 10.0, later.deadline = 20.0;
  const std::vector<mission::CycleStats> cycles =
      mission::account({unreachable_goal(0, 4.0), delivered, expired, later}, 2, 10.0);
  ASSERT_EQ(cycles.size(), 2u);
  EXPECT_EQ(cycles[0].requested, 3);
  EXPECT_EQ(cycles[0].unreachable, 1);
  EXPECT_EQ(cycles[0].expired, 1);  // the unreachable goal is not an expiry
  EXPECT_EQ(cycles[0].delivered, 1);
  EXPECT_EQ(cycles[0].total_unreachable, 1);
  EXPECT_EQ(cycles[0].total_expired, 1);
  EXPECT_EQ(cycles[0].total_pending, 0);
  EXPECT_EQ(cycles[1].requested, 1);
  EXPECT_EQ(cycles[1].unreachable, 1);
  EXPECT_EQ(cycles[1].expired, 0);
  EXPECT_EQ(cycles[1].total_unreachable, 2);
  EXPECT_EQ(cycles[1].total_requested, 4);
}

TEST(AccountingTest, UnreachableOnlyFromPendingAndOnlyWithItsState) {
  EXPECT_NO_THROW(mission::account({unreachable_goal(0, 4.0)}, 1, 10.0));
  // A time without the state, or the state without a time: an internal error.
  GoalRecord no_state = unreachable_goal(0, 4.0);
  no_state.state = mission::GoalState::kExpired;
  EXPECT_THROW(mission::account({no_state}, 1, 10.0), RuntimeError);
  no_state.state = mission::GoalState::kPending;
  EXPECT_THROW(mission::account({no_state}, 1, 10.0), RuntimeError);
  try {
    mission::account({no_state}, 1, 10.0);
  } catch (const RuntimeError& e) {
    EXPECT_NE(std::string(e.what()).find("internal error"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("has an unreachable_at but is pending"), std::string::npos) << e.what();
  }
  GoalRecord no_time = unreachable_goal(0, -1.0);
  EXPECT_THROW(mission::account({no_time}, 1, 10.0), RuntimeError);
  // Measured first (carried), then given up: not from pending.
  GoalRecord measured = unreachable_goal(0, 4.0);
  measured.measured_at = 2.0;
  EXPECT_THROW(mission::account({measured}, 1, 10.0), RuntimeError);
  // Given up and expired: twice final.
  GoalRecord twice = unreachable_goal(0, 4.0);
  twice.expired_at = 10.0;
  EXPECT_THROW(mission::account({twice}, 1, 10.0), RuntimeError);
  // Given up before it was requested.
  GoalRecord early = unreachable_goal(0, 4.0);
  early.requested_at = 5.0;
  EXPECT_THROW(mission::account({early}, 1, 10.0), RuntimeError);
}

}  // namespace
}  // namespace gather
